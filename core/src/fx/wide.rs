//! Fixed-point vectors summed in a wide accumulator: dot products and
//! lengths exact to one rounding (the `Real` face of [`Fx`] and the
//! geometry share them).

use nalgebra::Vector3;

use super::Fx;

/// The dot product of two fixed-point vectors in a wide accumulator: the
/// exact sum of products as Q32 bits (no rounding; it saturates only
/// beyond ±2⁶³, i.e. for components near the I16F16 limits).
#[must_use]
pub fn dot_wide(a: &Vector3<Fx>, b: &Vector3<Fx>) -> i64 {
    a.iter().zip(b.iter()).fold(0i64, |acc, (x, y)| {
        acc.saturating_add(x.to_bits() as i64 * y.to_bits() as i64)
    })
}

/// The Euclidean length of a fixed-point vector, from a wide accumulator
/// (exactly rounded up to saturation).
#[must_use]
pub fn length(v: &Vector3<Fx>) -> Fx {
    let squared_q32 = dot_wide(v, v) as u64; // a sum of squares is non-negative
    let r = squared_q32.isqrt(); // Q16
    let rounded = if squared_q32 - r * r > r { r + 1 } else { r };
    Fx::from_bits(rounded.min(i32::MAX as u64) as i32)
}
