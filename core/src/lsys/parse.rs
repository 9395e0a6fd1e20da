//! The grammar text parser: ABOP's notation (Secs. 1.6–1.10) line by line,
//! alloc-free, every error located. The format is specified in
//! `docs/lsystems.md`.

use core::cell::Cell;

use heapless::Vec;

use crate::fx::Fx;

use super::expr::{self, FUNCTIONS};
use super::grammar::{Grammar, Pattern, Production, Section, Span, Template};
use super::{
    Definition, MAX_BUFFERED_STEPS, MAX_CONSTANTS, MAX_EXPR_STACK, MAX_FORMALS, MAX_NAME,
    MAX_NESTING, MAX_PARAMS, ParseError, ParseErrorKind, UNSUPPORTED_SYMBOLS,
};
use crate::turtle::SURFACES;

type Name = Vec<u8, MAX_NAME>;
type Constants = Vec<Constant, MAX_CONSTANTS>;

/// A `name = value` line: a setting or a user constant, where it is
/// defined and whether any expression read it.
struct Constant {
    name: Name,
    value: Fx,
    line: u32,
    column: u32,
    read: Cell<bool>,
}
type Formals = Vec<Name, MAX_FORMALS>;

const fn capacity(limit: &'static str, capacity: usize) -> ParseErrorKind {
    ParseErrorKind::Capacity {
        limit,
        capacity: capacity as u32,
    }
}

/// Whether `b` can be a module's symbol: printable ASCII other than the
/// format's punctuation `( ) , # < > :`.
#[must_use]
pub(crate) fn is_symbol(b: u8) -> bool {
    b.is_ascii_graphic() && !b"(),#<>:".contains(&b)
}

/// The located error for a symbol that ABOP or L-Py gives a meaning
/// Morphogen does not implement.
fn unsupported(c: &Cursor<'_>, at: usize, symbol: u8) -> Result<(), ParseError> {
    if UNSUPPORTED_SYMBOLS.contains(&symbol) {
        Err(c.err_at(at, ParseErrorKind::UnsupportedSymbol { symbol }))
    } else {
        Ok(())
    }
}

/// A position in one line, limited to `pos..end`.
#[derive(Clone, Copy)]
struct Cursor<'t> {
    text: &'t str,
    pos: usize,
    end: usize,
    line: u32,
}

impl<'t> Cursor<'t> {
    fn bytes(&self) -> &'t [u8] {
        self.text.as_bytes()
    }
    fn peek(&self) -> Option<u8> {
        if self.pos < self.end {
            self.bytes().get(self.pos).copied()
        } else {
            None
        }
    }
    fn peek_at(&self, k: usize) -> Option<u8> {
        if self.pos + k < self.end {
            self.bytes().get(self.pos + k).copied()
        } else {
            None
        }
    }
    fn bump(&mut self) {
        self.pos += 1;
    }
    fn skip_ws(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.bump();
        }
    }
    fn at_end(&mut self) -> bool {
        self.skip_ws();
        self.pos >= self.end
    }
    fn err_at(&self, pos: usize, kind: ParseErrorKind) -> ParseError {
        ParseError {
            line: self.line,
            column: (pos as u32).saturating_add(1),
            kind,
        }
    }
    fn err(&self, kind: ParseErrorKind) -> ParseError {
        self.err_at(self.pos, kind)
    }
    fn expect(&mut self, byte: u8, what: &'static str) -> Result<(), ParseError> {
        self.skip_ws();
        if self.peek() == Some(byte) {
            self.bump();
            Ok(())
        } else {
            Err(self.err(ParseErrorKind::Expected(what)))
        }
    }
    fn expect_end(&mut self) -> Result<(), ParseError> {
        if self.at_end() {
            Ok(())
        } else {
            Err(self.err(ParseErrorKind::Expected("the end of the line")))
        }
    }
    /// `[A-Za-z_][A-Za-z0-9_]*`, or `None` (position unchanged).
    fn ident(&mut self) -> Option<&'t str> {
        let start = self.pos;
        match self.peek() {
            Some(b) if b.is_ascii_alphabetic() || b == b'_' => self.bump(),
            _ => return None,
        }
        while matches!(self.peek(), Some(b) if b.is_ascii_alphanumeric() || b == b'_') {
            self.bump();
        }
        self.text.get(start..self.pos)
    }
    fn name(&self, start: usize, word: &str) -> Result<Name, ParseError> {
        Name::from_slice(word.as_bytes())
            .map_err(|()| self.err_at(start, capacity("MAX_NAME", MAX_NAME)))
    }
    fn symbol(&mut self) -> Result<u8, ParseError> {
        self.skip_ws();
        match self.peek() {
            Some(b) if is_symbol(b) => {
                self.bump();
                Ok(b)
            }
            _ => Err(self.err(ParseErrorKind::Expected("a module symbol"))),
        }
    }
}

