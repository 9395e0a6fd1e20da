//! The force law of the relaxation (thesis Sec. 3.2.1.1, docs/mosaics.md),
//! the same on the plane (D = 2) and on a mesh (D = 3): every neighbour q
//! of p within the repulsion radius r pushes p by
//! (1 − d/r)·ρ_pq·r·(p − q)/d = ρ_pq·(r − d)·(p − q)/d; the sum Σ is
//! blended by w_a with its part along the anisotropy field v and scaled by
//! w_d, Δp = w_d·((1 − w_a)·Σ + w_a·(Σ·v)·v), held within ±r. The pair's
//! repulsion ρ_pq comes from the adhesion (1 − α_pq in the thesis; 1 for
//! like pairs during the initial relaxation). Cells move more easily along
//! v, so clones stretch along it, and a cell at rest stays at rest (the
//! thesis's sum with v itself, Sec. 3.2.4, moves every cell by w_a·v each
//! step: a drift that packs the clones the field points to; the original
//! MClone code scales the force per component instead). With momentum β
//! (heavy-ball relaxation) a cell also moves β times its last move, the
//! sum held within ±r. Integer sums: the same bits in any order and on
//! every machine.

use crate::fx::root::{isqrt_u32, isqrt_u64};

/// Q16 one.
pub(super) const ONE: i64 = 1 << 16;

/// Q16 one half, for rounding.
const HALF: i64 = ONE >> 1;

/// (r − d)/d as Q16 for a pair at squared distance `d2` (Q32), with
/// 0 < d2 < r².
#[inline(always)]
pub(super) fn ratio(d2: i64, r: i64) -> i64 {
    // Q16, 1 ≤ d < r (the max only tells the compiler: no division by
    // zero below); the 32-bit root is much cheaper when it fits.
    let d = match u32::try_from(d2) {
        Ok(d2) => i64::from(isqrt_u32(d2)),
        Err(_) => isqrt_u64(d2 as u64) as i64,
    }
    .max(1);
    // (r − d)/d as Q16: (r − d) < 2^30, so the shift fits in i64. A
    // 64-bit division is one instruction on a 64-bit machine, where
    // ⌊(r − d)·2^16/d⌋ = ⌊r·2^16/d⌋ − 2^16 (0 < d < r) spares the
    // subtraction and shift per pair (r·2^16 is the same for every
    // pair); elsewhere (a library call on a Cortex-M) 32 bits when the
    // numerator fits, as it does for r below 1.0.
    if cfg!(target_pointer_width = "64") {
        ((r << 16) / d) - ONE // d ≥ 1: no overflow
    } else {
        let n = (r - d) << 16;
        match u32::try_from(n) {
            // d < r < 2^30 is d as u32, at least 1: no division by zero
            // to check (nor its panic's place in flash).
            Ok(n) => i64::from(n / (d as u32).max(1)),
            Err(_) => n / d,
        }
    }
}

/// The sign of the push between coincident cells `i` and `j` (a child on
/// its parent): apart along the first axis, the lower index towards −.
#[inline(always)]
fn coincident(i: usize, j: usize) -> i64 {
    if i < j { -1 } else { 1 }
}

/// The push (Q32, the product of the Q16 repulsion `repel` and a Q16
/// displacement) on cell `i` of cell `j` displaced by `d` (Q16, p − q)
/// from it, at squared distance `d2` < r² (Q32): ρ·(r − d)·(p − q)/d.
#[inline(always)]
pub(super) fn push<const D: usize>(
    i: usize,
    j: usize,
    d: [i64; D],
    d2: i64,
    r: i64,
    repel: i64,
) -> [i64; D] {
    let mut f = [0; D];
    if d2 == 0 {
        if let Some(f) = f.first_mut() {
            *f = coincident(i, j) * repel * r;
        }
        return f;
    }
    let k = ratio(d2, r);
    // |k·d| ≤ (r − d)·2^16·(1 + 1/d) < 2^47 since |d_c| ≤ d.
    for (f, d) in f.iter_mut().zip(&d) {
        *f = ((k * d) >> 16) * repel;
    }
    f
}

