//! The L-system simulation: derive (ABOP, Secs. 1.1–1.10), then draw with
//! the turtle (Secs. 1.3, 1.5), streaming segment by segment.
//!
//! Frames: by default one frame (index 0, time `n`) holding the plants of
//! derivation step `n`; with `animate = 1`, frame `k` (time `k`) holds step
//! `k` for `k = 0..=n`, so a display can show the plant growing. Inside a
//! frame plant `i` (of `plants`) is derived with seed `seed + i` and drawn
//! from `(i·spacing, 0, 0)`. Each [`Simulation::step`] interprets at most
//! [`MODULES_PER_STEP`] modules (a [`Next::Pending`] counts as one, so a
//! step's work is bounded even where cuts or empty successors erase
//! billions of modules); progress counts finished plants.

use nalgebra::Vector3;

use crate::Error;
use crate::fx::Fx;
use crate::sim::{Deferred, Progress, Simulation, Start};
use crate::stream::{Record, Sink};
use crate::turtle::{Drawn, Params, Turtle};

use heapless::Vec;

use super::derive::Frame;
use super::grammar::Section;
use super::{Derivation, Grammar, LsysError, Module, Next, Streaming, VISITS_PER_CALL};

/// Modules interpreted per [`Simulation::step`] at most.
pub const MODULES_PER_STEP: usize = 512;

/// Modules one plant's string may have (a [`Next::Pending`] counts as
/// one): far above any preset's (abop-shrub draws 14,000 segments), about
/// as many as the host's default stream cap takes drawn, and the bound on
/// a grammar that draws nothing while its string grows past billions of
/// modules.
pub const MAX_PLANT_MODULES: u32 = 1 << 22;

/// A grammar being derived and drawn: by `D` ([`Streaming`] or
/// [`super::Buffered`]), the grammar parsed into the pools of a
/// [`Grammar`] of the same sizes, its interpretation rules (L-Py's
/// homomorphism) nested at most `INTERPRETATION` deep.
///
/// ```
/// use morphogen::lsys::{LSystem, LsysError, Streaming};
/// use morphogen::sim::Start;
/// // The defaults: 32 steps streaming, the default grammar pools, 8
/// // nested interpretation rules.
/// static PLANT: LSystem = LSystem::new();
/// // A smaller one: 8 steps, 8 productions, 64 successor modules, 8
/// // context modules, 256 bytes of code, 16 literals, 2 nested rules.
/// let mut small: LSystem<Streaming<8>, 8, 64, 8, 256, 16, 2> =
///     LSystem::with_derivation(Streaming::empty());
/// assert!(core::mem::size_of_val(&small) < core::mem::size_of_val(&PLANT) / 2);
/// // A grammar nesting its rules deeper than that is refused.
/// let deep = "n = 0\naxiom: A\ninterpretation:\nmaximum depth: 3\nA -> F A";
/// assert_eq!(
///     small.start(deep, 0),
///     Err(morphogen::Error::Lsys(LsysError::Capacity {
///         limit: "INTERPRETATION",
///         capacity: 2
///     }))
/// );
/// ```
#[derive(Debug)]
pub struct LSystem<
    D: Derivation = Streaming,
    const PRODUCTIONS: usize = 32,
    const SUCCESSORS: usize = 256,
    const CONTEXTS: usize = 32,
    const CODE: usize = 1024,
    const LITERALS: usize = 64,
    const INTERPRETATION: usize = 8,
> {
    grammar: Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    derivation: D,
    /// Interpretation rules being expanded for the turtle (L-Py's
    /// `interpretation:`, a homomorphism): one frame per nested rule.
    interpreting: Vec<Frame, INTERPRETATION>,
    turtle: Turtle<Fx>,
    seed: u64,
    frame: u32,
    plant: u8,
    drawing: bool,
    /// Modules (and pending calls) of the plant being drawn.
    modules: u32,
    done: u32,
    failed: Deferred,
}

pub(crate) fn turtle_params<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
>(
    g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
) -> Params<Fx> {
    let s = g.settings();
    Params {
        step: s.step,
        delta: crate::fx::Angle::from_degrees_fx(s.delta),
        width: s.width,
        thin: s.thin,
        tropism: Vector3::new(s.tropism[0], s.tropism[1], s.tropism[2]),
        elasticity: s.elasticity,
    }
}

