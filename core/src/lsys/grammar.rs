//! A parsed grammar: the productions of bracketed, stochastic,
//! context-sensitive and parametric L-systems (ABOP, Secs. 1.6–1.10), the
//! axiom and the settings, in fixed-capacity pools (no allocation, no
//! borrowing of the text).

use heapless::Vec;

use crate::fx::Fx;

use super::expr;
use super::{MAX_FORMALS, MAX_PARAMS, Module};

/// The numbers a grammar sets with `name = value` lines (defaults in
/// brackets): `n` derivation steps (required), `delta` the turn angle in
/// degrees \[90\], `step` the length of a bare `F` \[1\], `width` the
/// initial segment width \[1\], `thin` the factor a bare `!` multiplies
/// the width by \[0.7\], `plants` how many plants to draw side by side,
/// each from its own seed `seed + i` \[1\], `spacing` the distance between
/// them along x \[0\], `animate` 1 to draw every derivation step as its own
/// frame (0 draws only step `n`) \[0\], `tropism = x, y, z` the tropism
/// vector T \[0, 0, 0\] and `elasticity` the susceptibility e to it \[0\]
/// (ABOP Sec. 2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Settings {
    /// Derivation steps.
    pub steps: u8,
    /// Turn angle δ in degrees.
    pub delta: Fx,
    /// Length of a bare `F`, `f`, `G`, `g`.
    pub step: Fx,
    /// Initial width.
    pub width: Fx,
    /// Factor applied by a bare `!`.
    pub thin: Fx,
    /// Plants drawn side by side.
    pub plants: u8,
    /// Distance between plants along x.
    pub spacing: Fx,
    /// Whether every derivation step is drawn as a frame.
    pub animate: bool,
    /// The tropism vector T (`tropism = x, y, z`, ABOP Sec. 2.2).
    pub tropism: [Fx; 3],
    /// The susceptibility e to tropism (`elasticity`; 0, the default,
    /// turns tropism off).
    pub elasticity: Fx,
}

impl Settings {
    /// The defaults (with `n = 0`).
    pub const DEFAULT: Settings = Settings {
        steps: 0,
        delta: Fx::from_int(90),
        step: Fx::ONE,
        width: Fx::ONE,
        thin: Fx::from_bits(45_875), // 0.7
        plants: 1,
        spacing: Fx::ZERO,
        animate: false,
        tropism: [Fx::ZERO; 3],
        elasticity: Fx::ZERO,
    };
}

/// A pattern in a context: a symbol and its number of formal parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Pattern {
    pub symbol: u8,
    pub arity: u8,
}

/// A successor module: its symbol and the code of its parameters (`arity`
/// expressions back to back from `code`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Template {
    pub symbol: u8,
    pub arity: u8,
    pub code: u16,
}

/// A `start..start + len` range in one of the pools.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Span {
    pub start: u16,
    pub len: u16,
}

impl Span {
    pub fn range(self) -> core::ops::Range<usize> {
        self.start as usize..self.start as usize + self.len as usize
    }
}

/// The section a rule belongs to (L-Py's `production:`,
/// `decomposition:` and `interpretation:`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Section {
    /// Rewrites each derivation step (the default section).
    #[default]
    Production,
    /// Applied to the whole string after each step, nested down to
    /// `maximum depth` (L-Py).
    Decomposition,
    /// Applied only to the modules the turtle draws, nested down to
    /// `maximum depth`; never fed back into the derivation (a homomorphism).
    Interpretation,
}

/// `lc < pred > rc : condition -> (weight) successor`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Production {
    pub section: Section,
    pub predecessor: Pattern,
    /// Into the context pool, left to right.
    pub left: Span,
    /// Into the context pool, left to right.
    pub right: Span,
    /// Start of the condition's code, if any.
    pub condition: Option<u16>,
    /// Start of the probability weight's code, if any.
    pub weight: Option<u16>,
    /// Into the successor pool.
    pub successor: Span,
}

