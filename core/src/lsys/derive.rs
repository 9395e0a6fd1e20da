//! Derivation: choosing a production for each module (ABOP ch. 1.8–1.10)
//! and expanding the axiom `n` times, streaming ([`Streaming`]) or into a
//! double buffer ([`Buffered`]).
//!
//! Production choice, for a module `m` at position `p` of the string that
//! derivation step `k` rewrites:
//! 1. the candidates are the productions whose predecessor has `m`'s symbol
//!    and arity, whose contexts match (skipping ignored symbols and whole
//!    branches, ABOP p. 32) and whose condition is non-zero;
//! 2. none: `m` is copied unchanged;
//! 3. no candidate has a probability: the first one in the text wins;
//! 4. otherwise one is drawn with probability proportional to its weight
//!    (a missing weight counts 1, a negative one 0; all zero copies `m`),
//!    from one 32-bit draw of `KeyedRng::new(seed, stream_id(k, p))`.

use heapless::Vec;

use crate::fx::Fx;
use crate::rng::KeyedRng;

use super::context::{self, Context, Neighbours};
use super::grammar::{AXIOM, Grammar, Production, Section, Span, bind, matches};
use super::{LsysError, MAX_FORMALS, MAX_PARAMS, Module};

/// The RNG stream of the choice for the module at `position` of the string
/// rewritten by derivation step `step` (from 1): the step in the top 8 bits,
/// the position in the low 56.
#[must_use]
pub const fn stream_id(step: u8, position: u64) -> u64 {
    ((step as u64) << 56) | (position & ((1 << 56) - 1))
}

/// Modules a derivation visits in one [`Derivation::next_module`] call
/// before it gives up with [`Next::Pending`]: frames pushed and popped,
/// and modules that a cut removes or a production erases (ABOP p. 28;
/// `A -> ` with an empty successor). A descent through many levels takes
/// a few calls; a run of erased modules takes one per 8 of them, so a
/// simulation step (at most [`super::MODULES_PER_STEP`] calls) visits as
/// few modules as one that draws. Asked again, the derivation goes on
/// where it stopped.
pub const VISITS_PER_CALL: u32 = 8;

/// What a derivation gives when asked for its next module.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// The next module of the derived string.
    Module(Module),
    /// Not yet: [`VISITS_PER_CALL`] frames or modules were visited
    /// without reaching the next module; ask again.
    Pending,
    /// The derived string has ended.
    End,
}

/// A source of the derived string, module by module, from a grammar of
/// any pool sizes.
pub trait Derivation {
    /// Starts deriving `steps` steps of `grammar` with `seed`.
    ///
    /// # Errors
    /// A capacity, or [`LsysError::NeedsBuffer`] for a context-sensitive
    /// grammar given to [`Streaming`].
    fn restart<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
        steps: u8,
        seed: u64,
    ) -> Result<(), LsysError>;

    /// The next module of the derived string, after a bounded amount of
    /// work: [`Next::Pending`] when it is not reached yet.
    ///
    /// # Errors
    /// A capacity.
    fn next_module<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Result<Next, LsysError>;
}

