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

/// Narrows an `i64` to `i32`, saturating. Written as "does it survive the
/// round trip" (on a 32-bit core: one compare of the high word with the low
/// word's sign), and the bound from the sign (`-1 ^ MAX` is `MIN`): inlined
/// at every product, this is a fifth of the flash two range compares
/// would take.
const fn saturate(v: i64) -> i32 {
    let narrow = v as i32;
    if narrow as i64 == v {
        narrow
    } else {
        (v >> 63) as i32 ^ i32::MAX
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

    /// `num / den` rounded to nearest, ties away from zero; `den == 0`
    /// saturates like division. A `const fn`, so constants from the papers
    /// are written exactly: `Fx::from_ratio(137, 100)` is 1.37.
    ///
    /// A decimal written as its digits over its power of ten
    /// (`Fx::from_ratio(-1299, 1000)` for −1.299) is the value a scenario
    /// file's reader gives the decimal (it rounds the nearest `f64` to
    /// nearest, ties away from zero, and an `i32` ratio of a power of ten is
    /// never close enough to a tie for that `f64` to differ; the scenario
    /// crate's `from_ratio_rounds_decimals_as_the_reader` test checks it):
    /// hand-written parameters then have the scenario's parameter digest.
    /// [`Fx::from_decimal`] instead rounds ties to even, as `fixed`'s
    /// parser (and the L-system grammars) do: for a tie such as
    /// `0.00000762939453125` (2⁻¹⁷) the two differ by one LSB.
    #[must_use]
    pub const fn from_ratio(num: i32, den: i32) -> Fx {
        Fx::from_bits(div_bits((num as i64) << FRAC, den as i64))
    }

    /// `num / den` of two sums of raw bits at any scale (`num` in the
    /// scale of `den` times 2¹⁶), rounded to nearest and saturated as
    /// [`Fx::from_ratio`]: a mean or a quotient taken once from exact
    /// sums. `den` > 0.
    #[must_use]
    pub(crate) const fn from_wide_ratio(num: i64, den: i64) -> Fx {
        // Rounded as `div_round`, written out: a further caller of it
        // changes how the body kernels' divisions are inlined (8 % more
        // cycles for cow-growth on a Cortex-M3).
        let half = den / 2;
        let q = if num >= 0 {
            (num + half) / den
        } else {
            (num - half) / den
        };
        Fx::from_bits(saturate(q))
    }

    /// The non-negative decimal number `int.frac` (ASCII digits; either
    /// part may be empty) as `fixed`'s `I16F16::from_str` (1.29) parses it,
    /// computed with a few integer operations (that general parser is some
    /// 3 KB of firmware code): rounded to nearest, ties to even — except
    /// where `fixed` takes a fraction of 7 to 16 significant digits that
    /// its half-way point (k + ½)·2⁻¹⁶ starts with for that half-way point
    /// itself, a tie (so `0.3251876`, just below 21311.5 LSBs, gives 21312
    /// like `0.32518768310546875`). `None` for a byte that is not a digit,
    /// or a rounded value above [`Fx::MAX`].
    ///
    /// ```
    /// use morphogen::fx::Fx;
    /// assert_eq!(Fx::from_decimal(b"1", b"5"), Some(Fx::from_ratio(3, 2)));
    /// assert_eq!(Fx::from_decimal(b"", b"00000762939453125"), Some(Fx::ZERO)); // 2⁻¹⁷: a tie, to even
    /// assert_eq!(Fx::from_decimal(b"32768", b""), None);
    /// ```
    #[must_use]
    pub fn from_decimal(int: &[u8], frac: &[u8]) -> Option<Fx> {
        /// Digits of the fraction taken exactly: (k + ½)·2⁻¹⁶ has 17
        /// decimals, so a tie needs no more, and the digits after them only
        /// say whether the value is above one.
        const EXACT: usize = 17;
        /// 10¹⁷ / 2¹⁶ = 2·5¹⁷: the first `EXACT` digits as an integer `n`
        /// are `n / SCALE` LSBs.
        const SCALE: u64 = 2 * 762_939_453_125;
        /// Up to this many significant digits `fixed` rounds exactly.
        const FIXED_EXACT: usize = 6;
        let digit = |b: u8| b.is_ascii_digit().then(|| u64::from(b - b'0'));
        let mut whole = 0u64;
        for &b in int {
            // Above `MAX`'s integer part it stays above: no overflow.
            whole = (whole * 10 + digit(b)?).min(1 << FRAC);
        }
        // n < 10¹⁷ < 2⁵⁷.
        let mut n = 0u64;
        let mut rest_nonzero = false;
        let mut significant = 0;
        for k in 0..frac.len().max(EXACT) {
            let d = match frac.get(k) {
                Some(&b) => digit(b)?,
                None => 0,
            };
            if d != 0 {
                significant = k + 1;
            }
            if k < EXACT {
                n = n * 10 + d;
            } else {
                rest_nonzero |= d != 0;
            }
        }
        let (lsbs, rest) = (n / SCALE, n % SCALE);
        let half = SCALE / 2;
        // `fixed`'s tie: the digits are a proper prefix of the half-way
        // point's, which is above them by less than one unit of the last.
        let prefix_of_half = (FIXED_EXACT + 1..EXACT).contains(&significant)
            && rest < half
            && half - rest < 10u64.pow((EXACT - significant) as u32);
        let tie = (rest == half && !rest_nonzero) || prefix_of_half;
        let up = if tie { lsbs & 1 == 1 } else { rest >= half };
        let bits = (whole << FRAC) + lsbs + u64::from(up);
        i32::try_from(bits).ok().map(Fx::from_bits)
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
    fn saturate_is_a_clamp() {
        let edges = [i32::MIN as i64, i32::MAX as i64, 0, 1, -1];
        for edge in edges {
            for d in -2..=2i64 {
                let v = edge + d;
                assert_eq!(
                    saturate(v) as i64,
                    v.clamp(i32::MIN as i64, i32::MAX as i64),
                    "{v}"
                );
            }
        }
        for v in [
            i64::MIN,
            i64::MAX,
            i64::MIN + 1,
            i64::MAX - 1,
            1 << 40,
            -(1 << 40),
        ] {
            assert_eq!(
                saturate(v) as i64,
                v.clamp(i32::MIN as i64, i32::MAX as i64),
                "{v}"
            );
        }
    }

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

    /// `from_decimal` against `fixed`'s parser, which it replaces on the
    /// device: short and long fractions, exact ties (k/2¹⁷, the only
    /// values with a half LSB) with and without digits after them, and the
    /// edge of the range.
    #[test]
    fn from_decimal_is_fixed_from_str() {
        let check = |int: &str, frac: &str| {
            let text = format!(
                "{}.{}",
                if int.is_empty() { "0" } else { int },
                if frac.is_empty() { "0" } else { frac }
            );
            let expected = I16F16::from_str(&text).ok().map(Fx::from_fixed);
            assert_eq!(
                Fx::from_decimal(int.as_bytes(), frac.as_bytes()),
                expected,
                "{text}"
            );
        };
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        };
        for _ in 0..20_000 {
            let int = next(40_000).to_string();
            let digits = next(30) as usize;
            let frac: String = (0..digits)
                .map(|_| char::from(b'0' + next(10) as u8))
                .collect();
            check(&int, &frac);
            check("", &frac);
        }
        for _ in 0..20_000 {
            // k/2¹⁷ exactly (17 decimals), then maybe a non-zero digit.
            let k = next(1 << 17);
            let tie = format!("{:017}", k * 762_939_453_125);
            let int = next(32_768).to_string();
            check(&int, &tie);
            check(&int, &format!("{tie}0000"));
            check(&int, &format!("{tie}0001"));
        }
        for _ in 0..20_000 {
            // The first 7 to 16 digits of a half-way point (k + ½)·2⁻¹⁶.
            let k = 2 * next(1 << 16) + 1;
            let half = format!("{:017}", k * 762_939_453_125);
            let digits = 7 + next(10) as usize;
            check(&next(100).to_string(), &half[..digits]);
        }
        for (int, frac) in [
            ("", "3251876"),
            ("0000000000000000000000000000001", "5"),
            ("32767", "99999237060546875"),
            ("32767", "999992370605468750001"),
            ("32767", "99999618530273437"),
            ("32767", "999996185302734375"),
            ("32767", "9999961853027343750001"),
            ("32768", ""),
            ("0032767", "5"),
            ("", ""),
            ("99999999999999999999999", "1"),
        ] {
            check(int, frac);
        }
        assert_eq!(Fx::from_decimal(b"1a", b""), None);
        assert_eq!(Fx::from_decimal(b"1", b"5x"), None);
    }
}