/// A parsed L-system, its pools sized by its type (as heapless sizes a
/// `Vec<T, N>`): at most `PRODUCTIONS` productions (at most 255: a
/// production's index is a byte, 255 the axiom's), `SUCCESSORS` successor modules over all
/// productions and the axiom, `CONTEXTS` context modules (left and right)
/// over all productions, `CODE` bytes of compiled expression code and
/// `LITERALS` distinct numeric literals (at most 256: a literal's index is
/// a byte; `SUCCESSORS`, `CONTEXTS` and `CODE` below 65 536). A size
/// outside these is a build error. A grammar too big for its pools is a located
/// [`super::ParseErrorKind::Capacity`] naming the parameter
/// (`Grammar<PRODUCTIONS>`) and its value.
///
/// Memory: fixed by the type whatever the text (about 3 KB with the
/// defaults); [`Grammar::parse`] fills it in place, so a grammar can live
/// in a `static` and be re-parsed without a stack temporary.
///
/// ```
/// use morphogen::lsys::{Grammar, ParseErrorKind};
/// // The defaults: `Grammar::new()`.
/// let mut g = Grammar::new();
/// g.parse("n = 2\naxiom: F\nF -> F[+F]F").unwrap();
/// // Smaller pools for a small part: 4 productions, 16 successor modules.
/// let mut small = Grammar::<4, 16, 4, 64, 8>::empty();
/// small.parse("n = 2\naxiom: F\nF -> F[+F]F").unwrap();
/// let e = small.parse("n = 1\naxiom: F\nF -> FFFFFFFF[+FFFFFFFF]").unwrap_err();
/// assert_eq!(
///     e.kind,
///     ParseErrorKind::Capacity { limit: "SUCCESSORS", capacity: 16 }
/// );
/// ```
#[derive(Clone, Debug)]
pub struct Grammar<
    const PRODUCTIONS: usize = 32,
    const SUCCESSORS: usize = 256,
    const CONTEXTS: usize = 32,
    const CODE: usize = 1024,
    const LITERALS: usize = 64,
> {
    pub(crate) productions: Vec<Production, PRODUCTIONS>,
    pub(crate) contexts: Vec<Pattern, CONTEXTS>,
    pub(crate) templates: Vec<Template, SUCCESSORS>,
    pub(crate) code: Vec<u8, CODE>,
    pub(crate) literals: Vec<Fx, LITERALS>,
    pub(crate) axiom: Span,
    /// Symbols skipped when matching contexts, as a 128-bit set.
    pub(crate) ignored: [u32; 4],
    /// Symbols that some production's predecessor has, as a 128-bit set:
    /// a module whose symbol is not in it is copied without a choice.
    pub(crate) rewritten: [u32; 4],
    /// The same for decomposition rules.
    pub(crate) decomposed: [u32; 4],
    /// The same for interpretation rules.
    pub(crate) interpreted: [u32; 4],
    /// `maximum depth:` of the decomposition rules.
    pub(crate) decomposition_depth: u8,
    /// `maximum depth:` of the interpretation rules.
    pub(crate) interpretation_depth: u8,
    pub(crate) settings: Settings,
}

impl<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
> Default for Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>
{
    fn default() -> Self {
        Self::empty()
    }
}

impl Grammar {
    /// An empty grammar with the default pools (no productions, empty
    /// axiom, `n = 0`); [`Grammar::empty`] for other sizes.
    #[must_use]
    pub const fn new() -> Grammar {
        Grammar::empty()
    }
}

