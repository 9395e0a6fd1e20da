//! Compiled arithmetic expressions of parametric L-systems (ABOP ch. 1.10):
//! a stack bytecode evaluated in [`Fx`] with the crate's saturating,
//! round-to-nearest operators.
//!
//! Semantics: `a / 0` saturates to ±32768 (`0 / 0 = 0`); comparisons and
//! logic give 1 or 0 and treat any non-zero value as true; `a ^ b` is exact
//! repeated multiplication for integer `|b| ≤ 32`, `exp(b·ln a)` for other
//! `b` and `a > 0`, and 0 otherwise; `sin`, `cos` take degrees.

use crate::fx::{Fx, Real};

use super::MAX_EXPR_STACK;

/// Ends an expression.
pub(crate) const END: u8 = 0;
/// Pushes literal `code[pc + 1]`.
pub(crate) const LITERAL: u8 = 1;
/// Pushes formal parameter `code[pc + 1]`.
pub(crate) const FORMAL: u8 = 2;
pub(crate) const ADD: u8 = 3;
pub(crate) const SUB: u8 = 4;
pub(crate) const MUL: u8 = 5;
pub(crate) const DIV: u8 = 6;
pub(crate) const POW: u8 = 7;
pub(crate) const LT: u8 = 8;
pub(crate) const GT: u8 = 9;
pub(crate) const LE: u8 = 10;
pub(crate) const GE: u8 = 11;
pub(crate) const EQ: u8 = 12;
pub(crate) const NE: u8 = 13;
pub(crate) const AND: u8 = 14;
pub(crate) const OR: u8 = 15;
pub(crate) const NEG: u8 = 16;
pub(crate) const NOT: u8 = 17;
pub(crate) const SQRT: u8 = 18;
pub(crate) const SIN: u8 = 19;
pub(crate) const COS: u8 = 20;
pub(crate) const ABS: u8 = 21;
pub(crate) const FLOOR: u8 = 22;
pub(crate) const EXP: u8 = 23;
pub(crate) const LN: u8 = 24;

/// The functions callable as `name(x)`, with their opcodes.
pub(crate) const FUNCTIONS: [(&str, u8); 7] = [
    ("sqrt", SQRT),
    ("sin", SIN),
    ("cos", COS),
    ("abs", ABS),
    ("floor", FLOOR),
    ("exp", EXP),
    ("ln", LN),
];

/// How an opcode changes the stack depth (pops, pushes), and its operand
/// bytes.
pub(crate) const fn arity(op: u8) -> (usize, usize) {
    match op {
        LITERAL | FORMAL => (0, 1),
        ADD..=OR => (2, 1),
        _ => (1, 1),
    }
}

fn truth(b: bool) -> Fx {
    if b { Fx::ONE } else { Fx::ZERO }
}

fn power(base: Fx, exponent: Fx) -> Fx {
    if exponent.to_bits() & 0xFFFF == 0 && exponent.abs() <= Fx::from_int(32) {
        let k = exponent.floor_int();
        let mut p = Fx::ONE;
        for _ in 0..k.unsigned_abs() {
            p = p.saturating_mul(base);
        }
        return if k < 0 { p.recip() } else { p };
    }
    if base > Fx::ZERO {
        <Fx as Real>::exp(exponent.saturating_mul(<Fx as Real>::ln(base)))
    } else {
        Fx::ZERO
    }
}

/// Evaluates the expression at `code[start..]` with formal parameters
/// `formals`; returns its value and the index after its `END`.
///
/// The parser guarantees well-formed code (stack depth, operand indices);
/// on anything else the result is 0 rather than a panic.
pub(crate) fn eval(code: &[u8], literals: &[Fx], start: usize, formals: &[Fx]) -> (Fx, usize) {
    let mut stack = [Fx::ZERO; MAX_EXPR_STACK];
    let mut sp = 0usize;
    let mut pc = start;
    loop {
        let Some(&op) = code.get(pc) else {
            return (Fx::ZERO, pc);
        };
        pc += 1;
        if op == END {
            let top = if sp > 0 { stack[sp - 1] } else { Fx::ZERO };
            return (top, pc);
        }
        let value = match op {
            LITERAL | FORMAL => {
                let index = code.get(pc).copied().unwrap_or(0) as usize;
                pc += 1;
                let pool = if op == LITERAL { literals } else { formals };
                pool.get(index).copied().unwrap_or(Fx::ZERO)
            }
            ADD..=OR => {
                if sp < 2 {
                    return (Fx::ZERO, pc);
                }
                sp -= 2;
                let (a, b) = (stack[sp], stack[sp + 1]);
                match op {
                    ADD => a + b,
                    SUB => a - b,
                    MUL => a.saturating_mul(b),
                    DIV => a.saturating_div(b),
                    POW => power(a, b),
                    LT => truth(a < b),
                    GT => truth(a > b),
                    LE => truth(a <= b),
                    GE => truth(a >= b),
                    EQ => truth(a == b),
                    NE => truth(a != b),
                    AND => truth(a != Fx::ZERO && b != Fx::ZERO),
                    _ => truth(a != Fx::ZERO || b != Fx::ZERO),
                }
            }
            _ => {
                if sp < 1 {
                    return (Fx::ZERO, pc);
                }
                sp -= 1;
                let a = stack[sp];
                match op {
                    NEG => -a,
                    NOT => truth(a == Fx::ZERO),
                    SQRT => <Fx as Real>::sqrt(a),
                    SIN => <Fx as Real>::sin(crate::fx::Angle::from_degrees_fx(a)),
                    COS => <Fx as Real>::cos(crate::fx::Angle::from_degrees_fx(a)),
                    ABS => a.abs(),
                    FLOOR => a.floor(),
                    EXP => <Fx as Real>::exp(a),
                    _ => <Fx as Real>::ln(a),
                }
            }
        };
        let Some(slot) = stack.get_mut(sp) else {
            return (Fx::ZERO, pc);
        };
        *slot = value;
        sp += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytecode_evaluates_with_saturation() {
        let lits = [Fx::from_int(3), Fx::ZERO];
        // (f0 + 3) * f1 ; f0 / 0
        let code = [
            FORMAL, 0, LITERAL, 0, ADD, FORMAL, 1, MUL, END, FORMAL, 0, LITERAL, 1, DIV, END,
        ];
        let f = [Fx::from_int(2), Fx::HALF];
        let (v, next) = eval(&code, &lits, 0, &f);
        assert_eq!(v, Fx::from_ratio(5, 2));
        assert_eq!(next, 9);
        assert_eq!(eval(&code, &lits, next, &f).0, Fx::MAX);
        assert_eq!(
            power(Fx::from_int(2), Fx::from_int(-2)),
            Fx::from_ratio(1, 4)
        );
        assert_eq!(power(Fx::from_int(-2), Fx::from_int(3)), Fx::from_int(-8));
        let root = power(Fx::from_int(4), Fx::HALF);
        assert!(
            (root.to_bits() - Fx::from_int(2).to_bits()).abs() < 64,
            "{root}"
        );
    }
}
