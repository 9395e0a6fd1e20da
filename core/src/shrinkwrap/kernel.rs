//! The fixed-point pieces both shrinkwrap fields evaluate with: the
//! elements' (`field`) and the vertices' (bones paper, eqs. 1–2;
//! `vertices`).

use crate::fx::root::rounded_isqrt_u62;

/// u·w of Q16 bits within ±2³⁰, exact in Q32 (below 3·2⁶⁰).
pub(super) fn dot_near(u: &[i32; 3], w: &[i32; 3]) -> i64 {
    let product = |k: usize| (u[k] as i64).wrapping_mul(w[k] as i64);
    product(0).wrapping_add(product(1)).wrapping_add(product(2))
}

/// `inverse_distance(length_of_squared(squared))` for the square of an
/// offset within ±2³⁰ (below 3·2⁶⁰: its rounded root is below 2³¹, where
/// `length_of_squared` does not saturate) in fewer steps: the distance is
/// held at 2⁻¹² (16 bits) by rooting at least 241, since
/// √240 + ½ < 16 ≤ √241 + ½.
pub(super) fn inverse_of_squared(squared: u64) -> u32 {
    // The max(16) changes nothing; it spares the division a zero check.
    let d = (rounded_isqrt_u62(squared.max(241)) as u32).max(16);
    (0u32.wrapping_sub(d.wrapping_sub(d / 2)) / d).wrapping_add(1)
}
