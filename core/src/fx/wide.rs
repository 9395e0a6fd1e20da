//! Fixed-point vectors summed in a wide accumulator: dot products and
//! lengths exact to one rounding (the `Real` face of [`Fx`] and the
//! geometry share them).

use nalgebra::Vector3;

use super::Fx;
use super::root::rounded_isqrt_u64;

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
    // A sum of squares is non-negative.
    length_of_squared(dot_wide(v, v) as u64)
}

/// The length whose square is `squared_q32` (Q32 bits, as [`dot_wide`]
/// gives it), rounded to nearest and saturated: [`length`] for a square
/// already at hand (the shrinkwrap's field takes one per skeleton element
/// per evaluation).
#[must_use]
pub fn length_of_squared(squared_q32: u64) -> Fx {
    let rounded = rounded_isqrt_u64(squared_q32); // Q16
    Fx::from_bits(rounded.min(i32::MAX as u64) as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_of_squared_is_length() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let c = |k: u32| Fx::from_bits((state >> k) as i32 >> (state % 31));
            let v = Vector3::new(c(0), c(16), c(32));
            assert_eq!(length_of_squared(dot_wide(&v, &v) as u64), length(&v));
        }
        let extreme = Vector3::new(Fx::MIN, Fx::MIN, Fx::MIN);
        assert_eq!(
            length_of_squared(dot_wide(&extreme, &extreme) as u64),
            Fx::MAX
        );
    }
}
