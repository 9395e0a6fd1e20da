//! The I16F16 scalar with saturating, round-to-nearest arithmetic.

use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use fixed::types::I16F16;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A signed fixed-point number with 16 integer and 16 fractional bits
/// (range ±32768, resolution 2⁻¹⁶ ≈ 1.5·10⁻⁵).
///
/// A newtype over [`fixed::types::I16F16`] whose operators follow the
/// crate's overflow policy (see [`crate::fx`]): they saturate, in debug and
/// release alike, so nalgebra's generic matrix code can use them safely.
///
/// ```
/// use morphogen::fx::Fx;
/// let a = Fx::from_ratio(3, 2);
/// assert_eq!(a * Fx::from_int(2), Fx::from_int(3));
/// assert_eq!(Fx::MAX + Fx::ONE, Fx::MAX); // saturates
/// ```
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Fx(I16F16);

const FRAC: u32 = 16;

/// Narrows an `i64` to `i32`, saturating.
const fn saturate(v: i64) -> i32 {
    if v > i32::MAX as i64 {
        i32::MAX
    } else if v < i32::MIN as i64 {
        i32::MIN
    } else {
        v as i32
    }
}

/// Divides with rounding to nearest, half away from zero; `d` must be > 0.
const fn div_round(n: i64, d: i64) -> i64 {
    if n >= 0 {
        (n + d / 2) / d
    } else {
        -((-n + d / 2) / d)
    }
}

impl Fx {
    /// 0.
    pub const ZERO: Fx = Fx::from_bits(0);
    /// 1.
    pub const ONE: Fx = Fx::from_bits(1 << FRAC);
    /// 0.5.
    pub const HALF: Fx = Fx::from_bits(1 << (FRAC - 1));
    /// The smallest positive value, 2⁻¹⁶ (one LSB).
    pub const DELTA: Fx = Fx::from_bits(1);
    /// The largest value, 32768 − 2⁻¹⁶.
    pub const MAX: Fx = Fx::from_bits(i32::MAX);
    /// The smallest value, −32768.
    pub const MIN: Fx = Fx::from_bits(i32::MIN);
    /// π, rounded to nearest.
    pub const PI: Fx = Fx::from_bits(205_887);

    /// The number whose raw two's-complement bits are `bits` (value `bits / 65536`).
    #[must_use]
    pub const fn from_bits(bits: i32) -> Fx {
        Fx(I16F16::from_bits(bits))
    }

    /// The raw bits (value × 65536).
    #[must_use]
    pub const fn to_bits(self) -> i32 {
        self.0.to_bits()
    }

    /// An integer, saturating outside ±32768.
    #[must_use]
    pub const fn from_int(i: i32) -> Fx {
        Fx::from_bits(saturate((i as i64) << FRAC))
    }

    /// `num / den` rounded to nearest; `den == 0` saturates like division.
    /// A `const fn`, so constants from the papers are written exactly:
    /// `Fx::from_ratio(137, 100)` is 1.37.
    #[must_use]
    pub const fn from_ratio(num: i32, den: i32) -> Fx {
        Fx::from_bits(div_bits((num as i64) << FRAC, den as i64))
    }

    /// The wrapped `fixed` value, for formatting and parsing.
    #[must_use]
    pub const fn to_fixed(self) -> I16F16 {
        self.0
    }

    /// Wraps a `fixed` value.
    #[must_use]
    pub const fn from_fixed(v: I16F16) -> Fx {
        Fx(v)
    }

    /// Absolute value, saturating (`|MIN| = MAX`).
    #[must_use]
    pub const fn abs(self) -> Fx {
        Fx::from_bits(self.to_bits().saturating_abs())
    }

    /// The largest integer not above `self`.
    #[must_use]
    pub const fn floor(self) -> Fx {
        Fx::from_bits(self.to_bits() & !((1 << FRAC) - 1))
    }

    /// The integer part, rounded towards −∞.
    #[must_use]
    pub const fn floor_int(self) -> i32 {
        self.to_bits() >> FRAC
    }

    /// The product, rounded to nearest and saturated.
    #[must_use]
    pub const fn saturating_mul(self, rhs: Fx) -> Fx {
        let p = self.to_bits() as i64 * rhs.to_bits() as i64;
        Fx::from_bits(saturate((p + (1 << (FRAC - 1))) >> FRAC))
    }

    /// The product with an integer, saturated.
    #[must_use]
    pub const fn saturating_mul_int(self, rhs: i32) -> Fx {
        Fx::from_bits(saturate(self.to_bits() as i64 * rhs as i64))
    }

    /// The quotient rounded to nearest, or `None` when `rhs` is zero or the
    /// result does not fit.
    #[must_use]
    pub const fn checked_div(self, rhs: Fx) -> Option<Fx> {
        if rhs.to_bits() == 0 {
            return None;
        }
        let q = div_bits((self.to_bits() as i64) << FRAC, rhs.to_bits() as i64);
        let exact = div_round_signed((self.to_bits() as i64) << FRAC, rhs.to_bits() as i64);
        if exact != q as i64 {
            None
        } else {
            Some(Fx::from_bits(q))
        }
    }

    /// The quotient rounded to nearest and saturated; `x / 0` is `MAX`,
    /// `MIN` or (for `0 / 0`) zero.
    #[must_use]
    pub const fn saturating_div(self, rhs: Fx) -> Fx {
        Fx::from_bits(div_bits(
            (self.to_bits() as i64) << FRAC,
            rhs.to_bits() as i64,
        ))
    }

    /// `1 / self`, saturated (see [`Fx::saturating_div`]).
    #[must_use]
    pub const fn recip(self) -> Fx {
        Fx::ONE.saturating_div(self)
    }