/// Matches `p`'s contexts around `m` and binds every formal parameter
/// (left context, predecessor, right context, in text order).
fn bind_production<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
>(
    g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    p: &Production,
    m: &Module,
    context: Option<(Context<'_>, usize)>,
    formals: &mut [Fx; MAX_FORMALS],
) -> bool {
    let left = g.contexts.get(p.left.range()).unwrap_or(&[]);
    let right = g.contexts.get(p.right.range()).unwrap_or(&[]);
    let left_arity: usize = left.iter().map(|q| q.arity as usize).sum();
    if !bind(formals, left_arity, m) {
        return false;
    }
    if left.is_empty() && right.is_empty() {
        return true;
    }
    let Some((s, i)) = context else {
        return false;
    };
    let (mut j, mut offset) = (i, left_arity);
    for q in left.iter().rev() {
        let Some(k) = s.before(j) else {
            return false;
        };
        let Some(mk) = s.get(k) else { return false };
        offset -= q.arity as usize;
        if !matches(q, mk) || !bind(formals, offset, mk) {
            return false;
        }
        j = k;
    }
    let (mut j, mut offset) = (i + 1, left_arity + m.arity as usize);
    for q in right {
        let Some(k) = s.from(j) else {
            return false;
        };
        let Some(mk) = s.get(k) else { return false };
        if !matches(q, mk) || !bind(formals, offset, mk) {
            return false;
        }
        offset += q.arity as usize;
        j = k + 1;
    }
    true
}

/// The production applied to `m` (see the module docs) and its bound
/// formal parameters; `None` copies `m`.
fn choose<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
>(
    g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    m: &Module,
    context: Option<(Context<'_>, usize)>,
    step: u8,
    position: u64,
    seed: u64,
) -> Option<(u8, [Fx; MAX_FORMALS])> {
    choose_in(g, Section::Production, m, context, step, position, seed)
}

/// [`choose`] among the rules of `section`.
fn choose_in<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
>(
    g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    section: Section,
    m: &Module,
    context: Option<(Context<'_>, usize)>,
    step: u8,
    position: u64,
    seed: u64,
) -> Option<(u8, [Fx; MAX_FORMALS])> {
    if !g.has_rule_for(section, m.symbol) {
        return None;
    }
    let mut candidates = Vec::<(u8, Fx), PRODUCTIONS>::new();
    let mut weighted = false;
    for (k, p) in g.productions.iter().enumerate() {
        if p.section != section || !matches(&p.predecessor, m) {
            continue;
        }
        let mut formals = [Fx::ZERO; MAX_FORMALS];
        if !bind_production(g, p, m, context, &mut formals) {
            continue;
        }
        if let Some(c) = p.condition
            && g.eval(c as usize, &formals).0 == Fx::ZERO
        {
            continue;
        }
        let weight = match p.weight {
            Some(w) => {
                weighted = true;
                g.eval(w as usize, &formals).0.max(Fx::ZERO)
            }
            None => Fx::ONE,
        };
        if !weighted && p.weight.is_none() && candidates.is_empty() {
            // A deterministic first match wins unless a later candidate is
            // weighted; keep collecting only if another could apply.
            let more = g
                .productions
                .iter()
                .skip(k + 1)
                .any(|q| q.section == section && matches(&q.predecessor, m));
            if !more {
                return Some((k as u8, formals));
            }
        }
        // At most PRODUCTIONS candidates: the push cannot fail.
        let _ = candidates.push((k as u8, weight));
    }
    let &(first, _) = candidates.first()?;
    let chosen = if weighted {
        let total: i64 = candidates.iter().map(|c| c.1.to_bits() as i64).sum();
        if total == 0 {
            return None;
        }
        let draw = KeyedRng::new(seed, stream_id(step, position)).next_u32();
        // total < 2^36, so the product fits u128 and r < total.
        let r = ((draw as u128 * total as u128) >> 32) as i64;
        let mut acc = 0i64;
        let mut chosen = first;
        for &(k, w) in &candidates {
            acc += w.to_bits() as i64;
            if r < acc {
                chosen = k;
                break;
            }
        }
        chosen
    } else {
        first
    };
    let p = g.productions.get(chosen as usize)?;
    let mut formals = [Fx::ZERO; MAX_FORMALS];
    bind_production(g, p, m, context, &mut formals).then_some((chosen, formals))
}

/// One level of the depth-first expansion: which successor is being
/// expanded (the axiom's or a production's, looked up once when the frame
/// is pushed), how far, and the bound parameters of the module it
/// replaced: `F` of them, the predecessor's ([`MAX_PARAMS`]) or, for
/// [`Buffered`], its contexts' too ([`MAX_FORMALS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Frame<const F: usize = MAX_PARAMS> {
    successor: Span,
    next: u16,
    formals: [Fx; F],
}

impl<const F: usize> Frame<F> {
    /// No successor: all zero bytes.
    const IDLE: Self = Frame {
        successor: Span { start: 0, len: 0 },
        next: 0,
        formals: [Fx::ZERO; F],
    };
}

impl<const F: usize> Default for Frame<F> {
    fn default() -> Self {
        Frame::IDLE
    }
}

impl Frame {
    /// The frame expanding the first rule of `section` (a decomposition or
    /// interpretation rule: deterministic, context-free) that applies to
    /// `m`, if any.
    pub(crate) fn for_rule<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
        section: Section,
        m: &Module,
    ) -> Option<Frame> {
        let (rule, formals) = choose_in(g, section, m, None, 0, 0, 0)?;
        let mut f = [Fx::ZERO; MAX_PARAMS];
        f.copy_from_slice(formals.get(..MAX_PARAMS)?);
        Some(Frame {
            successor: g.successor(rule),
            next: 0,
            formals: f,
        })
    }
}

impl<const F: usize> Frame<F> {
    /// The next module of the successor, `None` at its end.
    pub(crate) fn next_module<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Option<Module> {
        if self.next >= self.successor.len {
            return None;
        }
        let m = g.instantiate(
            self.successor.start as usize + self.next as usize,
            &self.formals,
        );
        self.next += 1;
        Some(m)
    }
}

/// What [`Streaming`] reads and writes for each module of one level of
/// the derivation: the axiom's string is level 0, step `k`'s string
/// level `k`.
#[derive(Clone, Copy, Debug)]
struct Level {
    /// The successor being expanded into this level's string.
    frame: Frame,
    /// Modules of this level's string so far (its modules' positions).
    position: u64,
    /// Modules carried from this level to the last one at once.
    carried: u64,
}

impl Level {
    /// All zero bytes.
    const IDLE: Level = Level {
        frame: Frame::IDLE,
        position: 0,
        carried: 0,
    };
}

/// Levels 0 to `STEPS` (an array of `STEPS + 1` is not a stable type).
#[derive(Clone, Copy, Debug)]
struct Levels<T, const STEPS: usize> {
    axiom: T,
    steps: [T; STEPS],
}

impl<T: Copy, const STEPS: usize> Levels<T, STEPS> {
    /// Every level `value` (`const`).
    const fn filled(value: T) -> Self {
        Levels {
            axiom: value,
            steps: [value; STEPS],
        }
    }

    #[inline]
    fn get_mut(&mut self, level: usize) -> Option<&mut T> {
        match level.checked_sub(1) {
            None => Some(&mut self.axiom),
            Some(k) => self.steps.get_mut(k),
        }
    }

    /// Levels 0 to `STEPS`, in order.
    fn iter(&self) -> impl Iterator<Item = &T> {
        core::iter::once(&self.axiom).chain(&self.steps)
    }
}

/// Depth-first derivation of a context-free grammar: the string of step
/// `n` is produced module by module, holding one frame per step and one
/// position counter per step (for keying stochastic choices), never the
/// string. It derives up to `STEPS` steps (the default 32; fewer than 64)
/// in `STEPS + 1` levels of 44 bytes; more is the error `Capacity {
/// limit: "STEPS", capacity: STEPS }`.
///
/// Positions: the frames visit every level's string in order, so a running
/// counter per level gives each module its index in its level's string —
/// the same index [`Buffered`] sees. A module that no production rewrites
/// is carried to the last level at once: it is counted once in `carried`
/// at its level, and a module's index at level `k` is its level's counter
/// plus the modules carried from levels above `k`.
///
/// Cuts (`%`, ABOP p. 28): a `%` in level `k`'s string removes itself and
/// the rest of its branch from that string. Level `k`'s modules arrive in
/// string order (from its frame, or carried from a level above), so a
/// per-level state — cutting or not, and the bracket depth inside the cut
/// — removes them as they arrive; a removed module is neither counted nor
/// expanded. A module carried from level `j` and removed at level `k > j`
/// is counted at the levels `j + 1 .. k` it still reaches.
///
/// ```
/// use morphogen::lsys::{Derivation, Grammar, LsysError, Streaming};
/// let mut g = Grammar::new();
/// g.parse("n = 9\naxiom: F\nF -> F[+F]F").unwrap();
/// // Levels for 8 steps only: 9 is an error naming the capacity.
/// let mut d = Streaming::<8>::empty();
/// assert_eq!(
///     d.restart(&g, 8, 0),
///     Err(LsysError::Capacity {
///         limit: "STEPS",
///         capacity: 8
///     })
/// );
/// ```
#[derive(Clone, Debug)]
pub struct Streaming<const STEPS: usize = 32> {
    levels: Levels<Level, STEPS>,
    /// Per level: the bracket depth inside its cut, while it is cutting.
    cuts: Levels<u32, STEPS>,
    /// The levels whose frames are being expanded, `0..depth` (a stack).
    depth: usize,
    /// Bit `k` set while level `k` is cutting (the fast path needs none).
    /// Idle, both are zeros: the whole derivation is (a `Runner` writes an
    /// idle model with a memset, not from a template in flash).
    cutting: u64,
    steps: u8,
    seed: u64,
}

impl<const STEPS: usize> Default for Streaming<STEPS> {
    fn default() -> Self {
        Streaming::empty()
    }
}

impl Streaming {
    /// An idle derivation of up to 32 steps (`const`, for a `static`);
    /// [`Streaming::empty`] for other sizes.
    #[must_use]
    pub const fn new() -> Streaming {
        Streaming::empty()
    }
}

impl<const STEPS: usize> Streaming<STEPS> {
    /// The derivation steps it derives at most.
    pub const STEPS: usize = STEPS;

    /// An idle derivation of up to `STEPS` steps (`const`, for a
    /// `static`): `Streaming::<8>::empty()`.
    #[must_use]
    pub const fn empty() -> Self {
        // Level `STEPS` is a bit of the 64-bit `cutting` set: a build
        // error above, never a run-time one.
        const { assert!(STEPS < 64, "Streaming<STEPS>: STEPS < 64") };
        Streaming {
            levels: Levels::filled(Level::IDLE),
            cuts: Levels::filled(0),
            depth: 0,
            cutting: 0,
            steps: 0,
            seed: 0,
        }
    }

    fn capacity_error() -> LsysError {
        LsysError::Capacity {
            limit: "STEPS",
            capacity: STEPS as u32,
        }
    }

    /// Whether module `m` of level `level`'s string survives the cuts
    /// (updating that level's cut state): a `%` starts a cut and is
    /// removed; inside a cut every module is removed up to the `]` that
    /// closes the cut branch, which is kept.
    fn survives_cut(&mut self, level: usize, m: &Module) -> bool {
        let Some(depth) = self.cuts.get_mut(level) else {
            return true;
        };
        let bit = 1u64 << level; // level ≤ STEPS < 64
        if self.cutting & bit == 0 {
            if m.symbol == b'%' {
                *depth = 0;
                self.cutting |= bit;
                return false;
            }
            return true;
        }
        match m.symbol {
            b'[' => *depth = depth.saturating_add(1),
            b']' if *depth == 0 => {
                self.cutting &= !bit;
                return true;
            }
            b']' => *depth -= 1,
            _ => {}
        }
        false
    }

    /// Passes a module carried from `level` through the cuts of the levels
    /// below it; true if it reaches the last level. If a cut removes it at
    /// level `k`, it is counted at the levels `level + 1 .. k` it reached.
    fn carry_through_cuts(&mut self, level: usize, m: &Module) -> bool {
        for k in level + 1..=self.steps as usize {
            if !self.survives_cut(k, m) {
                for j in level + 1..k {
                    if let Some(reached) = self.levels.get_mut(j) {
                        reached.position += 1;
                    }
                }
                return false;
            }
        }
        true
    }

    /// After a complete derivation, the length of every intermediate
    /// string, from the axiom's to step `n`'s (before, each level's
    /// counter without the modules carried into it).
    pub fn positions(&self) -> impl Iterator<Item = u64> {
        self.levels
            .iter()
            .take(self.steps as usize + 1)
            .map(|l| l.position)
    }

    /// Adds to every level's counter the modules carried into it from the
    /// levels above, once the derivation is complete.
    fn settle_carried(&mut self) {
        // The axiom's level has none carried into it.
        let mut above = core::mem::take(&mut self.levels.axiom.carried);
        for l in &mut self.levels.steps {
            l.position = l.position.saturating_add(above);
            above = above.saturating_add(core::mem::take(&mut l.carried));
        }
    }

    /// [`Derivation::next_module`] past its fast path: pops finished
    /// frames, pushes a frame for each production chosen on the way down,
    /// and carries a module with no applicable production to the last
    /// level; pending after [`VISITS_PER_CALL`] of these.
    fn descend<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Result<Next, LsysError> {
        for _ in 0..VISITS_PER_CALL {
            let Some(level) = self.depth.checked_sub(1) else {
                self.settle_carried();
                return Ok(Next::End);
            };
            let Some(Level { frame, .. }) = self.levels.get_mut(level) else {
                return Ok(Next::End);
            };
            let span = frame.successor;
            if frame.next >= span.len {
                self.depth = level;
                continue;
            }
            let m = grammar.instantiate(span.start as usize + frame.next as usize, &frame.formals);
            frame.next += 1;
            if !self.survives_cut(level, &m) {
                continue;
            }
            let Some(Level { position, .. }) = self.levels.get_mut(level) else {
                return Ok(Next::End);
            };
            let own = *position;
            *position += 1;
            if level >= self.steps as usize {
                return Ok(Next::Module(m));
            }
            // Most modules have no production: skip the call to `choose`.
            let chosen = if grammar.is_rewritten(m.symbol) {
                let mut position = own;
                for j in 0..level {
                    if let Some(above) = self.levels.get_mut(j) {
                        position = position.saturating_add(above.carried);
                    }
                }
                choose(grammar, &m, None, level as u8 + 1, position, self.seed)
            } else {
                None
            };
            match chosen {
                Some((production, formals)) => {
                    let mut f = [Fx::ZERO; MAX_PARAMS];
                    f.copy_from_slice(&formals[..MAX_PARAMS]);
                    let next = self
                        .levels
                        .get_mut(self.depth)
                        .ok_or_else(Self::capacity_error)?;
                    next.frame = Frame {
                        successor: grammar.successor(production),
                        next: 0,
                        formals: f,
                    };
                    self.depth += 1;
                }
                None => {
                    if self.cutting >> (level + 1) != 0 && !self.carry_through_cuts(level, &m) {
                        continue;
                    }
                    if let Some(l) = self.levels.get_mut(level) {
                        l.carried += 1;
                    }
                    return Ok(Next::Module(m));
                }
            }
        }
        Ok(Next::Pending)
    }
}

impl<const STEPS: usize> Derivation for Streaming<STEPS> {
    fn restart<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
        steps: u8,
        seed: u64,
    ) -> Result<(), LsysError> {
        // The grammar's own `n` too, so that an animation fails at its
        // first frame rather than at step `STEPS + 1`.
        if steps.max(grammar.settings().steps) as usize > STEPS {
            return Err(Self::capacity_error());
        }
        if grammar.is_context_sensitive() || grammar.has_decomposition() {
            return Err(LsysError::NeedsBuffer);
        }
        // Level by level, not through `Levels::iter_mut`'s chain: the
        // smaller code in flash.
        (self.levels.axiom.position, self.levels.axiom.carried) = (0, 0);
        for l in &mut self.levels.steps {
            (l.position, l.carried) = (0, 0);
        }
        self.cuts = Levels::filled(0);
        self.cutting = 0;
        self.steps = steps;
        self.seed = seed;
        self.levels.axiom.frame = Frame {
            successor: grammar.successor(AXIOM),
            ..Frame::IDLE
        };
        self.depth = 1;
        Ok(())
    }

    #[inline]
    fn next_module<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Result<Next, LsysError> {
        // Fast path: the top frame's next module needs no choice (the
        // frame is at the last level, or no production rewrites the
        // module), so it is counted and returned as it is.
        let last = self.steps as usize;
        if self.cutting == 0
            && let Some(level) = self.depth.checked_sub(1)
            && let Some(l) = self.levels.get_mut(level)
        {
            let span = l.frame.successor;
            if l.frame.next < span.len {
                let m = grammar.instantiate(
                    span.start as usize + l.frame.next as usize,
                    &l.frame.formals,
                );
                let carried = level < last;
                if m.symbol != b'%' && (!carried || !grammar.is_rewritten(m.symbol)) {
                    l.frame.next += 1;
                    l.position += 1;
                    if carried {
                        l.carried += 1;
                    }
                    return Ok(Next::Module(m));
                }
            }
        }
        self.descend(grammar)
    }
}

