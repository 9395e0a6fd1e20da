//! Relaxation (thesis Sec. 3.2.1.1, DESIGN.md "Clonal mosaic"): every
//! neighbour q of p within the repulsion radius r pushes p by
//! (1 − d/r)·ρ_pq·r·(p − q)/d = ρ_pq·(r − d)·(p − q)/d, with the pair's
//! repulsion ρ_pq from the adhesion (1 − α_pq in the thesis; 1 for like
//! pairs here, [`Params::adhesion`](super::Params::adhesion)); the sum
//! Σ is blended by w_a with its part along the anisotropy field v and
//! scaled by w_d: Δp = w_d·((1 − w_a)·Σ + w_a·(Σ·v)·v). Cells move more
//! easily along v, so clones stretch along it, and a cell at rest stays at
//! rest (the thesis's sum with v itself, Sec. 3.2.4, moves every cell by
//! w_a·v each step: a drift that packs the clones the field points to;
//! the original MClone code scales the force per component instead). With momentum β (heavy-ball
//! relaxation) a cell also moves β times its last move, the sum held
//! within ±r. All pushes are computed (a Jacobi step) before any cell
//! moves, so the order of the loops does not matter and integer sums make
//! the result exact on every machine.

use core::ops::Range;

use super::control::Field;
use super::domain::Domain;
use super::grid::Grid;
use super::params::MAX_TYPES;
use super::store::{ArrayStore, CellSlices, CellStore};
use crate::fx::root::isqrt_u32;

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
    /// The repulsion ρ of each pair of types (from the adhesion; 1 during
    /// the initial relaxation).
    pub repel: [[i32; MAX_TYPES]; MAX_TYPES],
    /// w_d.
    pub push_weight: i32,
    /// w_a.
    pub anisotropy_weight: i32,
    /// The anisotropy field v (Q14), if any.
    pub field: Option<&'a Field>,
    /// β, the share of its last move a cell moves again (Q16, below 1).
    pub momentum: i32,
}

impl Forces<'_> {
    /// The push on cell `i` of cell `j` displaced by `(dx, dy)` from it,
    /// `(1 − α)·(r − d)·(p − q)/d` as Q32 (the product of Q16 repulsion
    /// and Q16 displacement), for `d2 = dx² + dy²` below `r²`.
    #[inline(always)]
    fn push(&self, i: usize, j: usize, dx: i64, dy: i64, d2: i64, repel: i32) -> [i64; 2] {
        let r = i64::from(self.radius);
        let repel = i64::from(repel);
        if d2 == 0 {
            // Coincident cells (a child on its parent): push apart along u,
            // the lower index towards −u.
            let s = if i < j { -1 } else { 1 };
            return [s * repel * r, 0];
        }
        // Q16, 1 ≤ d < r (the max only tells the compiler: no division by
        // zero below); the 32-bit root is much cheaper when it fits.
        let d = match u32::try_from(d2) {
            Ok(d2) => i64::from(isqrt_u32(d2)),
            Err(_) => crate::fx::root::isqrt_u64(d2 as u64) as i64,
        }
        .max(1);
        // (r − d)/d as Q16: (r − d) < 2^30, so the shift fits in i64. A
        // 64-bit division is one instruction on a 64-bit machine, where
        // ⌊(r − d)·2^16/d⌋ = ⌊r·2^16/d⌋ − 2^16 (0 < d < r) spares the
        // subtraction and shift per pair (r·2^16 is the same for every
        // pair); elsewhere (a library call on a Cortex-M) 32 bits when the
        // numerator fits, as it does for r below 1.0.
        let k = if cfg!(target_pointer_width = "64") {
            ((r << 16) / d) - ONE // d ≥ 1: no overflow
        } else {
            let n = (r - d) << 16;
            match u32::try_from(n) {
                Ok(n) => i64::from(n / d as u32),
                Err(_) => n / d,
            }
        };
        // |k·dx| ≤ (r − d)·2^16·(1 + 1/d) < 2^47 since |dx| ≤ d.
        let fx = (k * dx) >> 16;
        let fy = (k * dy) >> 16;
        [fx * repel, fy * repel]
    }

    /// The push of q (index `j`) on p (index `i`), or `None` beyond the
    /// radius ([`Forces::push`]).
    #[inline(always)]
    fn pair(&self, i: usize, j: usize, p: [i32; 2], q: [i32; 2], repel: i32) -> Option<[i64; 2]> {
        let dx = i64::from(self.domain.delta(0, p[0], q[0]));
        let dy = i64::from(self.domain.delta(1, p[1], q[1]));
        let d2 = dx * dx + dy * dy; // < 2·(2^30)², Q32
        let r = i64::from(self.radius);
        (d2 < r * r).then(|| self.push(i, j, dx, dy, d2, repel))
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
        let s = sum.map(|x| (x + (ONE >> 1)) >> 16); // Q16
        // (Σ·v)·v: Σ's part along the field (Q16; |v| ≤ 1 as Q14).
        let along = (s[0] * i64::from(v[0]) + s[1] * i64::from(v[1])) >> 14;
        let mut out = [0i32; 2];
        for c in 0..2 {
            let blend = if self.field.is_some() {
                let steer = (along * i64::from(v[c])) >> 14;
                ((ONE - wa) * s[c] + wa * steer + (ONE >> 1)) >> 16
            } else {
                s[c] // w_a = 0 without a field
            };
            let delta = (wd * blend + (ONE >> 1)) >> 16;
            // max/min, not clamp: the same for r ≥ 1, and no panic path
            // (with its formatting code) for reversed bounds.
            out[c] = delta.max(-r).min(r) as i32;
        }
        out
    }
}