impl<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
> Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>
{
    /// An empty grammar (no productions, empty axiom, `n = 0`) with these
    /// pools, `const` for a `static`:
    /// `Grammar::<8, 64, 8, 256, 16>::empty()`.
    #[must_use]
    pub const fn empty() -> Self {
        // The pools fit the indices that address them: a build error for
        // a size that does not, never a run-time one.
        const {
            assert!(
                PRODUCTIONS <= AXIOM as usize
                    && SUCCESSORS <= u16::MAX as usize
                    && CONTEXTS <= u16::MAX as usize
                    && CODE <= u16::MAX as usize
                    && LITERALS <= u8::MAX as usize + 1,
                "a Grammar's pools: PRODUCTIONS <= 255, LITERALS <= 256, the others < 65536"
            )
        };
        Grammar {
            productions: Vec::new(),
            contexts: Vec::new(),
            templates: Vec::new(),
            code: Vec::new(),
            literals: Vec::new(),
            axiom: Span { start: 0, len: 0 },
            ignored: [0; 4],
            rewritten: [0; 4],
            decomposed: [0; 4],
            interpreted: [0; 4],
            decomposition_depth: 1,
            interpretation_depth: 1,
            settings: Settings::DEFAULT,
        }
    }

    /// An empty grammar whose bytes are all zero (settings too), so that a
    /// runner slot holding one is written in place by a memset; parse a
    /// grammar before using it.
    pub(crate) const fn zeroed() -> Self {
        let mut zeroed = Self::empty();
        zeroed.decomposition_depth = 0;
        zeroed.interpretation_depth = 0;
        zeroed.settings = Settings {
            steps: 0,
            delta: Fx::ZERO,
            step: Fx::ZERO,
            width: Fx::ZERO,
            thin: Fx::ZERO,
            plants: 0,
            spacing: Fx::ZERO,
            animate: false,
            tropism: [Fx::ZERO; 3],
            elasticity: Fx::ZERO,
        };
        zeroed
    }
    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Number of productions.
    #[must_use]
    pub fn production_count(&self) -> usize {
        self.productions.len()
    }

    /// Whether any production has a left or right context (then only
    /// [`super::Buffered`] can derive it).
    #[must_use]
    pub fn is_context_sensitive(&self) -> bool {
        self.productions
            .iter()
            .any(|p| p.left.len > 0 || p.right.len > 0)
    }

    /// Whether any production has a probability weight: only then does a
    /// derivation depend on its seed.
    #[must_use]
    pub fn is_stochastic(&self) -> bool {
        self.productions.iter().any(|p| p.weight.is_some())
    }

    /// Whether the grammar has decomposition rules (then only
    /// [`super::Buffered`] can derive it).
    #[must_use]
    pub fn has_decomposition(&self) -> bool {
        self.decomposed != [0; 4]
    }

    /// Whether the grammar has interpretation rules (`interpretation:`,
    /// applied only for drawing).
    #[must_use]
    pub fn has_interpretation(&self) -> bool {
        self.interpreted != [0; 4]
    }

    /// Whether only [`super::Buffered`] can derive the grammar: it is
    /// context-sensitive, has decomposition rules, or asks for more steps
    /// than a default [`super::Streaming`] derives (32).
    #[must_use]
    pub fn needs_buffer(&self) -> bool {
        self.is_context_sensitive()
            || self.has_decomposition()
            || self.settings.steps as usize > <super::Streaming>::STEPS
    }

    /// Whether some rule of `section` may apply to `symbol`.
    #[inline]
    pub(crate) fn has_rule_for(&self, section: Section, symbol: u8) -> bool {
        let set = match section {
            Section::Production => &self.rewritten,
            Section::Decomposition => &self.decomposed,
            Section::Interpretation => &self.interpreted,
        };
        match set.get(symbol as usize / 32) {
            Some(word) => word & (1 << (symbol % 32)) != 0,
            None => true,
        }
    }

    /// Whether a successor or the axiom has a `%` (a cut, ABOP p. 28).
    #[must_use]
    pub fn has_cut(&self) -> bool {
        self.templates.iter().any(|t| t.symbol == b'%')
    }

    /// Whether `symbol` is in the `ignore:` set.
    #[must_use]
    pub fn is_ignored(&self, symbol: u8) -> bool {
        let word = self.ignored.get(symbol as usize / 32).copied().unwrap_or(0);
        symbol < 128 && word & (1 << (symbol % 32)) != 0
    }

    pub(crate) fn ignore(&mut self, symbol: u8) {
        if let Some(word) = self.ignored.get_mut(symbol as usize / 32) {
            *word |= 1 << (symbol % 32);
        }
    }

    /// Whether some production may rewrite `symbol` (always true past the
    /// 128-bit set, which a parsed grammar never reaches).
    #[must_use]
    #[inline]
    pub fn is_rewritten(&self, symbol: u8) -> bool {
        self.has_rule_for(Section::Production, symbol)
    }

    /// The number of modules in the axiom.
    #[must_use]
    pub fn axiom_len(&self) -> usize {
        self.axiom.len as usize
    }

    /// Evaluates the expression starting at `start`; returns the value and
    /// where the next expression starts.
    pub(crate) fn eval(&self, start: usize, formals: &[Fx]) -> (Fx, usize) {
        expr::eval(&self.code, &self.literals, start, formals)
    }

    /// Instantiates successor template `index` with `formals`.
    #[inline]
    pub(crate) fn instantiate(&self, index: usize, formals: &[Fx]) -> Module {
        let Some(t) = self.templates.get(index) else {
            return Module::default();
        };
        let mut m = Module::bare(t.symbol);
        m.arity = t.arity;
        let mut pc = t.code as usize;
        for slot in m.params.iter_mut().take(t.arity as usize) {
            let (v, next) = self.eval(pc, formals);
            *slot = v;
            pc = next;
        }
        m
    }

    /// The successor span of production `index`, or the axiom for
    /// `index == AXIOM`.
    pub(crate) fn successor(&self, index: u8) -> Span {
        if index == AXIOM {
            return self.axiom;
        }
        self.productions
            .get(index as usize)
            .map_or(Span::default(), |p| p.successor)
    }
}

/// The pseudo-production index of the axiom.
pub(crate) const AXIOM: u8 = u8::MAX;

/// Copies a module's parameters into `formals` at `offset`; false when they
/// do not fit (cannot happen for a parsed grammar).
pub(crate) fn bind(formals: &mut [Fx; MAX_FORMALS], offset: usize, m: &Module) -> bool {
    match formals.get_mut(offset..offset + m.arity as usize) {
        Some(slots) => {
            slots.copy_from_slice(m.args());
            true
        }
        None => false,
    }
}

/// Whether module `m` matches pattern `p` (symbol and arity).
pub(crate) fn matches(p: &Pattern, m: &Module) -> bool {
    p.symbol == m.symbol && p.arity == m.arity
}

const _: () = assert!(MAX_PARAMS <= MAX_FORMALS);