    /// The smaller of two values.
    #[must_use]
    pub const fn min(self, other: Fx) -> Fx {
        if self.to_bits() <= other.to_bits() {
            self
        } else {
            other
        }
    }

    /// The larger of two values.
    #[must_use]
    pub const fn max(self, other: Fx) -> Fx {
        if self.to_bits() >= other.to_bits() {
            self
        } else {
            other
        }
    }

    /// `self` limited to `[lo, hi]`.
    #[must_use]
    pub const fn clamp(self, lo: Fx, hi: Fx) -> Fx {
        self.max(lo).min(hi)
    }
}

/// `n / d` rounded to nearest with a signed divisor, not yet saturated.
const fn div_round_signed(n: i64, d: i64) -> i64 {
    if d < 0 {
        div_round(-n, -d)
    } else {
        div_round(n, d)
    }
}

/// Saturating, rounded fixed-point quotient of pre-shifted `n` by `d`.
const fn div_bits(n: i64, d: i64) -> i32 {
    if d == 0 {
        return if n > 0 {
            i32::MAX
        } else if n < 0 {
            i32::MIN
        } else {
            0
        };
    }
    saturate(div_round_signed(n, d))
}

impl Add for Fx {
    type Output = Fx;
    fn add(self, rhs: Fx) -> Fx {
        Fx(self.0.saturating_add(rhs.0))
    }
}

impl Sub for Fx {
    type Output = Fx;
    fn sub(self, rhs: Fx) -> Fx {
        Fx(self.0.saturating_sub(rhs.0))
    }
}

impl Mul for Fx {
    type Output = Fx;
    fn mul(self, rhs: Fx) -> Fx {
        self.saturating_mul(rhs)
    }
}

impl Div for Fx {
    type Output = Fx;
    fn div(self, rhs: Fx) -> Fx {
        self.saturating_div(rhs)
    }
}

impl Neg for Fx {
    type Output = Fx;
    fn neg(self) -> Fx {
        Fx(self.0.saturating_neg())
    }
}

macro_rules! assign_op {
    ($Trait:ident, $method:ident, $op:tt) => {
        impl $Trait for Fx {
            fn $method(&mut self, rhs: Fx) {
                *self = *self $op rhs;
            }
        }
    };
}
assign_op!(AddAssign, add_assign, +);
assign_op!(SubAssign, sub_assign, -);
assign_op!(MulAssign, mul_assign, *);
assign_op!(DivAssign, div_assign, /);

impl num_traits::Zero for Fx {
    fn zero() -> Fx {
        Fx::ZERO
    }
    fn is_zero(&self) -> bool {
        self.to_bits() == 0
    }
}

impl num_traits::One for Fx {
    fn one() -> Fx {
        Fx::ONE
    }
}

impl fmt::Debug for Fx {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

impl fmt::Display for Fx {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Fx {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "Fx({=i32:#x})", self.to_bits());
    }
}

/// On the wire an `Fx` is its raw `i32` bits (postcard: zigzag varint).
impl Serialize for Fx {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_i32(self.to_bits())
    }
}

impl<'de> Deserialize<'de> for Fx {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Fx, D::Error> {
        i32::deserialize(d).map(Fx::from_bits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multiplication_rounds_to_nearest_and_saturates() {
        let third = Fx::from_ratio(1, 3);
        assert_eq!(third.to_bits(), 21_845);
        assert_eq!((third * Fx::from_int(3)).to_bits(), 65_535);
        assert_eq!((Fx::DELTA * Fx::HALF).to_bits(), 1); // 0.5 LSB rounds up
        assert_eq!((-Fx::DELTA * Fx::HALF).to_bits(), 0); // −0.5 LSB rounds up
        assert_eq!(Fx::from_int(300) * Fx::from_int(300), Fx::MAX);
        assert_eq!(Fx::from_int(-300) * Fx::from_int(300), Fx::MIN);
    }

    #[test]
    fn division_rounds_and_saturates() {
        assert_eq!(Fx::ONE / Fx::from_int(3), Fx::from_ratio(1, 3));
        assert_eq!((-Fx::ONE / Fx::from_int(3)).to_bits(), -21_845);
        assert_eq!(Fx::ONE / Fx::ZERO, Fx::MAX);
        assert_eq!(-Fx::ONE / Fx::ZERO, Fx::MIN);
        assert_eq!(Fx::ZERO / Fx::ZERO, Fx::ZERO);
        assert_eq!(Fx::ONE.checked_div(Fx::ZERO), None);
        assert_eq!(Fx::from_int(1000).checked_div(Fx::from_ratio(1, 100)), None);
        assert_eq!(
            Fx::from_int(7).checked_div(Fx::from_int(2)),
            Some(Fx::from_ratio(7, 2))
        );
        assert_eq!(Fx::from_int(2).recip(), Fx::HALF);
    }

    #[test]
    fn addition_saturates_identically_in_debug_and_release() {
        assert_eq!(Fx::MAX + Fx::DELTA, Fx::MAX);
        assert_eq!(Fx::MIN - Fx::DELTA, Fx::MIN);
        assert_eq!(-Fx::MIN, Fx::MAX);
        assert_eq!(Fx::MIN.abs(), Fx::MAX);
        assert_eq!(Fx::from_int(40_000), Fx::MAX);
    }

    #[test]
    fn floor_rounds_towards_negative_infinity() {
        assert_eq!(Fx::from_ratio(-3, 2).floor(), Fx::from_int(-2));
        assert_eq!(Fx::from_ratio(-3, 2).floor_int(), -2);
        assert_eq!(Fx::from_ratio(5, 2).floor_int(), 2);
    }
}