/// Applies the cuts of ABOP p. 28 to a derived string in place: each `%`
/// is removed with the rest of its branch (up to, not including, the `]`
/// that closes it, or to the end of the string at the top level). Returns
/// the new length.
fn cut(s: &mut [Module], len: usize) -> usize {
    let mut out = 0usize;
    // Bracket depth inside the current cut, if any.
    let mut cutting: Option<u32> = None;
    for read in 0..len.min(s.len()) {
        let Some(&m) = s.get(read) else { break };
        let keep = match (cutting, m.symbol) {
            (None, b'%') => {
                cutting = Some(0);
                false
            }
            (None, _) => true,
            (Some(0), b']') => {
                cutting = None;
                true
            }
            (Some(d), b']') => {
                cutting = Some(d - 1);
                false
            }
            (Some(d), b'[') => {
                cutting = Some(d.saturating_add(1));
                false
            }
            (Some(_), _) => false,
        };
        if keep {
            if let Some(slot) = s.get_mut(out) {
                *slot = m;
            }
            out += 1;
        }
    }
    out
}

/// Derivation into two caller-provided module buffers (a fixed-capacity
/// double buffer): step `k` reads one and writes the other. Handles
/// context-sensitive grammars, whose contexts are matched through
/// [`Neighbours`] linked once a step (a third caller-provided buffer, one
/// per module); the capacity is the shortest buffer's length
/// (`BUFFER_MODULES` in errors). Decomposition rules (L-Py's
/// `decomposition:`) nest at most `DECOMPOSITION` deep: a grammar whose
/// `maximum depth:` is more is refused by [`Derivation::restart`].
///
/// [`Derivation::restart`] writes the axiom; the steps are derived by
/// [`Derivation::next_module`], [`VISITS_PER_CALL`] visits a call (a
/// module rewritten, a module or decomposition frame written, a step
/// closed), pending until the string is derived, then read module by
/// module.
///
/// ```
/// use morphogen::lsys::{Buffered, Derivation, Grammar, LsysError, Module, Neighbours};
/// let mut g = Grammar::new();
/// g.parse("n = 1\naxiom: A\nA -> X\ndecomposition:\nmaximum depth: 3\nX -> Y\nY -> Z\nZ -> W")
///     .unwrap();
/// let (mut a, mut b) = ([Module::default(); 8], [Module::default(); 8]);
/// let mut links = [Neighbours::default(); 8];
/// // The default nests 16 decomposition rules; this one 2.
/// let mut d = Buffered::<'_, 2>::over(&mut a, &mut b, &mut links);
/// assert_eq!(
///     d.restart(&g, 1, 0),
///     Err(LsysError::Capacity {
///         limit: "DECOMPOSITION",
///         capacity: 2
///     })
/// );
/// ```
#[derive(Debug)]
pub struct Buffered<'b, const DECOMPOSITION: usize = 16> {
    a: &'b mut [Module],
    b: &'b mut [Module],
    links: &'b mut [Neighbours],
    front_is_a: bool,
    /// Modules of the front string.
    len: usize,
    read: usize,
    peak: usize,
    /// Steps asked for, and the step under way (from 1 to `steps`).
    steps: u8,
    step: u8,
    /// Whether the last step is written (the string is read from then on).
    derived: bool,
    seed: u64,
    /// The front module rewritten next.
    position: usize,
    /// Modules the step under way has written to the back buffer.
    out: usize,
    /// The successor being written for the last module rewritten.
    expanding: Option<Frame<MAX_FORMALS>>,
    /// The decomposition rules being applied to a module written, depth
    /// first (L-Py's `Lsystem::__recursiveSteps`).
    decomposing: Vec<Frame, DECOMPOSITION>,
}