/// Finds `needle` in `hay[from..to]`.
fn find(hay: &[u8], from: usize, to: usize, needle: &[u8]) -> Option<usize> {
    let window = hay.get(from..to)?;
    window
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + from)
}

/// Compiles one expression into the grammar's code pool.
struct Compiler<
    'g,
    'c,
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
> {
    grammar: &'g mut Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    formals: &'c [Name],
    constants: &'c [Constant],
    depth: usize,
    nesting: usize,
}

impl<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
> Compiler<'_, '_, PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>
{
    fn emit(&mut self, c: &Cursor<'_>, op: u8, operand: Option<u8>) -> Result<(), ParseError> {
        let (pops, pushes) = expr::arity(op);
        self.depth = self.depth.saturating_sub(pops) + pushes;
        if self.depth > MAX_EXPR_STACK {
            return Err(c.err(capacity("MAX_EXPR_STACK", MAX_EXPR_STACK)));
        }
        let full = || c.err(capacity("CODE", CODE));
        self.grammar.code.push(op).map_err(|_| full())?;
        if let Some(b) = operand {
            self.grammar.code.push(b).map_err(|_| full())?;
        }
        Ok(())
    }

    fn literal(&mut self, c: &Cursor<'_>, at: usize, v: Fx) -> Result<(), ParseError> {
        let index = match self.grammar.literals.iter().position(|&l| l == v) {
            Some(i) => i,
            None => {
                self.grammar
                    .literals
                    .push(v)
                    .map_err(|_| c.err_at(at, capacity("LITERALS", LITERALS)))?;
                self.grammar.literals.len() - 1
            }
        };
        self.emit(c, expr::LITERAL, Some(index as u8))
    }

    /// A whole expression followed by `END`; returns where its code starts.
    fn expression(&mut self, c: &mut Cursor<'_>) -> Result<u16, ParseError> {
        let start = self.grammar.code.len() as u16;
        self.depth = 0;
        self.or(c)?;
        self.emit(c, expr::END, None)?;
        Ok(start)
    }

    fn or(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.and(c)?;
        loop {
            c.skip_ws();
            if c.peek() == Some(b'|') && c.peek_at(1) == Some(b'|') {
                c.pos += 2;
                self.and(c)?;
                self.emit(c, expr::OR, None)?;
            } else {
                return Ok(());
            }
        }
    }

    fn and(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.comparison(c)?;
        loop {
            c.skip_ws();
            if c.peek() == Some(b'&') && c.peek_at(1) == Some(b'&') {
                c.pos += 2;
                self.comparison(c)?;
                self.emit(c, expr::AND, None)?;
            } else {
                return Ok(());
            }
        }
    }

    fn comparison(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.sum(c)?;
        c.skip_ws();
        let (op, len) = match (c.peek(), c.peek_at(1)) {
            (Some(b'<'), Some(b'=')) => (expr::LE, 2),
            (Some(b'>'), Some(b'=')) => (expr::GE, 2),
            (Some(b'='), Some(b'=')) => (expr::EQ, 2),
            (Some(b'!'), Some(b'=')) => (expr::NE, 2),
            (Some(b'<'), _) => (expr::LT, 1),
            (Some(b'>'), _) => (expr::GT, 1),
            _ => return Ok(()),
        };
        c.pos += len;
        self.sum(c)?;
        self.emit(c, op, None)
    }

    fn sum(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.product(c)?;
        loop {
            c.skip_ws();
            let op = match (c.peek(), c.peek_at(1)) {
                (Some(b'+'), _) => expr::ADD,
                (Some(b'-'), next) if next != Some(b'>') => expr::SUB,
                _ => return Ok(()),
            };
            c.bump();
            self.product(c)?;
            self.emit(c, op, None)?;
        }
    }

    fn product(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.unary(c)?;
        loop {
            c.skip_ws();
            let op = match c.peek() {
                Some(b'*') => expr::MUL,
                Some(b'/') => expr::DIV,
                _ => return Ok(()),
            };
            c.bump();
            self.unary(c)?;
            self.emit(c, op, None)?;
        }
    }

    fn unary(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            return Err(c.err(capacity("MAX_NESTING", MAX_NESTING)));
        }
        c.skip_ws();
        let result = match (c.peek(), c.peek_at(1)) {
            (Some(b'-'), _) => {
                c.bump();
                self.unary(c).and_then(|()| self.emit(c, expr::NEG, None))
            }
            (Some(b'!'), next) if next != Some(b'=') => {
                c.bump();
                self.unary(c).and_then(|()| self.emit(c, expr::NOT, None))
            }
            _ => self.power(c),
        };
        self.nesting -= 1;
        result
    }

    fn power(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        self.atom(c)?;
        c.skip_ws();
        if c.peek() == Some(b'^') {
            c.bump();
            self.unary(c)?;
            self.emit(c, expr::POW, None)?;
        }
        Ok(())
    }

    fn atom(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        c.skip_ws();
        let start = c.pos;
        match c.peek() {
            Some(b'(') => {
                c.bump();
                self.or(c)?;
                c.expect(b')', "`)`")
            }
            Some(b) if b.is_ascii_digit() || b == b'.' => {
                let v = number(c)?;
                self.literal(c, start, v)
            }
            Some(b) if b.is_ascii_alphabetic() || b == b'_' => {
                let word = c.ident().unwrap_or("");
                let save = *c;
                c.skip_ws();
                if c.peek() == Some(b'(')
                    && let Some(&(_, op)) = FUNCTIONS.iter().find(|(f, _)| *f == word)
                {
                    c.bump();
                    self.or(c)?;
                    c.expect(b')', "`)`")?;
                    return self.emit(c, op, None);
                }
                *c = save;
                if let Some(i) = self
                    .formals
                    .iter()
                    .position(|f| f.as_slice() == word.as_bytes())
                {
                    return self.emit(c, expr::FORMAL, Some(i as u8));
                }
                match self
                    .constants
                    .iter()
                    .find(|k| k.name.as_slice() == word.as_bytes())
                {
                    Some(k) => {
                        k.read.set(true);
                        self.literal(c, start, k.value)
                    }
                    None => Err(c.err_at(start, ParseErrorKind::UnknownName)),
                }
            }
            _ => Err(c.err(ParseErrorKind::Expected("an expression"))),
        }
    }
}

