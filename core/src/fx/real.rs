//! The scalar trait every kernel is generic over: [`Fx`] computes what
//! fixtures hold, `f64` (through `libm`) is the accuracy reference.

#![allow(clippy::float_arithmetic)] // the f64 reference implementation lives here

use core::fmt::Debug;
use core::ops::Neg;

use nalgebra::{ClosedAddAssign, ClosedMulAssign, ClosedSubAssign, Scalar, Vector3};
use num_traits::{One, Zero};

use super::wide::{dot_wide, length};
use super::{Angle, Fx, func};

/// A real number type a kernel computes with.
///
/// For [`Fx`] every operation follows the fixed-point overflow policy
/// (saturating, round to nearest); for `f64` it is the exact `libm`
/// function. Write a kernel once as `fn step<R: Real>(…)` and compare the
/// two instances to measure the fixed-point error.
pub trait Real:
    Scalar
    + Copy
    + Debug
    + PartialOrd
    + Zero
    + One
    + ClosedAddAssign
    + ClosedSubAssign
    + ClosedMulAssign
    + Neg<Output = Self>
{
    /// Converts a fixed-point parameter (exactly, for `f64`).
    fn from_fx(x: Fx) -> Self;
    /// An integer.
    fn from_int(i: i32) -> Self;
    /// `num / den` (rounded for [`Fx`]).
    fn from_ratio(num: i32, den: i32) -> Self;
    /// The value as `f64`, for comparisons against the reference.
    fn to_f64(self) -> f64;
    /// Division (saturating for [`Fx`]; `x / 0` saturates).
    fn div(self, rhs: Self) -> Self;
    /// (self + other)·½, rounded as that sum and product are in this type.
    fn midpoint(self, other: Self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Square root; negative input gives zero.
    fn sqrt(self) -> Self;
    /// e^self.
    fn exp(self) -> Self;
    /// ln(self); non-positive input gives the most negative value.
    fn ln(self) -> Self;
    /// The logistic function 1 / (1 + e^(−self)).
    fn sigmoid(self) -> Self;
    /// sin of a binary angle.
    fn sin(a: Angle) -> Self;
    /// cos of a binary angle.
    fn cos(a: Angle) -> Self;
    /// The angle of `(x, y)`.
    fn atan2(y: Self, x: Self) -> Angle;
    /// `a · self` for an angle `a` taken as signed (see [`Angle::scale`]).
    fn scale_angle(self, a: Angle) -> Angle;

    /// An accumulator for sums of many terms: exact Q16 bits in an `i64`
    /// for [`Fx`] (rounded once, by [`Real::narrow`]), `f64` for `f64`.
    type Wide: Copy + Default;
    /// `acc + x` in the accumulator.
    fn widen(acc: Self::Wide, x: Self) -> Self::Wide;
    /// The accumulated sum (saturating for [`Fx`]).
    fn narrow(acc: Self::Wide) -> Self;
    /// `a · b` from a wide accumulator (rounded once for [`Fx`]).
    fn dot(a: &Vector3<Self>, b: &Vector3<Self>) -> Self;
    /// `‖v‖` from a wide accumulator (exactly rounded for [`Fx`]).
    fn norm(v: &Vector3<Self>) -> Self;
}

impl Real for Fx {
    fn from_fx(x: Fx) -> Fx {
        x
    }
    fn from_int(i: i32) -> Fx {
        Fx::from_int(i)
    }
    fn from_ratio(num: i32, den: i32) -> Fx {
        Fx::from_ratio(num, den)
    }
    fn to_f64(self) -> f64 {
        self.to_fixed().to_num::<f64>()
    }
    fn div(self, rhs: Fx) -> Fx {
        self.saturating_div(rhs)
    }
    fn midpoint(self, other: Fx) -> Fx {
        // The saturating sum s times ½ (2¹⁵ bits), rounded half up as
        // `Fx::saturating_mul`: (s·2¹⁵ + 2¹⁵) >> 16 = ⌊(s + 1)/2⌋, within
        // i32 (no saturation), in three instructions.
        let s = i64::from((self + other).to_bits());
        Fx::from_bits(((s + 1) >> 1) as i32)
    }
    fn abs(self) -> Fx {
        Fx::abs(self)
    }
    fn sqrt(self) -> Fx {
        func::sqrt(self)
    }
    fn exp(self) -> Fx {
        func::exp(self)
    }
    fn ln(self) -> Fx {
        func::ln(self)
    }
    fn sigmoid(self) -> Fx {
        func::sigmoid(self)
    }
    fn sin(a: Angle) -> Fx {
        func::sin(a)
    }
    fn cos(a: Angle) -> Fx {
        func::cos(a)
    }
    fn atan2(y: Fx, x: Fx) -> Angle {
        func::atan2(y, x)
    }
    fn scale_angle(self, a: Angle) -> Angle {
        a.scale(self)
    }

    type Wide = i64;
    fn widen(acc: i64, x: Fx) -> i64 {
        acc.saturating_add(x.to_bits() as i64)
    }
    fn narrow(acc: i64) -> Fx {
        Fx::from_bits(acc.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
    }
    fn dot(a: &Vector3<Fx>, b: &Vector3<Fx>) -> Fx {
        // Q32 to Q16, rounding half up.
        let q16 = dot_wide(a, b).saturating_add(1 << 15) >> 16;
        Fx::from_bits(q16.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
    }
    fn norm(v: &Vector3<Fx>) -> Fx {
        length(v)
    }
}

/// Turns per binary-angle unit.
const TURN_UNITS: f64 = 4_294_967_296.0;

fn radians(a: Angle) -> f64 {
    a.signed() as f64 / TURN_UNITS * core::f64::consts::TAU
}

impl Real for f64 {
    fn from_fx(x: Fx) -> f64 {
        x.to_bits() as f64 / 65_536.0
    }
    fn from_int(i: i32) -> f64 {
        i as f64
    }
    fn from_ratio(num: i32, den: i32) -> f64 {
        num as f64 / den as f64
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn div(self, rhs: f64) -> f64 {
        self / rhs
    }
    fn midpoint(self, other: f64) -> f64 {
        (self + other) * 0.5
    }
    fn abs(self) -> f64 {
        libm::fabs(self)
    }
    fn sqrt(self) -> f64 {
        if self <= 0.0 { 0.0 } else { libm::sqrt(self) }
    }
    fn exp(self) -> f64 {
        libm::exp(self)
    }
    fn ln(self) -> f64 {
        if self <= 0.0 {
            f64::MIN
        } else {
            libm::log(self)
        }
    }
    fn sigmoid(self) -> f64 {
        1.0 / (1.0 + libm::exp(-self))
    }
    fn sin(a: Angle) -> f64 {
        libm::sin(radians(a))
    }
    fn cos(a: Angle) -> f64 {
        libm::cos(radians(a))
    }
    fn atan2(y: f64, x: f64) -> Angle {
        let turns = libm::atan2(y, x) / core::f64::consts::TAU;
        Angle(libm::round(turns * TURN_UNITS) as i64 as u32)
    }
    fn scale_angle(self, a: Angle) -> Angle {
        Angle(libm::round(a.signed() as f64 * self) as i64 as u32)
    }

    type Wide = f64;
    fn widen(acc: f64, x: f64) -> f64 {
        acc + x
    }
    fn narrow(acc: f64) -> f64 {
        acc
    }
    fn dot(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        a.x * b.x + a.y * b.y + a.z * b.z
    }
    fn norm(v: &Vector3<f64>) -> f64 {
        libm::sqrt(Self::dot(v, v))
    }
}
