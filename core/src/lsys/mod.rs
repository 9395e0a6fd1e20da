//! L-systems as a plant modeller knows them (ABOP: Prusinkiewicz &
//! Lindenmayer, *The Algorithmic Beauty of Plants*, ch. 1–2): bracketed,
//! stochastic, parametric and context-sensitive, derived in bounded memory.
//!
//! - [`Grammar`] is parsed from a small text format (`docs/lsystems.md`)
//!   into fixed-capacity pools, without allocation; errors carry a line and
//!   a column.
//! - [`Streaming`] derives a context-free system depth first: its state is
//!   one frame per derivation step, so the derived string is never held
//!   (ABOP Fig. 1.25's shrub has 77 399 modules after 7 steps; streaming
//!   needs a few hundred bytes for it).
//! - [`Buffered`] derives any system, context-sensitive ones included, in
//!   two caller-provided module buffers (a double buffer), matching
//!   contexts through a third of links ([`Neighbours`]).
//! - Both do bounded work per call ([`VISITS_PER_CALL`]), answering
//!   [`Next::Pending`] where cuts or empty successors erase what they
//!   visit.
//! - Both key each stochastic choice by (derivation step, position of the
//!   module in the string it rewrites), so they agree module for module.
//! - [`LSystem`] is the simulation: it derives and feeds the modules to the
//!   3D [`crate::turtle`], which emits segments and polygons.
//!
//! ```
//! use morphogen::lsys::{Derivation, Grammar, Next, Streaming};
//! let mut g = Grammar::new();
//! g.parse("n = 2\naxiom: F\nF -> F[+F]F").unwrap();
//! let mut d = Streaming::new();
//! d.restart(&g, 2, 0).unwrap();
//! let mut text = heapless::String::<64>::new();
//! loop {
//!     match d.next_module(&g).unwrap() {
//!         Next::Module(m) => text.push(m.symbol as char).unwrap(),
//!         Next::Pending => {} // cuts or empty successors: ask again
//!         Next::End => break,
//!     }
//! }
//! assert_eq!(text, "F[+F]F[+F[+F]F]F[+F]F");
//! ```
//!
//! # Capacities
//!
//! What a maker sizes for the RAM of their part is in the types, as
//! heapless puts a `Vec`'s capacity in `Vec<T, N>`, with defaults that
//! `new()` gives:
//!
//! - [`Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>`](Grammar)
//!   (32, 256, 32, 1024, 64: about 3 KB): productions, successor modules
//!   over all productions and the axiom, context modules over all
//!   productions, bytes of expression code, distinct literals;
//!   `Grammar::<8, 64, 8, 256, 16>::empty()` holds under 1 KB.
//! - [`Streaming<STEPS>`](Streaming) (32): derivation steps, one frame and
//!   its counters (~44 bytes) each.
//! - [`LSystem<D, PRODUCTIONS, …, INTERPRETATION>`](LSystem) owns a
//!   derivation `D` and a grammar of those pools, and draws through at
//!   most `INTERPRETATION` (8) nested interpretation rules, a frame
//!   (24 bytes) each.
//! - [`Buffered<'b, DECOMPOSITION>`](Buffered) borrows its buffers, whose
//!   length is its capacity, and applies at most `DECOMPOSITION` (16)
//!   nested decomposition rules, a frame each.
//!
//! A grammar or derivation too big for them is a
//! [`ParseErrorKind::Capacity`] or [`LsysError::Capacity`] naming the type
//! and parameter (`Grammar<PRODUCTIONS>`, `Streaming<STEPS>`,
//! `LSystem<INTERPRETATION>`, `Buffered<DECOMPOSITION>`,
//! `BUFFER_MODULES`) with its value in that type. A grammar's `maximum
//! depth:` (1 to 255) is such a need: it is checked where the grammar meets
//! the type, when [`LSystem`] starts it or [`Buffered`] restarts on it.
//!
//! The `MAX_*` constants below stay constants: they are limits of the
//! grammar language, which every grammar file may rely on whatever type
//! parses it, not RAM a maker trades. [`MAX_PARAMS`] is the shape of
//! [`Module`], which the derivations, the turtle and the callers' module
//! buffers share; [`MAX_FORMALS`], [`MAX_NAME`], [`MAX_EXPR_STACK`] and
//! [`MAX_NESTING`] bound one production or expression (stack, not pools);
//! [`MAX_CONSTANTS`] is the parser's table, on the stack only while it
//! parses; [`MAX_BUFFERED_STEPS`] is the 8-bit step field of
//! [`stream_id`]; [`MAX_PLANT_MODULES`] bounds work, not memory.

