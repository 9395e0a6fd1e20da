//! Relaxation (thesis Sec. 3.2.1.1, DESIGN.md "Clonal mosaic"): every
//! neighbour q of p within the repulsion radius r pushes p by
//! (1 − d/r)·(1 − α_pq)·r·(p − q)/d = (1 − α_pq)·(r − d)·(p − q)/d; the sum
//! Σ is scaled by w_d and blended with the anisotropy field v by w_a:
//! Δp = w_d·((1 − w_a)·Σ + w_a·r·v). All pushes are computed (a Jacobi
//! step) before any cell moves, so the order of the loops does not matter
//! and integer sums make the result exact on every machine.

use super::control::Field;
use super::domain::Domain;
use super::grid::Grid;
use super::params::MAX_TYPES;
use super::store::CellSlices;

/// Q16 one.
const ONE: i64 = 1 << 16;

/// The constants of one relaxation step (all fixed point, Q16 unless
/// noted).
#[derive(Clone, Copy, Debug)]
pub struct Forces<'a> {
    /// The domain (for periodic distances and walls).
    pub domain: &'a Domain,
    /// The repulsion radius r.
    pub radius: i32,
    /// 1 − α for each pair of types.
    pub repel: [[i32; MAX_TYPES]; MAX_TYPES],
    /// w_d.
    pub push_weight: i32,
    /// w_a.
    pub anisotropy_weight: i32,
    /// The anisotropy field v (Q14), if any.
    pub field: Option<&'a Field>,
}

impl Forces<'_> {
    /// The push of q (index `j`) on p (index `i`), `(1 − α)·(r − d)·(p − q)/d`
    /// as Q32 (the product of Q16 repulsion and Q16 displacement), or `None`
    /// beyond the radius.
    #[inline(always)]
    fn pair(&self, i: usize, j: usize, p: [i32; 2], q: [i32; 2], repel: i32) -> Option<[i64; 2]> {
        let dx = i64::from(self.domain.delta(0, p[0], q[0]));
        let dy = i64::from(self.domain.delta(1, p[1], q[1]));
        let d2 = dx * dx + dy * dy; // < 2·(2^30)², Q32
        let r = i64::from(self.radius);
        if d2 >= r * r {
            return None;
        }
        let repel = i64::from(repel);
        if d2 == 0 {
            // Coincident cells (a child on its parent): push apart along u,
            // the lower index towards −u.
            let s = if i < j { -1 } else { 1 };
            return Some([s * repel * r, 0]);
        }
        // Q16, 1 ≤ d < r; the 32-bit root is much cheaper when it fits.
        let d = if d2 <= i64::from(u32::MAX) {
            i64::from((d2 as u32).isqrt())
        } else {
            (d2 as u64).isqrt() as i64
        };
        // (r − d)/d as Q16: (r − d) < 2^30, so the shift fits in i64.
        let k = ((r - d) << 16) / d;
        // |k·dx| ≤ (r − d)·2^16·(1 + 1/d) < 2^47 since |dx| ≤ d.
        let fx = (k * dx) >> 16;
        let fy = (k * dy) >> 16;
        Some([fx * repel, fy * repel])
    }

    /// Turns the sum of pair pushes (Q32) at position `p` into the cell's
    /// displacement (Q16), held within ±r.
    #[inline]
    fn displacement(&self, sum: [i64; 2], p: [i32; 2]) -> [i32; 2] {
        let r = i64::from(self.radius);
        let wa = i64::from(self.anisotropy_weight);
        let wd = i64::from(self.push_weight);
        let v = match self.field {
            Some(f) => f.at(self.domain, p),
            None => [0, 0],
        };
        let mut out = [0i32; 2];
        for c in 0..2 {
            let s = (sum[c] + (ONE >> 1)) >> 16; // Q16
            let aniso = (r * i64::from(v[c])) >> 14; // Q16
            let blend = ((ONE - wa) * s + wa * aniso + (ONE >> 1)) >> 16;
            let delta = (wd * blend + (ONE >> 1)) >> 16;
            out[c] = delta.clamp(-r, r) as i32;
        }
        out
    }
}

/// One relaxation step over the first `n` cells with the grid `grid`
/// (already planned for `forces.radius`): builds the grid, gathers the
/// positions in bin order into the push scratch (so neighbours are read
/// from contiguous memory), computes each cell's push from those old
/// positions only, and writes its new position straight into `pos` (which
/// the loop no longer reads: still a Jacobi step).
pub fn relax(cells: &mut CellSlices<'_>, n: usize, grid: &Grid, forces: &Forces<'_>) {
    grid.build(&cells.pos[..n], &mut cells.order[..n], cells.bins);
    let order = &cells.order[..n];
    let bins = &cells.bins[..=grid.bins()];
    let sorted = &mut cells.push[..n];
    for (s, &i) in sorted.iter_mut().zip(order) {
        *s = cells.pos[i as usize];
    }
    let sorted = &cells.push[..n];
    let kind = &cells.kind[..n];
    let domain = forces.domain;
    let size = domain.size.map(|s| s.to_bits());
    let r = forces.radius;
    for (slot, (&p, &i)) in sorted.iter().zip(order).enumerate() {
        let i = i as usize;
        let repel = &forces.repel[kind[i] as usize % MAX_TYPES];
        let (cols, nc) = grid.span(0, p[0], r, size[0]);
        let (rows, nr) = grid.span(1, p[1], r, size[1]);
        let mut sum = [0i64; 2];
        for &row in &rows[..nr] {
            for &col in &cols[..nc] {
                let nb = (row * grid.cols + col) as usize;
                let (lo, hi) = (bins[nb] as usize, bins[nb + 1] as usize);
                for (t, q) in sorted[lo..hi].iter().enumerate() {
                    let t = lo + t;
                    if t == slot {
                        continue;
                    }
                    let j = order[t] as usize;
                    let rep = repel[kind[j] as usize % MAX_TYPES];
                    if let Some(f) = forces.pair(i, j, p, *q, rep) {
                        sum[0] += f[0];
                        sum[1] += f[1];
                    }
                }
            }
        }
        let d = forces.displacement(sum, p);
        cells.pos[i] = [
            domain.confine(0, i64::from(p[0]) + i64::from(d[0])),
            domain.confine(1, i64::from(p[1]) + i64::from(d[1])),
        ];
    }
}

/// The same step by brute force, O(N²): the reference for tests and the
/// bench. Integer sums are exact, so it gives bit-identical positions.
pub fn relax_naive(cells: &mut CellSlices<'_>, n: usize, forces: &Forces<'_>) {
    let pos = &cells.pos[..n];
    let kind = &cells.kind[..n];
    for i in 0..n {
        let repel = &forces.repel[kind[i] as usize % MAX_TYPES];
        let mut sum = [0i64; 2];
        for j in 0..n {
            if j == i {
                continue;
            }
            if let Some(f) = forces.pair(i, j, pos[i], pos[j], repel[kind[j] as usize % MAX_TYPES])
            {
                sum[0] += f[0];
                sum[1] += f[1];
            }
        }
        cells.push[i] = forces.displacement(sum, pos[i]);
    }
    apply(cells, n, forces.domain);
}

fn apply(cells: &mut CellSlices<'_>, n: usize, domain: &Domain) {
    for (p, d) in cells.pos[..n].iter_mut().zip(&cells.push[..n]) {
        for c in 0..2 {
            p[c] = domain.confine(c, i64::from(p[c]) + i64::from(d[c]));
        }
    }
}
