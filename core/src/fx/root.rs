//! Exact integer square roots from a first guess in a table and Newton
//! steps: [`isqrt_u32`] for the relaxation's squared distances (thesis
//! Sec. 3.2.1.1; one division where `u32::isqrt` takes two, each a library
//! call on a Cortex-M0) and [`isqrt_u64`] / [`rounded_isqrt_u64`] for
//! fixed-point lengths and square roots (the shrinkwrap's field, the
//! turtle).

/// Newton's starting point for `x` in `[2^30, 2^32)`, indexed by its top
/// byte `b` (no index needs a bounds check; entries below 64 are never
/// read): `(⌊√(b·2^24 + 2^23)⌋ − 2^15) >> 7`, so the guess
/// `2^15 + 128·entry + 64` is within 192 of `√x`.
const GUESS: [u8; 256] = {
    let mut table = [0u8; 256];
    let mut b = 64;
    while b < table.len() {
        let middle = ((b as u32) << 24) | (1 << 23);
        // ⌊√middle⌋ ∈ [2^15, 2^16), so the entry is below 256.
        table[b] = ((middle.isqrt() - (1 << 15)) >> 7) as u8;
        b += 1;
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
    // x ≥ 2^30: the top byte is in [64, 256).
    let entry = u32::from(GUESS[(x >> 24) as u8 as usize]);
    // y0 ∈ [2^15, 2^16): x / y0 < 2^17, so the sum cannot overflow.
    let y0 = (1 << 15) + (entry << 7) + 64;
    // Newton from |y0 − √x| ≤ 192 lands in [⌊√x⌋, ⌊√x⌋ + 1]: the step's
    // error (y0 − √x)²/(2·y0) is below 1, and the floors keep it at or above
    // ⌊√x⌋ (the tests check every square and its neighbours).
    let y1 = (y0 + x / y0) >> 1; // < 2^17: its square fits in u64
    let root = if u64::from(y1) * u64::from(y1) > u64::from(x) {
        y1 - 1
    } else {
        y1
    };
    root >> (shift >> 1)
}

/// √n at the knots n = k·2⁵⁶ (k = 0‥256), less 2³¹: round(√k·2²⁸) − 2³¹
/// for k ≥ 64 (0‥2³¹), 0 below (never read). 1 KB, computed by the
/// compiler, only on 64-bit targets; indexed by the top byte, so that no
/// index needs a bounds check.
const ROOT_KNOTS: [u32; 257] = {
    let mut table = [0u32; 257];
    let mut k = 64;
    while k <= 256 {
        // round(√y) = ⌈⌊√(4y)⌋ / 2⌉ with y = k·2⁵⁶.
        let four_y = (k as u128) << 58;
        table[k] = (four_y.isqrt().div_ceil(2) - (1 << 31)) as u32;
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

/// ⌊√x + ½⌋, exactly (√x is never an integer and a half): the root of
/// [`isqrt_u64`] rounded to nearest, on 64-bit targets with one square
/// for both the floor's correction and the rounding.
#[must_use]
pub(crate) fn rounded_isqrt_u64(x: u64) -> u64 {
    if cfg!(target_pointer_width = "64") {
        if x == 0 {
            return 0;
        }
        // y ∈ {⌊√x⌋, ⌊√x⌋ + 1} ∩ [1, 2³²): y² and y² + y fit.
        let y = newton_candidate(x).min(u64::from(u32::MAX));
        let square = y * y;
        // Below y²: ⌊√x⌋ = y − 1, rounded up when x > (y − 1)² + (y − 1)
        // = y² − y; else ⌊√x⌋ = y, rounded up when x > y² + y.
        y - 1 + u64::from(x > square - y) + u64::from(x > square + y)
    } else {
        let r = x.isqrt();
        // r² ≤ x: no underflow. Round up when the rest exceeds r, i.e.
        // x ≥ (r + ½)².
        if x - r * r > r { r + 1 } else { r }
    }
}

/// [`rounded_isqrt_u64`] for 1 ≤ x < 2⁶² (the caller's range proof), without
/// its guards for 0 and for roots of 2³² (on 64-bit targets; elsewhere
/// the same function). Wrapping arithmetic: no panic outside the range,
/// only a wrong root.
#[must_use]
pub(crate) fn rounded_isqrt_u62(x: u64) -> u64 {
    if cfg!(target_pointer_width = "64") {
        // y ∈ {⌊√x⌋, ⌊√x⌋ + 1} ⊂ [1, 2³¹]: y² + y fits, y − 1 ≥ 0.
        let y = newton_candidate(x);
        let square = y.wrapping_mul(y);
        let below = u64::from(x > square.wrapping_sub(y));
        let above = u64::from(x > square.wrapping_add(y));
        y.wrapping_sub(1).wrapping_add(below).wrapping_add(above)
    } else {
        rounded_isqrt_u64(x)
    }
}

/// ⌊√x⌋, exactly, in a few instructions where `u64::isqrt` needs a few
/// dozen on a 64-bit machine: [`newton_candidate`] and one correction.
#[must_use]
fn newton_u64(x: u64) -> u64 {
    if x == 0 {
        return 0;
    }
    let r = newton_candidate(x);
    // r² > x implies r ≥ 1: no underflow.
    if r.checked_mul(r).is_none_or(|square| square > x) {
        r - 1
    } else {
        r
    }
}

/// ⌊√x⌋ or ⌊√x⌋ + 1, for x > 0, in one division: x is scaled by 4ʲ into
/// n ∈ [2⁶², 2⁶⁴), √n is interpolated between the [`ROOT_KNOTS`] either
/// side to within 2¹⁴ + 300 (the chord of a concave root lies below it by
/// at most h²·|f″|/8 = 2²⁸/(32·64^{3/2}) = 2¹⁴ at k = 64; the table, the
/// 16-bit fraction and the floors add under 300), one Newton step takes
/// the error to at most (2¹⁴ + 300)²/(2·(2³¹ − 2¹⁵)) < 0.07 above √n
/// (never below ⌊√n⌋ with floors), and scaling back keeps
/// {⌊√n⌋, ⌊√n⌋ + 1} within {⌊√x⌋, ⌊√x⌋ + 1}.
fn newton_candidate(x: u64) -> u64 {
    // Even, so that √ scales back by a shift; x << shift has one of its
    // top two bits set.
    let shift = x.leading_zeros() & !1;
    let n = x << shift;
    // n ≥ 2⁶², so the top byte k is 64‥255; k + 1 ≤ 256.
    let k = (n >> 56) as usize;
    let (low, high) = (ROOT_KNOTS[k], ROOT_KNOTS[k + 1]);
    // high − low < 2²⁴ (the root's slope), the fraction < 2¹⁶.
    let fraction = (n >> 40) & 0xFFFF;
    let rise = (u64::from(high.wrapping_sub(low)) * fraction) >> 16;
    // estimate ∈ [2³¹ − 2¹⁵, 2³²]: n / estimate < 2³³, the sum < 2³⁴.
    let estimate = (1 << 31) + u64::from(low) + rise;
    let y = (estimate + n / estimate.max(1)) / 2;
    y >> (shift / 2)
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

    /// Where `newton_candidate` is worst: in the middle of every interval
    /// between two knots (and a quarter either side), at every scale.
    fn interval_middles() -> impl Iterator<Item = u64> {
        (64..256u64).flat_map(|k| {
            (0..=56).flat_map(move |shift| {
                [1, 2, 3].map(|quarter| ((k << 56) + (quarter << 54)) >> shift)
            })
        })
    }

    /// `newton_u64` is `u64::isqrt` at every knot of the table and between
    /// knots, at squares and their neighbours over the whole range, and at
    /// random.
    #[test]
    fn newton_u64_is_isqrt() {
        let check = |x: u64| assert_eq!(newton_u64(x), x.isqrt(), "{x}");
        interval_middles().for_each(check);
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

    /// `rounded_isqrt_u62` is `rounded_isqrt_u64` over its range.
    #[test]
    fn rounded_isqrt_u62_is_rounded_isqrt_u64_below_2_62() {
        let check = |x: u64| assert_eq!(rounded_isqrt_u62(x), rounded_isqrt_u64(x), "{x}");
        for x in 1..1 << 16 {
            check(x);
        }
        interval_middles().filter(|&x| x >> 62 == 0).for_each(check);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = (state >> 2) >> (state % 62);
            let r = x.isqrt();
            for y in [x, r * r, r * r + r, r * r + r + 1] {
                if y > 0 {
                    check(y);
                }
            }
        }
        check((1 << 62) - 1);
    }

    /// `rounded_isqrt_u64` is ⌈⌊√(4x)⌋ / 2⌉ (round half up, in 128 bits) on
    /// the same values as `newton_u64_is_isqrt`, and on the neighbours of
    /// the half-way points (r + ½)².
    #[test]
    fn rounded_isqrt_u64_rounds_to_nearest() {
        let check = |x: u64| {
            let reference = ((u128::from(x) << 2).isqrt().div_ceil(2)) as u64;
            assert_eq!(rounded_isqrt_u64(x), reference, "{x}");
        };
        for x in 0..1 << 16 {
            check(x);
        }
        interval_middles().for_each(check);
        for k in 64..=256u64 {
            for shift in 0..=56 {
                let edge = (k << 56) >> shift;
                for x in [edge.wrapping_sub(1), edge, edge.wrapping_add(1)] {
                    check(x);
                }
            }
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = state >> (state % 64);
            // r² + r and r² + r + 1 straddle (r + ½)².
            let r = x.isqrt().min(u64::from(u32::MAX) - 1);
            for y in [x, r * r, (r * r).wrapping_sub(1), r * r + r, r * r + r + 1] {
                check(y);
            }
        }
        check(u64::MAX);
        check(u64::from(u32::MAX) * u64::from(u32::MAX));
    }
}