impl<'b> Buffered<'b> {
    /// A derivation over two module buffers and the context links of the
    /// string being rewritten (all three the same length: the shortest is
    /// the capacity), nesting up to 16 decomposition rules;
    /// [`Buffered::over`] for other depths.
    #[must_use]
    pub fn new(
        a: &'b mut [Module],
        b: &'b mut [Module],
        links: &'b mut [Neighbours],
    ) -> Buffered<'b> {
        Buffered::over(a, b, links)
    }
}

impl<'b, const DECOMPOSITION: usize> Buffered<'b, DECOMPOSITION> {
    /// A derivation over two module buffers and the context links of the
    /// string being rewritten, as [`Buffered::new`], nesting up to
    /// `DECOMPOSITION` decomposition rules:
    /// `Buffered::<'_, 4>::over(&mut a, &mut b, &mut links)`.
    #[must_use]
    pub fn over(a: &'b mut [Module], b: &'b mut [Module], links: &'b mut [Neighbours]) -> Self {
        Buffered {
            a,
            b,
            links,
            front_is_a: true,
            len: 0,
            read: 0,
            peak: 0,
            steps: 0,
            step: 1,
            derived: true,
            seed: 0,
            position: 0,
            out: 0,
            expanding: None,
            decomposing: Vec::new(),
        }
    }