/// The pushes of a pair on each other, exactly [`push`] from both sides:
/// on cell `i` by `j` displaced by `d` from it (with the repulsion
/// `repel[0]`), and on `j` by `i` (`repel[1]`), one root and one division
/// for both. The floor of `k·(−d)/2^16` is taken from `−k·d` itself, not
/// as the negated floor of `k·d`, so the bits are those of `j`'s own push.
#[inline(always)]
pub(super) fn pair_pushes<const D: usize>(
    i: usize,
    j: usize,
    d: [i64; D],
    d2: i64,
    r: i64,
    repel: [i32; 2],
) -> [[i64; D]; 2] {
    let (on_p, on_q) = (i64::from(repel[0]), i64::from(repel[1]));
    let mut f = [[0; D]; 2];
    let [p, q] = &mut f;
    if d2 == 0 {
        let s = coincident(i, j) * r;
        if let (Some(p), Some(q)) = (p.first_mut(), q.first_mut()) {
            (*p, *q) = (s * on_p, -s * on_q);
        }
        return f;
    }
    let k = ratio(d2, r);
    // Range as in [`push`]: |k·d| < 2^47, so −k·d fits.
    for ((p, q), d) in p.iter_mut().zip(q.iter_mut()).zip(&d) {
        let m = k * d;
        (*p, *q) = ((m >> 16) * on_p, ((-m) >> 16) * on_q);
    }
    f
}

/// The weights that turn a cell's summed pushes into its step (Q16).
#[derive(Clone, Copy, Debug)]
pub(super) struct Step {
    /// The repulsion radius r: a step stays within ±r.
    pub r: i64,
    /// w_d.
    pub push_weight: i64,
    /// w_a.
    pub anisotropy_weight: i64,
    /// β.
    pub momentum: i64,
}

impl Step {
    /// The displacement (Q16, within ±r) of a cell pushed by `sum` (Q32),
    /// with the anisotropy field `v` (Q14, |v| ≤ 1) where it is, if any:
    /// w_d·((1 − w_a)·Σ + w_a·(Σ·v)·v). Cells move more easily along v,
    /// so clones stretch along it, and a cell at rest stays at rest.
    #[inline(always)]
    pub(super) fn displacement<const D: usize>(
        &self,
        sum: [i64; D],
        v: Option<[i32; D]>,
    ) -> [i64; D] {
        let (r, wd, wa) = (self.r, self.push_weight, self.anisotropy_weight);
        let mut s = [0; D]; // Q16
        for (s, x) in s.iter_mut().zip(&sum) {
            *s = (x + HALF) >> 16;
        }
        let mut out = s;
        if let Some(v) = v {
            // (Σ·v)·v: Σ's part along the field (Q16; |v| ≤ 1 as Q14).
            let mut along = 0;
            for (s, v) in s.iter().zip(&v) {
                along += s * i64::from(*v);
            }
            let along = along >> 14;
            for (o, (s, v)) in out.iter_mut().zip(s.iter().zip(&v)) {
                let steer = (along * i64::from(*v)) >> 14;
                *o = ((ONE - wa) * s + wa * steer + HALF) >> 16;
            }
        }
        for o in &mut out {
            // max/min, not clamp: the same for r ≥ 1, and no panic path
            // (with its formatting code) for reversed bounds.
            *o = ((wd * *o + HALF) >> 16).max(-r).min(r);
        }
        out
    }

    /// The displacement `d` (within ±r) plus β times the cell's `last`
    /// move, within ±r.
    #[inline(always)]
    pub(super) fn carried<const D: usize>(&self, d: [i64; D], last: [i32; D]) -> [i64; D] {
        let (beta, r) = (self.momentum, self.r);
        let mut out = d;
        for (o, last) in out.iter_mut().zip(&last) {
            // |d| ≤ r and |β·last| < r: the sum fits easily in i64.
            let carry = (beta * i64::from(*last) + HALF) >> 16;
            *o = (*o + carry).max(-r).min(r);
        }
        out
    }
}
