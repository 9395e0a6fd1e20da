//! The elementary functions on [`Fx`] and [`Angle`], from the tables in
//! `tables.rs` with linear interpolation. Accuracy (asserted over dense
//! sweeps in `accuracy.rs`): sin/cos ≤ 2 LSB, sqrt ≤ 0.5 LSB (exactly
//! rounded), sigmoid ≤ 2 LSB, atan2 ≤ 2⁻¹⁸ turn, exp and ln within
//! 2⁻¹⁶ relative or 2 LSB.

use super::tables::{ATAN_Q32, EXP2_Q30, LOG2_Q31, SIGMOID_Q32, SIN_Q30};
use super::{Angle, Fx};

/// Interpolates `table` at `index + frac / 2^frac_bits`; `index + 1` must
/// be in the table whenever `frac > 0`.
fn lerp(table: &[u32], index: usize, frac: u64, frac_bits: u32) -> u64 {
    let a = table.get(index).copied().unwrap_or(0) as u64;
    if frac == 0 {
        return a;
    }
    let b = table.get(index + 1).copied().unwrap_or(0) as u64;
    // Tables are monotone increasing, so b ≥ a.
    a + (((b - a) * frac + (1 << (frac_bits - 1))) >> frac_bits)
}

/// Rounds a non-negative value with `shift` extra fractional bits.
const fn round_shift(v: u64, shift: u32) -> u64 {
    (v + (1 << (shift - 1))) >> shift
}

/// sin on the first quadrant: `x` in `[0, 2³⁰]` quarter-turn units, Q2.30 out.
fn quarter_sin_q30(x: u32) -> u64 {
    let index = (x >> 22) as usize;
    lerp(&SIN_Q30, index, (x & ((1 << 22) - 1)) as u64, 22)
}

/// The sine of a binary angle.
pub(super) fn sin(a: Angle) -> Fx {
    let quadrant = a.0 >> 30;
    let r = a.0 & ((1 << 30) - 1);
    let folded = if quadrant & 1 == 0 { r } else { (1 << 30) - r };
    let magnitude = round_shift(quarter_sin_q30(folded), 14) as i32; // ≤ 65536
    Fx::from_bits(if quadrant >= 2 { -magnitude } else { magnitude })
}

/// The cosine of a binary angle.
pub(super) fn cos(a: Angle) -> Fx {
    sin(a + Angle::QUARTER)
}

/// The angle of the vector `(x, y)`; `atan2(0, 0)` is zero.
pub(super) fn atan2(y: Fx, x: Fx) -> Angle {
    let (ax, ay) = (
        (x.to_bits() as i64).unsigned_abs(),
        (y.to_bits() as i64).unsigned_abs(),
    );
    if ax == 0 && ay == 0 {
        return Angle::ZERO;
    }
    // atan of the ratio of the smaller to the larger component, in [0, 1/8 turn].
    let (small, large) = if ay <= ax { (ay, ax) } else { (ax, ay) };
    let t = (small << 32) / large; // Q32 in [0, 2³²]
    let octant = lerp(&ATAN_Q32, (t >> 24) as usize, t & ((1 << 24) - 1), 24) as u32;
    let first = if ay <= ax { octant } else { (1 << 30) - octant };
    let half = if x.to_bits() < 0 {
        (1u32 << 31) - first
    } else {
        first
    };
    Angle(if y.to_bits() < 0 {
        half.wrapping_neg()
    } else {
        half
    })
}

/// The square root, exactly rounded; negative input gives zero.
pub(super) fn sqrt(x: Fx) -> Fx {
    if x.to_bits() <= 0 {
        return Fx::ZERO;
    }
    let n = (x.to_bits() as u64) << 16;
    let r = super::root::isqrt_u64(n);
    // Round to nearest: r + 1 when n − r² > r (i.e. n ≥ (r + ½)²).
    let rounded = if n - r * r > r { r + 1 } else { r };
    Fx::from_bits(rounded as i32)
}

/// log₂(e) in Q2.30.
const LOG2_E_Q30: i64 = 1_549_082_005;
/// ln(2) in Q0.32.
const LN2_Q32: i128 = 2_977_044_472;

/// e^x, saturating at [`Fx::MAX`]; below about −11.1 the result is zero.
pub(super) fn exp(x: Fx) -> Fx {
    // y = x·log₂e in Q46; e^x = 2^k · 2^f with k = ⌊y⌋, f ∈ [0, 1).
    let y = x.to_bits() as i64 * LOG2_E_Q30;
    let k = y >> 46;
    if k >= 15 {
        return Fx::MAX;
    }
    if k < -18 {
        return Fx::ZERO;
    }
    let f = (y & ((1 << 46) - 1)) as u64;
    let f16 = f >> 30; // 16 fractional bits are plenty for the interpolation
    let mantissa = lerp(&EXP2_Q30, (f16 >> 8) as usize, f16 & 0xff, 8); // Q30 in [2³⁰, 2³¹]
    // value in Q16 = mantissa · 2^k / 2^14
    let shift = k - 14;
    let bits = if shift >= 0 {
        mantissa << shift
    } else {
        round_shift(mantissa, (-shift) as u32)
    };
    Fx::from_bits(bits.min(i32::MAX as u64) as i32)
}