mod context;
mod derive;
mod expr;
mod grammar;
pub mod module;
mod parse;
mod sim;

#[cfg(test)]
mod fuzz_tests;
#[cfg(test)]
mod tests;

pub use context::Neighbours;
pub use derive::{Buffered, Derivation, Next, Streaming, VISITS_PER_CALL, stream_id};
pub use grammar::{Grammar, Settings};
pub use module::{MAX_PARAMS, Module};
pub(crate) use sim::turtle_params;
pub use sim::{LSystem, MAX_PLANT_MODULES, MODULES_PER_STEP};

use crate::fx::Fx;
use crate::turtle::TurtleError;

/// Formal parameters of one production (contexts and predecessor).
pub const MAX_FORMALS: usize = 8;
/// Named constants and settings.
pub const MAX_CONSTANTS: usize = 32;
/// Characters of a constant's or formal parameter's name.
pub const MAX_NAME: usize = 16;
/// Evaluation stack of one expression.
pub const MAX_EXPR_STACK: usize = 16;
/// Nesting of parentheses and unary operators in one expression.
pub const MAX_NESTING: usize = 16;
/// Derivation steps `n` any grammar may ask for: the 8-bit step field of
/// [`stream_id`]. Beyond a [`Streaming`]'s `STEPS` (32 by default) only
/// [`Buffered`] derives it.
pub const MAX_BUFFERED_STEPS: usize = 255;

/// Where a grammar is wrong: 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParseError {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub column: u32,
    /// What is wrong.
    pub kind: ParseErrorKind,
}

/// What is wrong with a grammar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ParseErrorKind {
    /// Something else was expected here (the text says what).
    Expected(&'static str),
    /// A name that is neither a formal parameter nor a constant.
    UnknownName,
    /// A name defined twice (a constant, a setting or a formal parameter).
    DuplicateName,
    /// A second `axiom:` line.
    DuplicateAxiom,
    /// No `axiom:` line.
    MissingAxiom,
    /// No `n = …` line.
    MissingSteps,
    /// A number that does not fit I16F16 (±32768).
    NumberOutOfRange,
    /// A character outside printable ASCII.
    NotAscii,
    /// A setting with a value outside its range (the text says which).
    InvalidValue(&'static str),
    /// A `]` without its `[` in the same successor (a branch closes in
    /// the successor that opens it, ABOP Sec. 1.6).
    UnmatchedClose,
    /// A `[` that its successor does not close.
    UnclosedBranch,
    /// A capacity was exceeded: a pool of the grammar's type or a limit
    /// of the language.
    Capacity {
        /// The limit's name: the type and its parameter
        /// (`Grammar<PRODUCTIONS>`) or the constant (`MAX_NAME`).
        limit: &'static str,
        /// Its value (in the grammar's type, for a parameter).
        capacity: u32,
    },
    /// `~` not followed by the letter of a predefined surface
    /// ([`crate::turtle::SURFACES`]).
    UnknownSurface,
    /// A module symbol that ABOP or L-Py gives a meaning Morphogen does
    /// not implement: refused rather than silently drawn as nothing.
    UnsupportedSymbol {
        /// The symbol.
        symbol: u8,
    },
}

/// The names a grammar's `name = value` lines give a meaning
/// (`docs/lsystems.md`, *Settings*); any other name is a user constant.
pub const SETTINGS: [&str; 10] = [
    "n",
    "delta",
    "step",
    "width",
    "thin",
    "plants",
    "spacing",
    "animate",
    "tropism",
    "elasticity",
];

/// A `name = value` line of a grammar, as [`Grammar::parse_with`] reports
/// it: a setting or a user constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Definition<'t> {
    /// The name as written.
    pub name: &'t str,
    /// Its value.
    pub value: Fx,
    /// Whether any expression reads it (a setting acts by its name
    /// whether read or not).
    pub read: bool,
    /// The line of its name, from 1.
    pub line: u32,
    /// The column of its name, from 1.
    pub column: u32,
}

