//! The bone skeleton (bones paper, Secs. 2–4 and 6): the elements an
//! L-system's turtle draws. `F` draws a segment element whose weight ρ is
//! the turtle's width; `O(ρ)` puts a point element at the turtle (`O`
//! alone: ρ = the width); `{ … }` is a convex polygon element of weight
//! ρ = the width at `}` (its vertices as the turtle records them: `{`,
//! every `.` and every `f`/`F` move inside); every other symbol means
//! what it means for plants (`docs/lsystems.md`).

use heapless::Vec;
use nalgebra::Vector3;

use crate::Error;
use crate::fx::Fx;
use crate::lsys::{
    Derivation, Grammar, LsysError, Next, Streaming, VISITS_PER_CALL, turtle_params,
};
use crate::shrinkwrap::{Element, polygon_edges};
use crate::turtle::{Drawn, Turtle};

/// Skeleton elements of one bone.
pub const MAX_ELEMENTS: usize = 64;
/// Every bone skeleton fits the shrinkwrap's prepared field.
const _: () = assert!(MAX_ELEMENTS <= crate::shrinkwrap::PREPARED_ELEMENTS);
/// Modules of one derived skeleton string (so that a grammar that grows
/// without drawing still ends).
pub const MAX_SKELETON_MODULES: u32 = 8192;
/// Frames and modules visited deriving one skeleton string, counted
/// [`VISITS_PER_CALL`] for each [`Next::Pending`] answer: a grammar that
/// erases what it grows (a cut, an empty successor) ends too. Buffered
/// derivation of 255 steps of strings twice [`MAX_SKELETON_MODULES`]
/// long needs a quarter of it.
pub const MAX_SKELETON_VISITS: u32 = 1 << 24;

/// The elements of one bone.
pub type Skeleton = Vec<Element<Fx>, MAX_ELEMENTS>;

/// A bone grammar with the derivation and the turtle that draw it:
/// [`Streaming`] (context-free grammars, the MCU's), or on a host
/// [`crate::lsys::Buffered`] for the context-sensitive L-systems the
/// paper chose (Sec. 3).
#[derive(Debug)]
pub struct Grower<D: Derivation = Streaming> {
    grammar: Grammar,
    derivation: D,
    turtle: Turtle<Fx>,
}

impl Grower<Streaming> {
    /// An empty grower (`const`, for a `static`; all zero bytes, so that
    /// it is written in place).
    #[must_use]
    pub const fn new() -> Grower<Streaming> {
        Grower::with_derivation(Streaming::new())
    }
}

impl<D: Derivation> Grower<D> {
    /// An empty grower over `derivation`.
    #[must_use]
    pub const fn with_derivation(derivation: D) -> Grower<D> {
        Grower {
            grammar: Grammar::zeroed(),
            derivation,
            turtle: Turtle::zeroed(),
        }
    }

    /// Parses `text` in place.
    ///
    /// # Errors
    /// The parse error; [`LsysError::Unsupported`] for interpretation
    /// rules (the skeleton is the derived string itself: none is silently
    /// ignored).
    pub fn load(&mut self, text: &str) -> Result<(), LsysError> {
        self.grammar.parse(text)?;
        if self.grammar.has_interpretation() {
            return Err(LsysError::Unsupported(
                "interpretation rules in a bone skeleton (it is the derived string itself)",
            ));
        }
        self.turtle = Turtle::new(turtle_params(&self.grammar));
        Ok(())
    }

    /// The parsed grammar.
    #[must_use]
    pub fn grammar(&self) -> &Grammar {
        &self.grammar
    }

    /// Derives `steps` steps with `seed` and draws the skeleton into `out`.
    ///
    /// # Errors
    /// A derivation or turtle error, a polygon that is not a convex
    /// polygon element ([`polygon_edges`]), or [`MAX_ELEMENTS`] (a
    /// polygon takes one per edge), [`MAX_SKELETON_MODULES`] or
    /// [`MAX_SKELETON_VISITS`] exceeded.
    pub fn grow(&mut self, steps: u8, seed: u64, out: &mut Skeleton) -> Result<(), Error> {
        out.clear();
        self.derivation.restart(&self.grammar, steps, seed)?;
        self.turtle.reset(Vector3::zeros());
        let full = || Error::Capacity {
            limit: "MAX_ELEMENTS",
            capacity: MAX_ELEMENTS as u32,
        };
        let (mut modules, mut visits) = (0u32, 0u32);
        loop {
            let m = match self.derivation.next_module(&self.grammar)? {
                Next::Module(m) => m,
                Next::Pending => {
                    visits += VISITS_PER_CALL;
                    if visits > MAX_SKELETON_VISITS {
                        return Err(Error::Capacity {
                            limit: "MAX_SKELETON_VISITS",
                            capacity: MAX_SKELETON_VISITS,
                        });
                    }
                    continue;
                }
                Next::End => break,
            };
            modules += 1;
            if modules > MAX_SKELETON_MODULES {
                return Err(Error::Capacity {
                    limit: "MAX_SKELETON_MODULES",
                    capacity: MAX_SKELETON_MODULES,
                });
            }
            if m.symbol == b'O' {
                let s = self.turtle.state();
                let weight = m.args().first().copied().unwrap_or(s.width);
                out.push(Element::point(s.position, weight))
                    .map_err(|_| full())?;
                continue;
            }
            match (m.symbol, self.turtle.apply(&m).map_err(LsysError::from)?) {
                (b'F', Drawn::Segment { a, b, width, .. }) => {
                    out.push(Element::segment(a, b, width))
                        .map_err(|_| full())?;
                }
                (_, Drawn::Polygon { .. }) => {
                    let width = self.turtle.state().width;
                    for edge in polygon_edges(self.turtle.polygon(), width)? {
                        out.push(edge).map_err(|_| full())?;
                    }
                }
                _ => {}
            }
        }
        self.turtle.finish().map_err(LsysError::from)?;
        Ok(())
    }
}

impl Default for Grower {
    fn default() -> Self {
        Grower::new()
    }
}