/// What one relaxation step reads: the old positions in grid-bin order
/// (so neighbours are read from contiguous memory), the grid and the
/// forces. Each cell's new position is a function of the snapshot alone,
/// so the cells can move in any order, or side by side on several threads
/// ([`Relax`]), with the same result.
#[derive(Debug)]
pub struct Snapshot<'s> {
    sorted: &'s [[i32; 2]],
    order: &'s [u32],
    bins: &'s [u32],
    kind: &'s [u8],
    grid: &'s Grid,
    /// [`Grid::shifts_exact`], once for every cell.
    shifted: bool,
    forces: &'s Forces<'s>,
}

impl Snapshot<'_> {
    /// Cells in the snapshot.
    #[must_use]
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Whether it holds no cell.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The index of the cell in grid slot `slot` (below [`Snapshot::len`]).
    #[must_use]
    pub fn cell(&self, slot: usize) -> usize {
        self.order[slot] as usize
    }

    /// The new position of a cell at `p` displaced by `d` by its
    /// neighbours' pushes ([`Snapshot::sweep`]).
    #[must_use]
    pub fn moved(&self, p: [i32; 2], d: [i32; 2]) -> [i32; 2] {
        let domain = self.forces.domain;
        [
            domain.confine(0, i64::from(p[0]) + i64::from(d[0])),
            domain.confine(1, i64::from(p[1]) + i64::from(d[1])),
        ]
    }

    /// With momentum ([`Forces::momentum`]), the new position of a cell at
    /// `p` displaced by `d` ([`Snapshot::sweep`]) and the move it made: `d`
    /// and β times its `last` move, within ±r.
    #[must_use]
    pub fn carried(&self, p: [i32; 2], d: [i32; 2], last: [i32; 2]) -> ([i32; 2], [i32; 2]) {
        let (domain, beta) = (self.forces.domain, i64::from(self.forces.momentum));
        let r = i64::from(self.forces.radius);
        let mut to = [0; 2];
        let mut step = [0; 2];
        for c in 0..2 {
            // |d| ≤ r and |β·last| < r: the sum fits easily in i64.
            let carry = (beta * i64::from(last[c]) + (ONE >> 1)) >> 16;
            let s = (i64::from(d[c]) + carry).max(-r).min(r);
            to[c] = domain.confine(c, i64::from(p[c]) + s);
            // The move made: less than s against a wall.
            step[c] = domain.delta(c, to[c], p[c]);
        }
        (to, step)
    }

    /// Calls `each(slot, p, d)` for the grid slots `slots` in order, with
    /// the old position p of the slot's cell and its displacement d by the
    /// pushes of its neighbours within the radius.
    pub fn sweep(&self, slots: Range<usize>, mut each: impl FnMut(usize, [i32; 2], [i32; 2])) {
        if self.shifted {
            self.sweep_cells::<true>(slots, &mut each);
        } else {
            self.sweep_cells::<false>(slots, &mut each);
        }
    }

    /// [`Snapshot::sweep`] with [`Snapshot::pushes`].
    #[inline(always)]
    fn sweep_cells<const SHIFTED: bool>(
        &self,
        slots: Range<usize>,
        each: &mut impl FnMut(usize, [i32; 2], [i32; 2]),
    ) {
        let end = slots.end.min(self.sorted.len());
        for slot in slots.start..end {
            let p = self.sorted[slot];
            let sum = self.pushes::<SHIFTED>(slot, p);
            each(slot, p, self.forces.displacement(sum, p));
        }
    }

    /// The sum of the pushes on the cell in grid slot `slot`; `SHIFTED`:
    /// displacements from the bins' shifts ([`Grid::span`]), else from
    /// [`Domain::delta`](super::domain::Domain::delta). A row's run of
    /// bins is one slice of the sorted positions ([`Snapshot::run_pushes`]).
    #[inline(always)]
    fn pushes<const SHIFTED: bool>(&self, slot: usize, p: [i32; 2]) -> [i64; 2] {
        let mut sum = [0i64; 2];
        let (grid, bins, forces) = (self.grid, self.bins, self.forces);
        let size = forces.domain.size.map(|s| s.to_bits());
        let r = forces.radius;
        let cell = self.cell(slot);
        let probe = Probe {
            cell,
            p,
            reach: r - 1,
            window: (r as u32).wrapping_mul(2).wrapping_sub(1),
            r2: i64::from(r) * i64::from(r),
            repel: &forces.repel[self.kind_of(cell)],
        };
        let (cols, nc) = grid.span::<SHIFTED>(0, p[0], r, size[0]);
        let (rows, nr) = grid.span::<SHIFTED>(1, p[1], r, size[1]);
        let stride = grid.cols as usize;
        for cols in &cols[..nc.min(2)] {
            // i32: p ∈ [0, size), size ≤ 2^30 and |shift| ≤ size.
            let edge_u = (p[0] - cols.shift).wrapping_sub(probe.reach) as u32;
            // Range proof: a run never ends before its first bin ([`Grid::span`]).
            let width = (cols.end - cols.first) as usize;
            for rows in &rows[..nr.min(2)] {
                let edge = [edge_u, (p[1] - rows.shift).wrapping_sub(probe.reach) as u32];
                // The row's first bin of the run: below bins.len() ≤ 2^30 while
                // the row is in the grid, so neither it nor + width overflows.
                let mut first = rows.first as usize * stride + cols.first as usize;
                for _ in rows.first..rows.end {
                    let (Some(&start), Some(&end)) = (bins.get(first), bins.get(first + width))
                    else {
                        break;
                    };
                    sum =
                        self.run_pushes::<SHIFTED>(&probe, edge, start as usize..end as usize, sum);
                    first += stride;
                }
            }
        }
        sum
    }

    /// `sum` plus the pushes on the probed cell of the cells in the slots
    /// `run` within the radius. Most of them lie beyond it and cost a
    /// comparison or two: |d| < r ⇔ r − 1 − d ∈ [0, 2r − 1), one unsigned
    /// comparison, exact in wrapping u32 as r − 1 − d stays within ±2^31.
    /// With shifts, r − 1 − d = q − `edge` where `edge` is the cell's
    /// position less the run's shifts and r − 1: no subtraction first.
    #[inline(always)]
    fn run_pushes<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        run: core::ops::Range<usize>,
        mut sum: [i64; 2],
    ) -> [i64; 2] {
        let domain = self.forces.domain;
        // r − 1 − d.
        let offset = |axis: usize, q: i32| {
            if SHIFTED {
                (q as u32).wrapping_sub(edge[axis])
            } else {
                probe
                    .reach
                    .wrapping_sub(domain.delta(axis, probe.p[axis], q)) as u32
            }
        };
        let (Some(cells), Some(order)) = (self.sorted.get(run.clone()), self.order.get(run)) else {
            return sum;
        };
        for (q, &j) in cells.iter().zip(order) {
            // |dx| ≥ r: beyond the radius whatever dy is.
            let ox = offset(0, q[0]);
            if ox >= probe.window {
                continue;
            }
            let oy = offset(1, q[1]);
            if oy >= probe.window {
                continue;
            }
            // |d| < r: the offsets are below 2r − 1 < 2^31.
            let dx = i64::from(probe.reach - ox as i32);
            let dy = i64::from(probe.reach - oy as i32);
            let d2 = dx * dx + dy * dy; // < 2·r² ≤ 2^61, Q32
            if d2 >= probe.r2 {
                continue;
            }
            let j = j as usize;
            if d2 == 0 && j == probe.cell {
                continue; // the cell itself
            }
            let repel = probe.repel[self.kind_of(j)];
            let f = self.forces.push(probe.cell, j, dx, dy, d2, repel);
            sum = [sum[0] + f[0], sum[1] + f[1]];
        }
        sum
    }

    /// The type of cell `i`, as an index into the repulsion table.
    #[inline(always)]
    fn kind_of(&self, i: usize) -> usize {
        self.kind.get(i).map_or(0, |&k| k as usize % MAX_TYPES)
    }
}