    /// The front string: the axiom after [`Derivation::restart`], the
    /// string of the step under way, the derived string once
    /// [`Derivation::next_module`] has given a module or the end.
    #[must_use]
    pub fn string(&self) -> &[Module] {
        let front: &[Module] = if self.front_is_a { self.a } else { self.b };
        front.get(..self.len).unwrap_or(&[])
    }

    /// The largest number of modules held at once (both buffers) so far.
    #[must_use]
    pub fn peak_modules(&self) -> usize {
        self.peak
    }

    fn capacity(&self) -> usize {
        self.a.len().min(self.b.len()).min(self.links.len())
    }

    fn capacity_error(&self) -> LsysError {
        LsysError::Capacity {
            limit: "BUFFER_MODULES",
            capacity: self.capacity() as u32,
        }
    }

    /// A grammar nesting more decomposition rules than the type holds.
    const DEPTH_ERROR: LsysError = LsysError::Capacity {
        limit: "DECOMPOSITION",
        capacity: DECOMPOSITION as u32,
    };

    /// Links the front string for context matching, if the grammar has
    /// contexts.
    fn link<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) {
        if g.is_context_sensitive() {
            let front: &[Module] = if self.front_is_a { self.a } else { self.b };
            let front = front.get(..self.len).unwrap_or(&[]);
            context::link(g, front, self.links);
        }
    }

    /// Writes `m` at the end of the back string.
    fn put(&mut self, m: Module) -> Result<(), LsysError> {
        let error = self.capacity_error();
        if self.out >= self.capacity() {
            return Err(error);
        }
        let back: &mut [Module] = if self.front_is_a { self.b } else { self.a };
        *back.get_mut(self.out).ok_or(error)? = m;
        self.out += 1;
        Ok(())
    }

    /// Writes `m`, or starts decomposing it when a decomposition rule
    /// applies (L-Py decomposes the whole string after a step, copied
    /// modules too).
    fn write<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
        m: Module,
    ) -> Result<(), LsysError> {
        if !g.has_decomposition() {
            return self.put(m);
        }
        match Frame::for_rule(g, Section::Decomposition, &m) {
            // Pushed with the stack empty: it fits unless `DECOMPOSITION`
            // is 0, which `restart` refuses for a grammar that decomposes.
            Some(frame) => self.decomposing.push(frame).map_err(|_| Self::DEPTH_ERROR),
            None => self.put(m),
        }
    }

    /// One visit of the derivation under way (see the type's docs).
    fn visit<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Result<(), LsysError> {
        if let Some(top) = self.decomposing.last_mut() {
            let Some(x) = top.next_module(g) else {
                self.decomposing.pop();
                return Ok(());
            };
            // At most `maximum depth` (<= DECOMPOSITION, checked by
            // `restart`: a full stack is an error only for a grammar other
            // than the one restarted on) nested rules; the modules of the
            // deepest are kept as they are.
            return match Frame::for_rule(g, Section::Decomposition, &x) {
                Some(frame) if self.decomposing.len() < g.decomposition_depth as usize => {
                    self.decomposing.push(frame).map_err(|_| Self::DEPTH_ERROR)
                }
                _ => self.put(x),
            };
        }
        if let Some(expansion) = &mut self.expanding {
            return match expansion.next_module(g) {
                Some(m) => self.write(g, m),
                None => {
                    self.expanding = None;
                    Ok(())
                }
            };
        }
        let front: &[Module] = if self.front_is_a { self.a } else { self.b };
        let front = front.get(..self.len).unwrap_or(&[]);
        if let Some(&m) = front.get(self.position) {
            let chosen = choose(
                g,
                &m,
                Some((Context::new(front, self.links), self.position)),
                self.step,
                self.position as u64,
                self.seed,
            );
            self.position += 1;
            return match chosen {
                Some((production, formals)) => {
                    self.expanding = Some(Frame {
                        successor: g.successor(production),
                        next: 0,
                        formals,
                    });
                    Ok(())
                }
                None => self.write(g, m),
            };
        }
        // The step is written: the back string becomes the front.
        self.peak = self.peak.max(self.len + self.out);
        let back: &mut [Module] = if self.front_is_a { self.b } else { self.a };
        self.len = if g.has_cut() {
            cut(back, self.out)
        } else {
            self.out
        };
        self.front_is_a = !self.front_is_a;
        self.position = 0;
        self.out = 0;
        // A counter that saturated at `steps` = 255 would never end.
        if self.step >= self.steps {
            self.derived = true;
        } else {
            // step < steps ≤ u8::MAX: no overflow.
            self.step += 1;
            self.link(g);
        }
        Ok(())
    }
}