/// A decimal number `12`, `0.5`, `.5`, `3.`; an exponent (`1e-3`) is
/// refused where it starts, naming the form that is read.
fn number(c: &mut Cursor<'_>) -> Result<Fx, ParseError> {
    let start = c.pos;
    let mut digits = 0;
    let mut point = false;
    while let Some(b) = c.peek() {
        if b.is_ascii_digit() {
            digits += 1;
        } else if b == b'.' && !point {
            point = true;
        } else {
            break;
        }
        c.bump();
    }
    if digits == 0 {
        return Err(c.err_at(start, ParseErrorKind::Expected("a number")));
    }
    if matches!(c.peek(), Some(b'e' | b'E')) {
        return Err(c.err(ParseErrorKind::Expected(
            "a decimal without exponent (0.001, not 1e-3)",
        )));
    }
    let text = c.text.get(start..c.pos).unwrap_or("0");
    let (int, frac) = text.split_once('.').unwrap_or((text, ""));
    Fx::from_decimal(int.as_bytes(), frac.as_bytes())
        .ok_or_else(|| c.err_at(start, ParseErrorKind::NumberOutOfRange))
}

/// What `Grammar::parse` tracks across lines.
struct State {
    constants: Constants,
    axiom_seen: bool,
    steps_seen: bool,
    tropism_seen: bool,
    /// The section the next rules belong to.
    section: Section,
}

