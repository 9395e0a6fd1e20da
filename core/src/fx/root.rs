//! The integer square root of the relaxation's squared distances (thesis
//! Sec. 3.2.1.1, DESIGN.md "Clonal mosaic"): ⌊√n⌋ for every `u32`, from a
//! guess in a 192-byte table, one Newton step and one correction — one
//! division where `u32::isqrt` takes two (each a library call on a
//! Cortex-M0).

/// Newton's starting point for `x` in `[2^30, 2^32)`, indexed by
/// `(x >> 24) − 64`: `(⌊√(b·2^24 + 2^23)⌋ − 2^15) >> 7` for the top byte `b`,
/// so the guess `2^15 + 128·entry + 64` is within 192 of `√x`.
const GUESS: [u8; 192] = {
    let mut table = [0u8; 192];
    let mut k = 0;
    while k < table.len() {
        let middle = ((k as u32 + 64) << 24) | (1 << 23);
        // ⌊√middle⌋ ∈ [2^15, 2^16), so the entry is below 256.
        table[k] = ((middle.isqrt() - (1 << 15)) >> 7) as u8;
        k += 1;
    }
    table
};

/// ⌊√n⌋, exactly. Not inlined: one copy in flash for both relaxation
/// loops.
#[inline(never)]
#[must_use]
pub(crate) fn isqrt_u32(n: u32) -> u32 {
    if n == 0 {
        return 0;
    }
    // x = n·4^k in [2^30, 2^32); ⌊√n⌋ = ⌊⌊√x⌋ / 2^k⌋.
    let shift = n.leading_zeros() & !1;
    let x = n << shift;
    // x ≥ 2^30: the top byte is in [64, 256), the index in [0, 192).
    let entry = GUESS
        .get(((x >> 24) - 64) as usize)
        .map_or(0, |&e| u32::from(e));
    // y0 ∈ [2^15, 2^16): x / y0 < 2^17, so the sum cannot overflow.
    let y0 = (1 << 15) + (entry << 7) + 64;
    // Newton from |y0 − √x| ≤ 192 lands in [⌊√x⌋, ⌊√x⌋ + 1]: the step's
    // error (y0 − √x)²/(2·y0) is below 1, and the floors keep it at or above
    // ⌊√x⌋ (the tests check every square and its neighbours).
    let y1 = ((y0 + x / y0) >> 1).min(0xFFFF); // ⌊√x⌋ ≤ 0xFFFF, so y1² fits
    let root = if y1 * y1 > x { y1 - 1 } else { y1 };
    root >> (shift >> 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_is_exact_at_every_square_and_its_neighbours() {
        assert_eq!(isqrt_u32(0), 0);
        assert_eq!(isqrt_u32(u32::MAX), 0xFFFF);
        for k in 1..=0xFFFFu32 {
            let square = k * k;
            assert_eq!(isqrt_u32(square), k, "√{square}");
            assert_eq!(isqrt_u32(square - 1), k - 1, "√({square} − 1)");
            assert_eq!(isqrt_u32(square + 1), (square + 1).isqrt());
        }
    }

    #[test]
    fn isqrt_agrees_with_the_standard_library_on_a_sweep() {
        // An odd stride across the whole range, 2 million values.
        for n in (0..=u32::MAX).step_by(2_147) {
            assert_eq!(isqrt_u32(n), n.isqrt(), "√{n}");
        }
    }

    #[test]
    #[ignore = "every u32: minutes in debug, run with --release"]
    fn isqrt_is_exact_for_every_u32() {
        for n in 0..=u32::MAX {
            assert_eq!(isqrt_u32(n), n.isqrt(), "√{n}");
        }
    }
}