/// The cell whose pushes [`Snapshot::run_pushes`] sums up, and what each
/// candidate neighbour is compared with, computed once per cell.
#[derive(Debug)]
struct Probe<'f> {
    /// The cell's index.
    cell: usize,
    /// Its position.
    p: [i32; 2],
    /// r − 1.
    reach: i32,
    /// 2r − 1 (wrapping u32).
    window: u32,
    /// r² (Q32).
    r2: i64,
    /// The repulsion between its type and each other.
    repel: &'f [i32; MAX_TYPES],
}

/// Where a relaxation step writes: the positions, which the
/// [`Snapshot`] no longer reads (writing a new position there keeps the
/// step a Jacobi step), and the cells' last moves (empty in a store
/// without momentum).
#[derive(Debug)]
pub struct Moves<'s> {
    /// Positions by cell index.
    pub pos: &'s mut [[i32; 2]],
    /// Last moves by cell index.
    pub velocity: &'s mut [[i32; 2]],
}

/// Takes the snapshot of one relaxation step over the first `n` cells with
/// the grid `grid` (already planned for `forces.radius`): builds the grid
/// and gathers the positions in bin order into the push scratch. Returns it
/// with what the step writes.
pub fn snapshot<'s>(
    cells: &'s mut CellSlices<'_>,
    n: usize,
    grid: &'s Grid,
    forces: &'s Forces<'s>,
) -> (Snapshot<'s>, Moves<'s>) {
    grid.build(
        &cells.pos[..n],
        &mut cells.order[..n],
        cells.bins,
        &mut cells.push[..n],
    );
    let order = &cells.order[..n];
    let snapshot = Snapshot {
        sorted: &cells.push[..n],
        order,
        bins: &cells.bins[..=grid.bins()],
        kind: &cells.kind[..n],
        grid,
        shifted: grid.shifts_exact(),
        forces,
    };
    let velocity = match cells.velocity.get_mut(..n) {
        Some(v) => v,
        None => &mut [],
    };
    let moves = Moves {
        pos: &mut cells.pos[..n],
        velocity,
    };
    (snapshot, moves)
}