impl<const DECOMPOSITION: usize> Derivation for Buffered<'_, DECOMPOSITION> {
    fn restart<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
        steps: u8,
        seed: u64,
    ) -> Result<(), LsysError> {
        self.front_is_a = true;
        self.read = 0;
        self.len = 0;
        self.steps = steps;
        self.step = 1;
        self.derived = steps == 0;
        self.seed = seed;
        self.position = 0;
        self.out = 0;
        self.expanding = None;
        self.decomposing.clear();
        if grammar.has_decomposition() && grammar.decomposition_depth as usize > DECOMPOSITION {
            return Err(Self::DEPTH_ERROR);
        }
        let axiom = grammar.axiom.range();
        if axiom.len() > self.capacity() {
            return Err(self.capacity_error());
        }
        // As in L-Py, decomposition follows each step, not the axiom.
        self.len = axiom.len();
        for (slot, t) in self.a.iter_mut().zip(axiom) {
            *slot = grammar.instantiate(t, &[]);
        }
        self.peak = self.peak.max(self.len);
        if grammar.has_cut() {
            self.len = cut(self.a, self.len);
        }
        if steps > 0 {
            self.link(grammar);
        }
        Ok(())
    }

    fn next_module<
        const PRODUCTIONS: usize,
        const SUCCESSORS: usize,
        const CONTEXTS: usize,
        const CODE: usize,
        const LITERALS: usize,
    >(
        &mut self,
        grammar: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    ) -> Result<Next, LsysError> {
        for _ in 0..VISITS_PER_CALL {
            if self.derived {
                let m = self.string().get(self.read).copied();
                self.read += 1;
                return Ok(m.map_or(Next::End, Next::Module));
            }
            self.visit(grammar)?;
        }
        Ok(Next::Pending)
    }
}