impl<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
> Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>
{
    /// Parses `text` into `self`, replacing what it held.
    ///
    /// # Errors
    /// The first problem, with its line and column; `self` then holds an
    /// unspecified (but safe to drop or re-parse) grammar.
    pub fn parse(&mut self, text: &str) -> Result<(), ParseError> {
        self.parse_with(text, |_| {})
    }

    /// [`Grammar::parse`], calling `constant` with each `name = value` the
    /// text defines (settings but `tropism` included), in the order
    /// written, once every line is read (before the axiom and `n` are
    /// found missing): what a caller needs to refuse a constant that does nothing
    /// (the scenario crate's did-you-mean for a misspelt setting).
    ///
    /// # Errors
    /// As [`Grammar::parse`]; `constant` is not called when a line is
    /// refused.
    pub fn parse_with(
        &mut self,
        text: &str,
        mut constant: impl FnMut(Definition<'_>),
    ) -> Result<(), ParseError> {
        *self = Self::empty();
        let mut state = State {
            constants: Vec::new(),
            axiom_seen: false,
            steps_seen: false,
            tropism_seen: false,
            section: Section::Production,
        };
        let mut lines = 0u32;
        for raw in text.split('\n') {
            lines = lines.saturating_add(1);
            let raw = raw.strip_suffix('\r').unwrap_or(raw);
            let content = match raw.find('#') {
                Some(k) => raw.get(..k).unwrap_or(""),
                None => raw,
            };
            let mut c = Cursor {
                text: content,
                pos: 0,
                end: content.len(),
                line: lines,
            };
            if let Some(bad) = content
                .bytes()
                .position(|b| !(b.is_ascii_graphic() || b == b' ' || b == b'\t'))
            {
                // The column counts characters; every byte before `bad` is
                // ASCII, one character each.
                return Err(c.err_at(bad, ParseErrorKind::NotAscii));
            }
            if c.at_end() {
                continue;
            }
            self.statement(&mut c, &mut state)?;
        }
        for k in &state.constants {
            constant(Definition {
                name: core::str::from_utf8(&k.name).unwrap_or(""),
                value: k.value,
                read: k.read.get(),
                line: k.line,
                column: k.column,
            });
        }
        let end = ParseError {
            line: lines,
            column: 1,
            kind: ParseErrorKind::MissingAxiom,
        };
        if !state.axiom_seen {
            return Err(end);
        }
        if !state.steps_seen {
            return Err(ParseError {
                kind: ParseErrorKind::MissingSteps,
                ..end
            });
        }
        Ok(())
    }

    fn statement(&mut self, c: &mut Cursor<'_>, state: &mut State) -> Result<(), ParseError> {
        let start = c.pos;
        let arrow = find(c.bytes(), c.pos, c.end, b"->");
        if let Some(word) = c.ident() {
            c.skip_ws();
            if (word == "axiom" || word == "ignore") && c.peek() == Some(b':') {
                c.bump();
                return if word == "axiom" {
                    if state.axiom_seen {
                        return Err(c.err_at(start, ParseErrorKind::DuplicateAxiom));
                    }
                    state.axiom_seen = true;
                    self.axiom = self.parse_successor(c, &[], &state.constants)?;
                    Ok(())
                } else {
                    self.ignore_line(c)
                };
            }
            let section = match word {
                "production" => Some(Section::Production),
                "decomposition" => Some(Section::Decomposition),
                "interpretation" | "homomorphism" => Some(Section::Interpretation),
                _ => None,
            };
            if let Some(section) = section
                && c.peek() == Some(b':')
                && arrow.is_none()
            {
                c.bump();
                c.expect_end()?;
                state.section = section;
                return Ok(());
            }
            if word == "maximum" && arrow.is_none() {
                return self.maximum_depth(c, start, state);
            }
            if c.peek() == Some(b'=') && c.peek_at(1) != Some(b'=') && arrow.is_none() {
                c.bump();
                return self.assignment(c, start, word, state);
            }
        }
        c.pos = start;
        match arrow {
            Some(at) => self.production(c, at, &state.constants, state.section),
            None => Err(c.err(ParseErrorKind::Expected(
                "a production `pred -> successor`, `axiom:`, `ignore:`, `name = value`, a section `production:`, `decomposition:`, `interpretation:` or `maximum depth: n`",
            ))),
        }
    }

    fn ignore_line(&mut self, c: &mut Cursor<'_>) -> Result<(), ParseError> {
        while !c.at_end() {
            let s = c.symbol()?;
            self.ignore(s);
        }
        Ok(())
    }

    fn assignment(
        &mut self,
        c: &mut Cursor<'_>,
        start: usize,
        word: &str,
        state: &mut State,
    ) -> Result<(), ParseError> {
        let name = c.name(start, word)?;
        if state.constants.iter().any(|k| k.name == name) {
            return Err(c.err_at(start, ParseErrorKind::DuplicateName));
        }
        if word == "tropism" {
            return self.tropism(c, start, state);
        }
        let value_at = {
            c.skip_ws();
            c.pos
        };
        let value = self.constant(c, state)?;
        c.expect_end()?;
        let invalid = |what| c.err_at(value_at, ParseErrorKind::InvalidValue(what));
        let integer = |lo: i32, hi: i32| {
            let i = value.floor_int();
            (value.to_bits() & 0xFFFF == 0 && (lo..=hi).contains(&i)).then_some(i)
        };
        let s = &mut self.settings;
        match word {
            "n" => {
                s.steps = integer(0, MAX_BUFFERED_STEPS as i32).ok_or(invalid(
                    "`n` must be a whole number from 0 to MAX_BUFFERED_STEPS = 255 (above Streaming<STEPS>, 32 by default, only buffered derivation derives it)",
                ))? as u8;
                state.steps_seen = true;
            }
            "delta" => s.delta = value,
            "step" => s.step = value,
            "width" => s.width = value,
            "thin" => s.thin = value,
            "elasticity" => s.elasticity = value,
            "spacing" => s.spacing = value,
            "plants" => {
                s.plants = integer(1, 16)
                    .ok_or(invalid("`plants` must be a whole number from 1 to 16"))?
                    as u8;
            }
            "animate" => {
                s.animate = integer(0, 1).ok_or(invalid("`animate` must be 0 or 1"))? == 1;
            }
            _ => {}
        }
        let column = c.err_at(start, ParseErrorKind::DuplicateName).column;
        state
            .constants
            .push(Constant {
                name,
                value,
                line: c.line,
                column,
                read: Cell::new(false),
            })
            .map_err(|_| c.err_at(start, capacity("MAX_CONSTANTS", MAX_CONSTANTS)))
    }

    /// `maximum depth: n` in a `decomposition:` or `interpretation:`
    /// section (L-Py): how deep its rules may nest.
    fn maximum_depth(
        &mut self,
        c: &mut Cursor<'_>,
        start: usize,
        state: &State,
    ) -> Result<(), ParseError> {
        c.skip_ws();
        if c.ident() != Some("depth") {
            return Err(c.err(ParseErrorKind::Expected("`depth` (maximum depth: n)")));
        }
        c.expect(b':', "`:` (maximum depth: n)")?;
        c.skip_ws();
        let value_at = c.pos;
        let (code_len, literal_len) = (self.code.len(), self.literals.len());
        let at = Compiler {
            grammar: self,
            formals: &[],
            constants: &state.constants,
            depth: 0,
            nesting: 0,
        }
        .expression(c)?;
        c.expect_end()?;
        let (value, _) = self.eval(at as usize, &[]);
        self.code.truncate(code_len);
        self.literals.truncate(literal_len);
        let whole = value.to_bits() & 0xFFFF == 0;
        let depth = value.floor_int();
        let slot = match state.section {
            Section::Production => {
                return Err(c.err_at(
                    start,
                    ParseErrorKind::InvalidValue(
                        "`maximum depth` belongs in a `decomposition:` or `interpretation:` section",
                    ),
                ));
            }
            Section::Decomposition => &mut self.decomposition_depth,
            Section::Interpretation => &mut self.interpretation_depth,
        };
        // The language's range, the field's; the capacity of the type
        // that derives or draws the grammar is checked where it meets it
        // (`Buffered<DECOMPOSITION>`, `LSystem<INTERPRETATION>`).
        if !whole || !(1..=u8::MAX as i32).contains(&depth) {
            return Err(c.err_at(
                value_at,
                ParseErrorKind::InvalidValue(
                    "`maximum depth` must be a whole number from 1 to 255",
                ),
            ));
        }
        *slot = depth as u8;
        Ok(())
    }

    /// `tropism = x, y, z` (ABOP Sec. 2.2): three constant expressions, the
    /// vector T. Not a constant itself (it is three numbers).
    fn tropism(
        &mut self,
        c: &mut Cursor<'_>,
        start: usize,
        state: &mut State,
    ) -> Result<(), ParseError> {
        if state.tropism_seen {
            return Err(c.err_at(start, ParseErrorKind::DuplicateName));
        }
        state.tropism_seen = true;
        let mut t = [Fx::ZERO; 3];
        for (i, slot) in t.iter_mut().enumerate() {
            if i > 0 {
                c.expect(b',', "`,` (tropism = x, y, z)")?;
            }
            *slot = self.constant(c, state)?;
        }
        c.expect_end()?;
        self.settings.tropism = t;
        Ok(())
    }

    /// A constant expression at `c` (names are constants), evaluated; the
    /// code compiled for it is dropped again.
    fn constant(&mut self, c: &mut Cursor<'_>, state: &State) -> Result<Fx, ParseError> {
        let (code_len, literal_len) = (self.code.len(), self.literals.len());
        let mut compiler = Compiler {
            grammar: self,
            formals: &[],
            constants: &state.constants,
            depth: 0,
            nesting: 0,
        };
        let at = compiler.expression(c)?;
        let (value, _) = self.eval(at as usize, &[]);
        self.code.truncate(code_len);
        self.literals.truncate(literal_len);
        Ok(value)
    }

    /// `pattern ('(' name (',' name)* ')')?`, appending formals.
    fn pattern(
        &mut self,
        c: &mut Cursor<'_>,
        formals: &mut Formals,
    ) -> Result<Pattern, ParseError> {
        c.skip_ws();
        let at = c.pos;
        let symbol = c.symbol()?;
        unsupported(c, at, symbol)?;
        if symbol == b'[' || symbol == b']' {
            return Err(c.err_at(
                at,
                ParseErrorKind::Expected(
                    "a module other than `[` or `]` (brackets are neither rewritten nor matched)",
                ),
            ));
        }
        if symbol == b'%' || symbol == b'~' {
            return Err(c.err_at(
                at,
                ParseErrorKind::Expected(
                    "a module other than `%` or `~` (a cut is removed after the step that makes it, a surface is only drawn)",
                ),
            ));
        }
        let mut arity = 0u8;
        if c.peek() == Some(b'(') {
            c.bump();
            loop {
                c.skip_ws();
                let name_at = c.pos;
                let Some(word) = c.ident() else {
                    return Err(c.err(ParseErrorKind::Expected("a formal parameter name")));
                };
                let name = c.name(name_at, word)?;
                if formals.contains(&name) {
                    return Err(c.err_at(name_at, ParseErrorKind::DuplicateName));
                }
                if arity as usize >= MAX_PARAMS {
                    return Err(c.err_at(name_at, capacity("MAX_PARAMS", MAX_PARAMS)));
                }
                formals
                    .push(name)
                    .map_err(|_| c.err_at(name_at, capacity("MAX_FORMALS", MAX_FORMALS)))?;
                arity += 1;
                c.skip_ws();
                match c.peek() {
                    Some(b',') => c.bump(),
                    Some(b')') => {
                        c.bump();
                        break;
                    }
                    _ => return Err(c.err(ParseErrorKind::Expected("`,` or `)`"))),
                }
            }
        }
        Ok(Pattern { symbol, arity })
    }

    /// Patterns until `<`, `>` or the end of the cursor.
    fn patterns(
        &mut self,
        c: &mut Cursor<'_>,
        formals: &mut Formals,
    ) -> Result<Vec<Pattern, CONTEXTS>, ParseError> {
        let mut list = Vec::new();
        while !c.at_end() && !matches!(c.peek(), Some(b'<' | b'>')) {
            let at = c.pos;
            let p = self.pattern(c, formals)?;
            list.push(p)
                .map_err(|_| c.err_at(at, capacity("CONTEXTS", CONTEXTS)))?;
        }
        Ok(list)
    }

    fn context(&mut self, c: &Cursor<'_>, at: usize, list: &[Pattern]) -> Result<Span, ParseError> {
        let start = self.contexts.len() as u16;
        for &p in list {
            self.contexts
                .push(p)
                .map_err(|_| c.err_at(at, capacity("CONTEXTS", CONTEXTS)))?;
        }
        Ok(Span {
            start,
            len: list.len() as u16,
        })
    }

    fn production(
        &mut self,
        c: &mut Cursor<'_>,
        arrow: usize,
        constants: &Constants,
        section: Section,
    ) -> Result<(), ParseError> {
        let line_end = c.end;
        // L-Py writes `-->`: the rule text ends before it.
        let rule_end = if arrow > c.pos && c.bytes().get(arrow - 1) == Some(&b'-') {
            arrow - 1
        } else {
            arrow
        };
        let colon = find(c.bytes(), c.pos, rule_end, b":");
        let mut formals = Formals::new();
        // Predecessor with contexts.
        c.end = colon.unwrap_or(rule_end);
        let first_at = {
            c.skip_ws();
            c.pos
        };
        let first = self.patterns(c, &mut formals)?;
        let (left, pred_list, pred_at) = if c.peek() == Some(b'<') {
            if first.is_empty() {
                return Err(c.err(ParseErrorKind::Expected("a left-context module before `<`")));
            }
            c.bump();
            c.skip_ws();
            let at = c.pos;
            (first, self.patterns(c, &mut formals)?, at)
        } else {
            (Vec::new(), first, first_at)
        };
        let [predecessor] = pred_list.as_slice() else {
            return Err(c.err_at(
                pred_at,
                ParseErrorKind::Expected("one predecessor module before `->`"),
            ));
        };
        let mut right = Vec::<Pattern, CONTEXTS>::new();
        if c.peek() == Some(b'>') {
            c.bump();
            right = self.patterns(c, &mut formals)?;
            if right.is_empty() || c.peek() == Some(b'<') || c.peek() == Some(b'>') {
                return Err(c.err(ParseErrorKind::Expected("right-context modules after `>`")));
            }
        }
        if c.peek() == Some(b'<') {
            return Err(c.err(ParseErrorKind::Expected("`>` or `->` (only one `<`)")));
        }
        c.expect_end()?;
        if section != Section::Production && !(left.is_empty() && right.is_empty()) {
            return Err(c.err_at(
                first_at,
                ParseErrorKind::Expected(
                    "a rule without context (decomposition and interpretation rules are context-free)",
                ),
            ));
        }
        let left = self.context(c, first_at, &left)?;
        let right = self.context(c, pred_at, &right)?;
        // Condition.
        let mut condition = None;
        if let Some(colon) = colon {
            c.pos = colon + 1;
            c.end = rule_end;
            c.skip_ws();
            if c.peek() == Some(b'*') {
                c.bump();
            } else {
                condition = Some(self.compile(c, &formals, constants)?);
            }
            c.expect_end()?;
        }
        // Weight and successor.
        c.pos = arrow + 2;
        c.end = line_end;
        c.skip_ws();
        let mut weight = None;
        if c.peek() == Some(b'(') {
            if section != Section::Production {
                return Err(c.err(ParseErrorKind::Expected(
                    "a successor without a probability (decomposition and interpretation rules are deterministic)",
                )));
            }
            c.bump();
            weight = Some(self.compile(c, &formals, constants)?);
            c.expect(b')', "`)` after the probability")?;
        }
        let successor_at = {
            c.skip_ws();
            c.pos
        };
        let successor = self.parse_successor(c, &formals, constants)?;
        let cuts = self
            .templates
            .get(successor.range())
            .is_some_and(|t| t.iter().any(|t| t.symbol == b'%'));
        if section == Section::Interpretation && cuts {
            return Err(c.err_at(
                successor_at,
                ParseErrorKind::Expected(
                    "an interpretation successor without `%` (a cut acts on the derivation, which interpretation rules never reach)",
                ),
            ));
        }
        let set = match section {
            Section::Production => &mut self.rewritten,
            Section::Decomposition => &mut self.decomposed,
            Section::Interpretation => &mut self.interpreted,
        };
        if let Some(word) = set.get_mut(predecessor.symbol as usize / 32) {
            *word |= 1 << (predecessor.symbol % 32);
        }
        self.productions
            .push(Production {
                section,
                predecessor: *predecessor,
                left,
                right,
                condition,
                weight,
                successor,
            })
            .map_err(|_| c.err_at(first_at, capacity("PRODUCTIONS", PRODUCTIONS)))
    }

    fn compile(
        &mut self,
        c: &mut Cursor<'_>,
        formals: &[Name],
        constants: &Constants,
    ) -> Result<u16, ParseError> {
        Compiler {
            grammar: self,
            formals,
            constants,
            depth: 0,
            nesting: 0,
        }
        .expression(c)
    }

    /// Modules with parameter expressions, to the end of the cursor.
    fn parse_successor(
        &mut self,
        c: &mut Cursor<'_>,
        formals: &[Name],
        constants: &Constants,
    ) -> Result<Span, ParseError> {
        let start = self.templates.len() as u16;
        // Open branches in this successor, and where the outermost one
        // still open began.
        let (mut depth, mut outermost) = (0u16, 0usize);
        while !c.at_end() {
            let at = c.pos;
            let symbol = c.symbol()?;
            unsupported(c, at, symbol)?;
            match symbol {
                b'[' => {
                    if depth == 0 {
                        outermost = at;
                    }
                    depth = depth.saturating_add(1);
                }
                b']' => {
                    depth = depth
                        .checked_sub(1)
                        .ok_or_else(|| c.err_at(at, ParseErrorKind::UnmatchedClose))?;
                }
                _ => {}
            }
            let mut t = Template {
                symbol,
                arity: 0,
                code: self.code.len() as u16,
            };
            if symbol == b'~' {
                // `~X`: the surface's index becomes the first parameter.
                let surface = c
                    .peek()
                    .and_then(|x| SURFACES.iter().position(|(letter, _, _)| *letter == x))
                    .ok_or_else(|| c.err(ParseErrorKind::UnknownSurface))?;
                let letter_at = c.pos;
                c.bump();
                let mut compiler = Compiler {
                    grammar: self,
                    formals,
                    constants,
                    depth: 0,
                    nesting: 0,
                };
                compiler.literal(c, letter_at, Fx::from_int(surface as i32))?;
                compiler.emit(c, expr::END, None)?;
                t.arity = 1;
            }
            if c.peek() == Some(b'(') {
                c.bump();
                loop {
                    if t.arity as usize >= MAX_PARAMS {
                        return Err(c.err(capacity("MAX_PARAMS", MAX_PARAMS)));
                    }
                    self.compile(c, formals, constants)?;
                    t.arity += 1;
                    c.skip_ws();
                    match c.peek() {
                        Some(b',') => c.bump(),
                        Some(b')') => {
                            c.bump();
                            break;
                        }
                        _ => return Err(c.err(ParseErrorKind::Expected("`,` or `)`"))),
                    }
                }
            }
            self.templates
                .push(t)
                .map_err(|_| c.err_at(at, capacity("SUCCESSORS", SUCCESSORS)))?;
        }
        if depth > 0 {
            return Err(c.err_at(outermost, ParseErrorKind::UnclosedBranch));
        }
        Ok(Span {
            start,
            len: self.templates.len() as u16 - start,
        })
    }
}