/// One relaxation step over the first `n` cells, one cell after another.
pub fn relax(cells: &mut CellSlices<'_>, n: usize, grid: &Grid, forces: &Forces<'_>) {
    let (snapshot, moves) = snapshot(cells, n, grid, forces);
    // One closure for both cases: one copy of the sweep on an MCU.
    snapshot.sweep(0..snapshot.len(), |slot, p, d| {
        let i = snapshot.cell(slot);
        if forces.momentum == 0 {
            moves.pos[i] = snapshot.moved(p, d);
            return;
        }
        let last = moves.velocity.get(i).copied().unwrap_or([0; 2]);
        let (to, step) = snapshot.carried(p, d, last);
        moves.pos[i] = to;
        if let Some(v) = moves.velocity.get_mut(i) {
            *v = step;
        }
    });
}

/// How a cell store runs a relaxation step: one cell after another (the
/// default, [`relax`]), or, on a computer, side by side on several threads
/// through the [`Snapshot`], with the same result.
pub trait Relax: CellStore {
    /// One relaxation step over the first `n` cells with the grid `grid`
    /// (already planned for `forces.radius`).
    fn relax(&mut self, n: usize, grid: &Grid, forces: &Forces<'_>) {
        relax(&mut self.slices(), n, grid, forces);
    }
}

impl<const N: usize, const G: usize> Relax for ArrayStore<N, G> {}

/// The same step by brute force, O(N²), without momentum: the reference
/// for tests and the bench. Integer sums are exact, so it gives
/// bit-identical positions.
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
