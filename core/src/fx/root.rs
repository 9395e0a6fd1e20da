//! Exact integer square roots from a first guess in a table and Newton
//! steps: [`isqrt_u32`] for the relaxation's squared distances (thesis
//! Sec. 3.2.1.1; one division where `u32::isqrt` takes two, each a library
//! call on a Cortex-M0) and [`isqrt_u64`] for fixed-point lengths and
//! square roots (the shrinkwrap's field, the turtle; issue 15).

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

/// ⌊√n⌋, exactly. Not inlined on 32-bit targets: one copy in flash for
/// both relaxation loops.
#[cfg_attr(target_pointer_width = "64", inline)]
#[cfg_attr(not(target_pointer_width = "64"), inline(never))]
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

/// First estimates of √n for n = k·2⁵⁶ + f (k = 64‥255, f < 2⁵⁶): round(√(k + ½)·2¹²)
/// (192 × 2 B = 384 B, computed by the compiler), within 0.4 % of √n / 2¹⁶.
const ROOT_ESTIMATES: [u16; 192] = {
    let mut table = [0u16; 192];
    let mut k = 0;
    while k < 192 {
        // round(√y) = ⌈⌊√(4y)⌋ / 2⌉ with y = (k + 64 + ½)·2²⁴.
        let four_y = (2 * (k as u64 + 64) + 1) << 25;
        table[k] = four_y.isqrt().div_ceil(2) as u16;
        k += 1;
    }
    table
};

/// ⌊√x⌋, exactly: by [`newton_u64`] where a 64-bit division is an
/// instruction, and by the standard library's bit-by-bit root on 32-bit
/// targets, where each of Newton's divisions would be a library call of
/// ~100 cycles (the Cortex-M firmware ran its bodies 60 % slower with
/// them). Both give the same bits.
#[must_use]
pub(crate) fn isqrt_u64(x: u64) -> u64 {
    if cfg!(target_pointer_width = "64") {
        newton_u64(x)
    } else {
        x.isqrt()
    }
}

/// ⌊√x⌋, exactly, in a few instructions where `u64::isqrt` needs a few
/// dozen on a 64-bit machine: x is scaled by 4ʲ into [2⁶², 2⁶⁴), √ of that
/// is estimated from [`ROOT_ESTIMATES`] to ε ≤ 0.004, two Newton steps
/// take the error to ε²/2 ≈ 8·10⁻⁶ and then below 0.2 (of a result
/// < 2³²), and one correction after scaling back gives the floor.
#[must_use]
fn newton_u64(x: u64) -> u64 {
    if x == 0 {
        return 0;
    }
    // Even, so that √ scales back by a shift; x << shift has one of its
    // top two bits set.
    let shift = x.leading_zeros() & !1;
    let n = x << shift;
    // n ≥ 2⁶², so the top byte is 64‥255.
    let estimate = ROOT_ESTIMATES
        .get((n >> 56) as usize - 64)
        .map_or(u64::from(u32::MAX), |&e| u64::from(e) << 16);
    // Newton steps from any y > 0 stay ≥ ⌊√n⌋ and, from y ≥ 2³¹, below
    // 2³³ + 2³², so the sums cannot overflow (n / y ≤ 2³³).
    let y = (estimate + n / estimate) / 2;
    // y ≥ 2³¹; `max` spares the division its zero check.
    let y = (y + n / y.max(1)) / 2;
    // y ∈ {⌊√n⌋, ⌊√n⌋ + 1}, so r ∈ {⌊√x⌋, ⌊√x⌋ + 1}.
    let r = y >> (shift / 2);
    // r² > x implies r ≥ 1: no underflow.
    if r.checked_mul(r).is_none_or(|square| square > x) {
        r - 1
    } else {
        r
    }
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

    /// `newton_u64` is `u64::isqrt` at every bucket edge of the table, at
    /// squares and their neighbours over the whole range, and at random.
    #[test]
    fn newton_u64_is_isqrt() {
        let check = |x: u64| assert_eq!(newton_u64(x), x.isqrt(), "{x}");
        for x in 0..1 << 16 {
            check(x);
        }
        for k in 64..=256u64 {
            for shift in 0..=56 {
                let edge = (k << 56) >> shift;
                for x in [edge.wrapping_sub(1), edge, edge.wrapping_add(1)] {
                    check(x);
                }
            }
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = state >> (state % 64);
            let r = x.isqrt();
            for y in [x, r * r, (r * r).wrapping_sub(1), r * r + 2 * r] {
                check(y);
            }
        }
        check(u64::MAX);
        check(u64::from(u32::MAX) * u64::from(u32::MAX));
    }
}
