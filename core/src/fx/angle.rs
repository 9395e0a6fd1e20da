//! Binary angles: a `u32` where 2³² is one full turn, so wrap-around is free
//! and exact (README.md, "How it is built").

use core::ops::{Add, AddAssign, Neg, Sub, SubAssign};

use serde::{Deserialize, Serialize};

use super::Fx;

/// An angle as a fraction of a turn: `Angle(1 << 30)` is 90°.
///
/// Addition and subtraction wrap modulo one turn.
///
/// ```
/// use morphogen::fx::Angle;
/// assert_eq!(Angle::from_degrees(90), Angle::QUARTER);
/// assert_eq!(Angle::from_degrees(270) + Angle::QUARTER, Angle::ZERO);
/// ```
#[derive(
    Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Debug, Serialize, Deserialize,
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Angle(pub u32);

/// 2³² / 360, the binary-angle units in one degree, as Q16 (rounded).
const UNITS_PER_DEGREE_Q16: i64 = 781_874_935_307;
/// 2³² / 2π, the binary-angle units in one radian, as Q16 (rounded).
const UNITS_PER_RADIAN_Q16: i128 = 44_798_133_900_177;

impl Angle {
    /// No rotation.
    pub const ZERO: Angle = Angle(0);
    /// A quarter turn, 90°.
    pub const QUARTER: Angle = Angle(1 << 30);
    /// Half a turn, 180°.
    pub const HALF: Angle = Angle(1 << 31);

    /// Whole degrees, exactly rounded (`const`, for parameter tables).
    #[must_use]
    pub const fn from_degrees(deg: i32) -> Angle {
        Angle::from_turn_ratio(deg as i64, 360)
    }

    /// `num / den` of a turn, rounded to nearest (`const`); `den` must not
    /// be zero (a zero `den` gives [`Angle::ZERO`]).
    #[must_use]
    pub const fn from_turn_ratio(num: i64, den: i64) -> Angle {
        if den == 0 {
            return Angle::ZERO;
        }
        let n = (num as i128) << 32;
        let d = den as i128;
        let q = if (n >= 0) == (d > 0) {
            (n.abs() + d.abs() / 2) / d.abs()
        } else {
            -((n.abs() + d.abs() / 2) / d.abs())
        };
        Angle(q as u32)
    }

    /// Degrees given as a fixed-point number (e.g. read from a grammar), any
    /// magnitude: the product is taken modulo 2⁶⁴, whose bits 32..63 are
    /// exactly the angle modulo one turn, rounded.
    #[must_use]
    pub const fn from_degrees_fx(deg: Fx) -> Angle {
        let units = (deg.to_bits() as i64)
            .wrapping_mul(UNITS_PER_DEGREE_Q16)
            .wrapping_add(1 << 31)
            >> 32;
        Angle(units as u32)
    }

    /// Radians given as a fixed-point number.
    #[must_use]
    pub const fn from_radians_fx(rad: Fx) -> Angle {
        let units = (rad.to_bits() as i128 * UNITS_PER_RADIAN_Q16 + (1 << 31)) >> 32;
        Angle(units as u32)
    }

    /// The angle as a signed number of units in `[-2³¹, 2³¹)`, i.e. in
    /// `[−180°, 180°)`.
    #[must_use]
    pub const fn signed(self) -> i32 {
        self.0 as i32
    }

    /// The angle scaled by a fixed-point factor, taking the angle as signed
    /// (`[−180°, 180°)`) and rounding to nearest; the product wraps modulo a
    /// turn. Used for `α(τ) = α(T)·f(τ)` (horn paper, Sec. 6).
    #[must_use]
    pub const fn scale(self, factor: Fx) -> Angle {
        let p = self.signed() as i64 * factor.to_bits() as i64;
        Angle(((p + (1 << 15)) >> 16) as u32)
    }

    /// The angle times an integer, wrapping.
    #[must_use]
    pub const fn times(self, n: u32) -> Angle {
        Angle(self.0.wrapping_mul(n))
    }

    /// The angle in degrees in `[−180, 180)`, rounded (for display).
    #[must_use]
    pub const fn to_degrees_fx(self) -> Fx {
        let num = (self.signed() as i64) << 32;
        Fx::from_bits((num + UNITS_PER_DEGREE_Q16 / 2).div_euclid(UNITS_PER_DEGREE_Q16) as i32)
    }
}

impl Add for Angle {
    type Output = Angle;
    fn add(self, rhs: Angle) -> Angle {
        Angle(self.0.wrapping_add(rhs.0))
    }
}

impl Sub for Angle {
    type Output = Angle;
    fn sub(self, rhs: Angle) -> Angle {
        Angle(self.0.wrapping_sub(rhs.0))
    }
}

impl Neg for Angle {
    type Output = Angle;
    fn neg(self) -> Angle {
        Angle(self.0.wrapping_neg())
    }
}

impl AddAssign for Angle {
    fn add_assign(&mut self, rhs: Angle) {
        *self = *self + rhs;
    }
}

impl SubAssign for Angle {
    fn sub_assign(&mut self, rhs: Angle) {
        *self = *self - rhs;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degrees_convert_exactly_where_they_can() {
        assert_eq!(Angle::from_degrees(180), Angle::HALF);
        assert_eq!(Angle::from_degrees(-90), Angle(3 << 30));
        assert_eq!(Angle::from_degrees(45).0, 1 << 29);
        assert_eq!(Angle::from_degrees_fx(Fx::from_int(90)), Angle::QUARTER);
        assert_eq!(
            Angle::from_degrees_fx(Fx::from_ratio(45, 2)),
            Angle::from_turn_ratio(1, 16)
        );
        assert_eq!(Angle::from_radians_fx(Fx::PI), Angle(2_147_479_307)); // Fx::PI is π rounded to Q16
        assert_eq!(Angle::QUARTER.to_degrees_fx(), Fx::from_int(90));
        assert_eq!(Angle::from_degrees(-30).to_degrees_fx(), Fx::from_int(-30));
    }

    #[test]
    fn degrees_of_any_magnitude_wrap() {
        assert_eq!(
            Angle::from_degrees_fx(Fx::from_int(270)),
            Angle::from_degrees(-90)
        );
        assert_eq!(Angle::from_degrees_fx(Fx::from_int(-720)), Angle::ZERO);
        assert_eq!(
            Angle::from_degrees_fx(Fx::MAX),
            Angle::from_degrees_fx(Fx::MAX - Fx::from_int(360))
        );
        // Far from zero the rounded degree constant costs up to one unit.
        let far =
            Angle::from_degrees_fx(Fx::MIN) - Angle::from_degrees_fx(Fx::MIN + Fx::from_int(720));
        assert!(far.signed().abs() <= 1, "{far:?}");
    }

    #[test]
    fn scaling_takes_the_angle_as_signed() {
        assert_eq!(
            Angle::from_degrees(90).scale(Fx::HALF),
            Angle::from_degrees(45)
        );
        assert_eq!(
            Angle::from_degrees(-90).scale(Fx::HALF),
            Angle::from_degrees(-45)
        );
        let eighty = Angle::from_degrees(80).scale(Fx::HALF) - Angle::from_degrees(40);
        assert!(eighty.signed().abs() <= 1, "off by {eighty:?}");
        assert_eq!(Angle::from_degrees(75).scale(Fx::ZERO), Angle::ZERO);
        assert_eq!(
            Angle::from_degrees(75).scale(Fx::ONE),
            Angle::from_degrees(75)
        );
        assert_eq!(Angle::QUARTER.times(4), Angle::ZERO);
    }
}