/// The natural logarithm; zero and negative input give [`Fx::MIN`] (−∞
/// saturated).
pub(super) fn ln(x: Fx) -> Fx {
    let b = x.to_bits();
    if b <= 0 {
        return Fx::MIN;
    }
    Fx::from_bits(ln_q16(b as u64, 16) as i32)
}

/// ln(b / 2^frac_bits) as Q16 bits, for `b > 0` (`b == 0` gives −2³¹).
pub(crate) fn ln_q16(b: u64, frac_bits: u32) -> i64 {
    if b == 0 {
        return i32::MIN as i64;
    }
    let msb = 63 - b.leading_zeros() as i64;
    let exponent = msb - frac_bits as i64; // b = m·2^exponent with m ∈ [1, 2)
    let m_frac = (b << (63 - msb)) & ((1 << 63) - 1); // Q63 fraction of m − 1
    let f32 = m_frac >> 31; // Q32
    let log2_m = lerp(&LOG2_Q31, (f32 >> 24) as usize, f32 & ((1 << 24) - 1), 24) as i128; // Q31
    let log2_x = ((exponent as i128) << 31) + log2_m; // Q31
    let ln_q63 = log2_x * LN2_Q32;
    let half = 1i128 << 46;
    let q16 = if ln_q63 >= 0 {
        (ln_q63 + half) >> 47
    } else {
        -((-ln_q63 + half) >> 47)
    };
    q16 as i64
}

/// The logistic function 1 / (1 + e^(−x)), exactly symmetric:
/// `σ(−x) = 1 − σ(x)`.
pub(super) fn sigmoid(x: Fx) -> Fx {
    let ax = (x.to_bits() as i64).unsigned_abs();
    // Table step is 1/32, i.e. 2¹¹ input LSB; beyond 16 σ rounds to 1.
    let index = (ax >> 11) as usize;
    let upper_q32 = if index >= SIGMOID_Q32.len() - 1 {
        1u64 << 32
    } else {
        lerp(&SIGMOID_Q32, index, ax & ((1 << 11) - 1), 11)
    };
    let upper = round_shift(upper_q32, 16) as i32;
    Fx::from_bits(if x.to_bits() < 0 {
        (1 << 16) - upper
    } else {
        upper
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_points() {
        assert_eq!(sin(Angle::ZERO), Fx::ZERO);
        assert_eq!(sin(Angle::QUARTER), Fx::ONE);
        assert_eq!(sin(Angle::HALF), Fx::ZERO);
        assert_eq!(cos(Angle::ZERO), Fx::ONE);
        assert_eq!(cos(Angle::HALF), -Fx::ONE);
        assert_eq!(sqrt(Fx::from_int(4)), Fx::from_int(2));
        assert_eq!(sqrt(Fx::from_int(-4)), Fx::ZERO);
        assert_eq!(exp(Fx::ZERO), Fx::ONE);
        assert_eq!(exp(Fx::from_int(11)), Fx::MAX);
        assert_eq!(exp(Fx::from_int(-12)), Fx::ZERO);
        assert_eq!(ln(Fx::ONE), Fx::ZERO);
        assert_eq!(ln(Fx::ZERO), Fx::MIN);
        assert_eq!(sigmoid(Fx::ZERO), Fx::HALF);
        assert_eq!(sigmoid(Fx::from_int(20)), Fx::ONE);
        assert_eq!(sigmoid(Fx::from_int(-20)), Fx::ZERO);
        assert_eq!(atan2(Fx::ONE, Fx::ONE), Angle::from_degrees(45));
        assert_eq!(atan2(Fx::ONE, Fx::ZERO), Angle::QUARTER);
        assert_eq!(atan2(Fx::ZERO, -Fx::ONE), Angle::HALF);
        assert_eq!(atan2(-Fx::ONE, Fx::ZERO), Angle::from_degrees(-90));
        assert_eq!(atan2(Fx::ZERO, Fx::ZERO), Angle::ZERO);
    }

    #[test]
    fn sigmoid_is_exactly_symmetric() {
        for bits in (-(20 << 16)..(20 << 16)).step_by(997) {
            let x = Fx::from_bits(bits);
            assert_eq!(sigmoid(x) + sigmoid(-x), Fx::ONE, "at {x}");
        }
    }
}