impl LSystem<Streaming> {
    /// An empty simulation with streaming derivation (`const`, for a
    /// `static`); [`Start::start`] it with a grammar before stepping it (until
    /// then it has no steps).
    #[must_use]
    pub const fn new() -> LSystem<Streaming> {
        LSystem::with_derivation(Streaming::new())
    }
}

impl Default for LSystem<Streaming> {
    fn default() -> Self {
        LSystem::new()
    }
}

impl<
    D: Derivation,
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
    const INTERPRETATION: usize,
> LSystem<D, PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS, INTERPRETATION>
{
    /// An empty simulation over `derivation` (e.g. [`super::Buffered`]),
    /// its grammar pools those of the type (`LSystem<Buffered>` for the
    /// defaults). Apart from `derivation` it is all zero bytes, so that a
    /// runner slot holding one is written in place by a memset.
    #[must_use]
    pub const fn with_derivation(derivation: D) -> Self {
        LSystem {
            grammar: Grammar::zeroed(),
            derivation,
            interpreting: Vec::new(),
            turtle: Turtle::zeroed(),
            seed: 0,
            frame: 0,
            plant: 0,
            drawing: false,
            modules: 0,
            done: 0,
            failed: Deferred::new(),
        }
    }

    /// The parsed grammar.
    #[must_use]
    pub fn grammar(&self) -> &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS> {
        &self.grammar
    }

    /// The derivation (e.g. to read [`super::Buffered::peak_modules`]).
    #[must_use]
    pub fn derivation(&self) -> &D {
        &self.derivation
    }

    fn frames(&self) -> u32 {
        let s = self.grammar.settings();
        if s.animate { s.steps as u32 + 1 } else { 1 }
    }

    fn total(&self) -> u32 {
        self.frames() * self.grammar.settings().plants as u32
    }

    fn depth(&self) -> u8 {
        let s = self.grammar.settings();
        if s.animate { self.frame as u8 } else { s.steps }
    }

    fn draw(&mut self, m: &Module, sink: &mut dyn Sink) -> Result<(), Error> {
        let bits = |v: Vector3<Fx>| [v.x, v.y, v.z];
        match self.turtle.apply(m).map_err(LsysError::from)? {
            Drawn::Nothing => {}
            Drawn::Segment {
                a,
                b,
                width,
                colour,
            } => sink.record(&Record::Segment {
                a: bits(a),
                b: bits(b),
                width,
                colour,
            })?,
            Drawn::Polygon { colour } => {
                let vertices = self.turtle.polygon();
                sink.record(&Record::Polygon {
                    vertices: vertices.len() as u16,
                    colour,
                })?;
                for &v in vertices {
                    sink.record(&Record::Point { p: bits(v) })?;
                }
            }
        }
        Ok(())
    }

    /// The next module for the turtle: the derived string with the
    /// interpretation rules applied (depth first, at most `maximum depth`
    /// nested, as L-Py's `Lsystem::__recursiveInterpretation`), so a
    /// homomorphism draws without changing what is derived. On computers
    /// a grammar without interpretation rules skips it, and it is kept out
    /// of line: inlined, it slows the per-module loop of every grammar (the
    /// shrub bench: 19.6 M instructions out of line, 21.2 M inlined).
    /// 32-bit targets always call it, inlined: one copy of the derivation's
    /// fast path in flash.
    /// Like the derivation, it is pending after [`VISITS_PER_CALL`]
    /// modules or frames (rules with empty successors erase modules).
    #[cfg_attr(target_pointer_width = "64", inline(never))]
    fn next_drawn(&mut self) -> Result<Next, LsysError> {
        for _ in 0..VISITS_PER_CALL {
            let m = match self.interpreting.last_mut() {
                Some(top) => match top.next_module(&self.grammar) {
                    Some(m) => m,
                    None => {
                        self.interpreting.pop();
                        continue;
                    }
                },
                None => match self.derivation.next_module(&self.grammar)? {
                    Next::Module(m) => m,
                    other => return Ok(other),
                },
            };
            if !self.grammar.has_rule_for(Section::Interpretation, m.symbol) {
                return Ok(Next::Module(m));
            }
            // At `maximum depth` (<= INTERPRETATION, checked by `start`,
            // so the push fits) the module is drawn as it is.
            if self.interpreting.len() >= self.grammar.interpretation_depth as usize {
                return Ok(Next::Module(m));
            }
            let Some(frame) = Frame::for_rule(&self.grammar, Section::Interpretation, &m) else {
                return Ok(Next::Module(m));
            };
            let _ = self.interpreting.push(frame);
        }
        Ok(Next::Pending)
    }

    fn advance(&mut self, sink: &mut dyn Sink) -> Result<(), Error> {
        if !self.drawing {
            let depth = self.depth();
            if self.plant == 0 {
                sink.record(&Record::FrameStart {
                    frame: self.frame,
                    time: Fx::from_int(depth as i32),
                })?;
            }
            let seed = self.seed.wrapping_add(self.plant as u64);
            self.derivation.restart(&self.grammar, depth, seed)?;
            let x = self
                .grammar
                .settings()
                .spacing
                .saturating_mul_int(self.plant as i32);
            self.turtle.reset(Vector3::new(x, Fx::ZERO, Fx::ZERO));
            self.interpreting.clear();
            self.drawing = true;
            self.modules = 0;
        }
        // Without interpretation rules the turtle draws the derived string
        // itself: no per-module rule lookup (see `next_drawn`).
        let direct = cfg!(target_pointer_width = "64") && !self.grammar.has_interpretation();
        for _ in 0..MODULES_PER_STEP {
            self.modules += 1;
            if self.modules > MAX_PLANT_MODULES {
                return Err(LsysError::Capacity {
                    limit: "MAX_PLANT_MODULES",
                    capacity: MAX_PLANT_MODULES,
                }
                .into());
            }
            let next = if direct {
                self.derivation.next_module(&self.grammar)?
            } else {
                self.next_drawn()?
            };
            let m = match next {
                Next::Module(m) => m,
                Next::Pending => continue,
                Next::End => {
                    self.turtle.finish().map_err(LsysError::from)?;
                    self.drawing = false;
                    self.done += 1;
                    self.plant += 1;
                    if self.plant >= self.grammar.settings().plants {
                        sink.record(&Record::FrameEnd { frame: self.frame })?;
                        self.plant = 0;
                        self.frame += 1;
                    }
                    break;
                }
            };
            self.draw(&m, sink)?;
        }
        Ok(())
    }
}