/// Module symbols that ABOP or L-Py give a meaning Morphogen does not
/// implement: a grammar using one is a located
/// [`ParseErrorKind::UnsupportedSymbol`] error. What each means there is
/// told where grammars come in (`scenario/src/unsupported.rs`), not in a
/// device's flash.
pub const UNSUPPORTED_SYMBOLS: [u8; 4] = *b"@?_;";

impl core::fmt::Display for ParseErrorKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ParseErrorKind::Expected(what) => write!(f, "expected {what}"),
            ParseErrorKind::UnknownName => {
                f.write_str("unknown name (not a formal parameter or a constant)")
            }
            ParseErrorKind::DuplicateName => f.write_str("name defined twice"),
            ParseErrorKind::DuplicateAxiom => f.write_str("a second `axiom:` line"),
            ParseErrorKind::MissingAxiom => f.write_str("no `axiom:` line"),
            ParseErrorKind::MissingSteps => f.write_str("no `n = <derivation steps>` line"),
            ParseErrorKind::NumberOutOfRange => {
                f.write_str("number out of range (fixed point, ±32768)")
            }
            ParseErrorKind::NotAscii => f.write_str("character outside printable ASCII"),
            ParseErrorKind::InvalidValue(what) => write!(f, "invalid value: {what}"),
            ParseErrorKind::UnmatchedClose => {
                f.write_str("`]` without its `[` (a branch closes in the successor that opens it)")
            }
            ParseErrorKind::UnclosedBranch => {
                f.write_str("`[` not closed in its successor (a branch closes where it opens)")
            }
            ParseErrorKind::Capacity { limit, capacity } => write!(
                f,
                "capacity {limit} = {capacity} exceeded (see core/src/lsys/mod.rs)"
            ),
            ParseErrorKind::UnknownSurface => f.write_str(
                "`~` must be followed by a predefined surface: `~L` (leaf) or `~P` (petal), optionally `(scale)`",
            ),
            ParseErrorKind::UnsupportedSymbol { symbol } => write!(
                f,
                "the symbol `{}` is not supported (ABOP or L-Py give it a meaning Morphogen does not implement)",
                char::from(*symbol)
            ),
        }
    }
}

impl core::fmt::Display for ParseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.kind)
    }
}

impl core::error::Error for ParseError {}

/// An error from parsing, deriving or drawing an L-system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum LsysError {
    /// The grammar text is malformed.
    Parse(ParseError),
    /// A derivation capacity was exceeded.
    Capacity {
        /// The limit's name: the type and its parameter
        /// (`Streaming<STEPS>`), `BUFFER_MODULES` (a [`Buffered`]'s buffers)
        /// or the constant (`MAX_PLANT_MODULES`).
        limit: &'static str,
        /// Its value.
        capacity: u32,
    },
    /// A context-sensitive grammar, or one with decomposition rules,
    /// cannot be derived by [`Streaming`]; use [`Buffered`].
    NeedsBuffer,
    /// The turtle failed.
    Turtle(TurtleError),
    /// A section the model using the grammar does not apply (named), e.g.
    /// `interpretation:` rules in a bone skeleton.
    Unsupported(&'static str),
}

impl core::fmt::Display for LsysError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LsysError::Parse(e) => write!(f, "grammar {e}"),
            LsysError::Capacity { limit, capacity } => {
                write!(f, "capacity {limit} = {capacity} exceeded")
            }
            LsysError::NeedsBuffer => f.write_str(
                "a context-sensitive grammar, or one with decomposition rules, needs buffered derivation",
            ),
            LsysError::Turtle(e) => write!(f, "turtle: {e}"),
            LsysError::Unsupported(what) => write!(f, "{what} are not supported here"),
        }
    }
}

impl core::error::Error for LsysError {}

impl From<ParseError> for LsysError {
    fn from(e: ParseError) -> LsysError {
        LsysError::Parse(e)
    }
}

impl From<TurtleError> for LsysError {
    fn from(e: TurtleError) -> LsysError {
        LsysError::Turtle(e)
    }
}