impl<
    D: Derivation,
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
    const INTERPRETATION: usize,
> Start<'_> for LSystem<D, PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS, INTERPRETATION>
{
    /// The grammar's text (docs/lsystems.md).
    type Params = str;

    /// Parses `grammar` in place and rewinds to its first frame; a parse
    /// error, or a `maximum depth:` of interpretation rules above
    /// `INTERPRETATION` ([`LsysError::Capacity`]), is also every step's
    /// ([`Error::Lsys`]).
    fn start(&mut self, grammar: &str, seed: u64) -> Result<(), Error> {
        self.seed = seed;
        self.frame = 0;
        self.plant = 0;
        self.drawing = false;
        self.done = 0;
        let parsed = match self.grammar.parse(grammar) {
            Ok(())
                if self.grammar.has_interpretation()
                    && self.grammar.interpretation_depth as usize > INTERPRETATION =>
            {
                Err(LsysError::Capacity {
                    limit: "INTERPRETATION",
                    capacity: INTERPRETATION as u32,
                })
            }
            parsed => parsed.map_err(LsysError::from),
        };
        if parsed.is_ok() {
            self.turtle = Turtle::new(turtle_params(&self.grammar));
        }
        self.failed.keep(parsed.map_err(Error::Lsys))
    }
}

impl<
    D: Derivation,
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
    const INTERPRETATION: usize,
> Simulation for LSystem<D, PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS, INTERPRETATION>
{
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.failed.check()?;
        let total = self.total();
        if self.done < total {
            let advanced = self.advance(sink);
            self.failed.keep(advanced)?;
        }
        Ok(Progress {
            done: self.done.min(total),
            total,
        })
    }
}
