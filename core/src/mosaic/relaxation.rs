//! Relaxation on the plane (thesis Sec. 3.2.1.1, docs/mosaics.md): the
//! pushes of the force law ([`super::force`]) of every neighbour within
//! the repulsion radius r, found by the neighbour scan that the plane
//! shares with a mesh ([`super::scan`]) in a grid of bins at least r wide
//! ([`Grid`]) on the periodic or walled domain, summed into each cell's
//! step, taken along the anisotropy field and confined to the domain.

use core::ops::Range;

use super::control::Field;
use super::domain::Domain;
use super::force::{self, Step};
use super::grid::Grid;
use super::ground::{CellSlices, Ground};
use super::params::MAX_TYPES;
use super::scan::{Bins, Probe, Scan};

/// The constants of one relaxation step (all fixed point, Q16 unless
/// noted).
#[derive(Clone, Copy, Debug)]
pub struct Forces<'a> {
    /// The domain (for periodic distances and walls).
    pub domain: &'a Domain,
    /// The grid of bins, planned for `radius` ([`Grid::plan`]).
    pub grid: &'a Grid,
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
    /// The weights of a cell's step ([`force::Step`]).
    #[inline(always)]
    fn step(&self) -> Step {
        Step {
            r: i64::from(self.radius),
            push_weight: i64::from(self.push_weight),
            anisotropy_weight: i64::from(self.anisotropy_weight),
            momentum: i64::from(self.momentum),
        }
    }

    /// The push of q (index `j`) on p (index `i`), or `None` beyond the
    /// radius ([`force::push`]).
    #[inline(always)]
    fn pair(&self, i: usize, j: usize, p: [i32; 2], q: [i32; 2], repel: i32) -> Option<[i64; 2]> {
        let dx = i64::from(self.domain.delta(0, p[0], q[0]));
        let dy = i64::from(self.domain.delta(1, p[1], q[1]));
        let d2 = dx * dx + dy * dy; // < 2·(2^30)², Q32
        let r = i64::from(self.radius);
        (d2 < r * r).then(|| force::push(i, j, [dx, dy], d2, r, i64::from(repel)))
    }

    /// Turns the sum of pair pushes (Q32) at position `p` into the cell's
    /// displacement (Q16), held within ±r ([`Step::displacement`], with
    /// the field at `p`).
    #[inline]
    fn displacement(&self, sum: [i64; 2], p: [i32; 2]) -> [i32; 2] {
        let v = self.field.map(|f| {
            let v = f.at(self.domain, p);
            [i32::from(v[0]), i32::from(v[1])]
        });
        let d = self.step().displacement(sum, v);
        [d[0] as i32, d[1] as i32] // within ±r < 2^31
    }
}

/// What one relaxation step reads: the old positions in grid-bin order
/// (so neighbours are read from contiguous memory), the grid and the
/// forces. Each cell's new position is a function of the snapshot alone,
/// so the cells can move in any order, or side by side on several threads
/// ([`Relax`](super::store::Relax)), with the same result.
#[derive(Debug)]
pub struct Snapshot<'s> {
    scan: Scan<'s, 2>,
    bins: PlaneBins<'s>,
    /// [`Grid::shifts_exact`], once for every cell.
    shifted: bool,
    forces: &'s Forces<'s>,
}

impl Snapshot<'_> {
    /// Cells in the snapshot.
    #[must_use]
    pub fn len(&self) -> usize {
        self.scan.order.len()
    }

    /// Whether it holds no cell.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.scan.order.is_empty()
    }

    /// The index of the cell in grid slot `slot` (below [`Snapshot::len`]).
    #[must_use]
    pub fn cell(&self, slot: usize) -> usize {
        self.scan.order[slot] as usize
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
        self.carry(p, d, last)
    }

    /// [`Snapshot::carried`], inlined where the cells move in slot order
    /// ([`Snapshot::move_slots`]); out of line in the per-cell loops,
    /// which it would slow by 4 % (the croton bench).
    #[inline(always)]
    fn carry(&self, p: [i32; 2], d: [i32; 2], last: [i32; 2]) -> ([i32; 2], [i32; 2]) {
        let domain = self.forces.domain;
        let s = (self.forces.step()).carried([i64::from(d[0]), i64::from(d[1])], last);
        let mut to = [0; 2];
        let mut step = [0; 2];
        for c in 0..2 {
            to[c] = domain.confine(c, i64::from(p[c]) + s[c]);
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
            self.sweep_cells(&Shifted::<true>(&self.bins), slots, &mut each);
        } else {
            self.sweep_cells(&Shifted::<false>(&self.bins), slots, &mut each);
        }
    }

    /// [`Snapshot::sweep`] through `bins`.
    #[inline(always)]
    fn sweep_cells<B: Bins<2>>(
        &self,
        bins: &B,
        slots: Range<usize>,
        each: &mut impl FnMut(usize, [i32; 2], [i32; 2]),
    ) {
        let end = slots.end.min(self.scan.sorted.len());
        for slot in slots.start..end {
            let (p, d) = self.displaced(slot, self.scan.pushes(bins, slot));
            each(slot, p, d);
        }
    }

    /// The old position of the cell in grid slot `slot` (below
    /// [`Snapshot::len`]) and its displacement by the pushes `sum` (Q32)
    /// of its neighbours ([`Snapshot::pair_sums`]).
    #[must_use]
    pub fn displaced(&self, slot: usize, sum: [i64; 2]) -> ([i32; 2], [i32; 2]) {
        let p = self.scan.sorted[slot];
        (p, self.forces.displacement(sum, p))
    }

    /// Moves the cells of the grid slots from `first` on, as many as `to`
    /// holds, in slot order: each by the sum of its neighbours' pushes
    /// (`sums`, [`Snapshot::pair_sums`]) into `to` and, with momentum, by
    /// its last move (`last`) too, the move it made into `made` (`last`
    /// and `made` empty: none). A computer that keeps its cells in grid
    /// order moves them so, a share of the slots per thread.
    pub fn move_slots(
        &self,
        first: usize,
        sums: &[[i64; 2]],
        last: &[[i32; 2]],
        to: &mut [[i32; 2]],
        made: &mut [[i32; 2]],
    ) {
        let momentum = self.forces.momentum != 0 && !last.is_empty();
        for (k, (sum, p)) in sums.iter().zip(to.iter_mut()).enumerate() {
            let (from, d) = self.displaced(first + k, *sum);
            match (last.get(k), made.get_mut(k)) {
                (Some(&last), Some(made)) if momentum => (*p, *made) = self.carry(from, d, last),
                _ => *p = self.moved(from, d),
            }
        }
    }

    /// Adds to `sums` the pushes (Q32) of every pair of cells within the
    /// radius whose lower slot is in `slots`, on both of its cells, each
    /// pair once; a push on a later slot past the end of `sums` goes to
    /// `beyond(slot, push)`, so that threads can each take a share of the
    /// slots with its own part of the sums (only pairs across a share's
    /// end, a few rows of cells, go beyond). Over all slots, the sums of
    /// [`Snapshot::sweep`] with half its roots and candidates.
    pub fn pair_sums(
        &self,
        slots: Range<usize>,
        sums: &mut [[i64; 2]],
        beyond: &mut impl FnMut(usize, [i64; 2]),
    ) {
        if self.shifted {
            self.scan
                .pair_sums(&Shifted::<true>(&self.bins), slots, sums, beyond);
        } else {
            self.scan
                .pair_sums(&Shifted::<false>(&self.bins), slots, sums, beyond);
        }
    }
}

/// The plane's bins for the scan: the grid's runs of bins within the
/// radius, across the wrap of a periodic domain.
#[derive(Clone, Copy, Debug)]
struct PlaneBins<'s> {
    grid: &'s Grid,
    /// Each bin's first slot (and one past the last).
    bins: &'s [u32],
    domain: &'s Domain,
    radius: i32,
}

/// [`PlaneBins`] as the scan reads them; `SHIFTED`: the runs' shifts give
/// each candidate's displacement ([`Grid::shifts_exact`]), else
/// [`Domain::delta`] does.
#[derive(Debug)]
struct Shifted<'b, const SHIFTED: bool>(&'b PlaneBins<'b>);

impl<const SHIFTED: bool> Bins<2> for Shifted<'_, SHIFTED> {
    /// Each row of the bins within the radius is one run of slots (a
    /// row's run of bins is one slice of the sorted positions).
    #[inline(always)]
    fn runs<A>(
        &self,
        probe: &Probe<'_, 2>,
        init: A,
        mut visit: impl FnMut(A, [u32; 2], Range<usize>) -> A,
    ) -> A {
        let mut acc = init;
        let PlaneBins {
            grid,
            bins,
            domain,
            radius: r,
        } = *self.0;
        let size = domain.size.map(|s| s.to_bits());
        let p = probe.p;
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
                    acc = visit(acc, edge, start as usize..end as usize);
                    first += stride;
                }
            }
        }
        acc
    }

    /// With shifts, r − 1 − d = q − `edge`: no subtraction first; else
    /// r − 1 − [`Domain::delta`] (exact in wrapping u32 as it stays within
    /// ±2^31).
    #[inline(always)]
    fn offsets(
        &self,
        probe: &Probe<'_, 2>,
        edge: [u32; 2],
        q: [i32; 2],
    ) -> Option<([i64; 2], i64)> {
        let offset = |axis: usize, q: i32| {
            if SHIFTED {
                (q as u32).wrapping_sub(edge[axis])
            } else {
                let d = self.0.domain.delta(axis, probe.p[axis], q);
                probe.reach.wrapping_sub(d) as u32
            }
        };
        // |dx| ≥ r: beyond the radius whatever dy is.
        let ox = offset(0, q[0]);
        if !probe.reaches(ox) {
            return None;
        }
        let oy = offset(1, q[1]);
        if !probe.reaches(oy) {
            return None;
        }
        let (dx, dy) = (probe.displacement(ox), probe.displacement(oy));
        let d2 = dx * dx + dy * dy; // < 2·r² ≤ 2^61, Q32
        (d2 < probe.r2).then_some(([dx, dy], d2))
    }
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

impl Moves<'_> {
    /// Moves the cell in grid slot `slot`, at `p`, by its displacement `d`
    /// ([`Snapshot::moved`]), or with its momentum ([`Snapshot::carried`]).
    #[inline]
    fn settle(&mut self, snapshot: &Snapshot<'_>, slot: usize, p: [i32; 2], d: [i32; 2]) {
        let Some(&i) = snapshot.scan.order.get(slot) else {
            return;
        };
        let i = i as usize;
        let Some(pos) = self.pos.get_mut(i) else {
            return;
        };
        if snapshot.forces.momentum == 0 {
            *pos = snapshot.moved(p, d);
            return;
        }
        let last = self.velocity.get(i).copied().unwrap_or([0; 2]);
        let (to, step) = snapshot.carried(p, d, last);
        *pos = to;
        if let Some(v) = self.velocity.get_mut(i) {
            *v = step;
        }
    }
}

/// Takes the snapshot of one relaxation step over the first `n` cells with
/// the forces' grid: builds the grid
/// and gathers the positions in bin order into the push scratch. Returns it
/// with what the step writes.
pub fn snapshot<'s>(
    cells: &'s mut CellSlices<'_, Plane>,
    n: usize,
    forces: &'s Forces<'s>,
) -> (Snapshot<'s>, Moves<'s>) {
    forces.grid.build(
        &cells.pos[..n],
        &mut cells.order[..n],
        cells.bins,
        &mut cells.sorted[..n],
    );
    sorted_snapshot(cells, n, forces)
}

/// [`snapshot`] of cells already sorted into the forces' grid
/// ([`Grid::build`] into `order`, `bins` and `sorted`), as a computer
/// does it on several threads.
pub fn sorted_snapshot<'s>(
    cells: &'s mut CellSlices<'_, Plane>,
    n: usize,
    forces: &'s Forces<'s>,
) -> (Snapshot<'s>, Moves<'s>) {
    let (order, grid) = (&cells.order[..n], forces.grid);
    let snapshot = Snapshot {
        scan: Scan {
            sorted: &cells.sorted[..n],
            order,
            kind: &cells.kind[..n],
            repel: &forces.repel,
            radius: forces.radius,
        },
        bins: PlaneBins {
            grid,
            bins: &cells.bins[..=grid.bins()],
            domain: forces.domain,
            radius: forces.radius,
        },
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
pub fn relax(cells: &mut CellSlices<'_, Plane>, n: usize, forces: &Forces<'_>) {
    let (snapshot, mut moves) = snapshot(cells, n, forces);
    // One closure for both cases: one copy of the sweep on an MCU.
    snapshot.sweep(0..snapshot.len(), |slot, p, d| {
        moves.settle(&snapshot, slot, p, d);
    });
}

/// One relaxation step over the first `n` cells, each pair of neighbours
/// found once ([`Snapshot::pair_sums`]) with the pushes summed in `sums`
/// (one per cell: 16 B a cell, which a computer has and an MCU's store
/// does not; fewer than `n`: as [`relax`]). The same positions as
/// [`relax`] with half its roots and candidates (666 instructions a cell
/// for its 807 on the croton bench).
pub fn relax_pairs(
    cells: &mut CellSlices<'_, Plane>,
    n: usize,
    forces: &Forces<'_>,
    sums: &mut [[i64; 2]],
) {
    let Some(sums) = sums.get_mut(..n) else {
        relax(cells, n, forces);
        return;
    };
    let (snapshot, mut moves) = snapshot(cells, n, forces);
    sums.fill([0; 2]);
    // Every later slot's sum is in `sums`: nothing goes beyond.
    snapshot.pair_sums(0..n, sums, &mut |_, _| {});
    for (slot, sum) in sums.iter().enumerate() {
        let (p, d) = snapshot.displaced(slot, *sum);
        moves.settle(&snapshot, slot, p, d);
    }
}

/// The plane, or a cylinder's side, or a torus: the [`Domain`] of
/// [`Params`](super::Params), its cells points (u, v) found through a
/// grid of bins ([`Grid`]).
#[derive(Clone, Copy, Debug)]
pub struct Plane;

impl Ground for Plane {
    type At = [i32; 2];
    type Point = [i32; 2];
    type Forces<'f> = Forces<'f>;
    const NO_PLACE: [i32; 2] = [0; 2];
    const ZERO: [i32; 2] = [0; 2];
    const NAME: &'static str = "Plane";

    fn relax_step(cells: &mut CellSlices<'_, Plane>, n: usize, forces: &Forces<'_>) {
        relax(cells, n, forces);
    }
}

/// The same step by brute force, O(N²), without momentum: the reference
/// for tests and the bench. Integer sums are exact, so it gives
/// bit-identical positions.
pub fn relax_naive(cells: &mut CellSlices<'_, Plane>, n: usize, forces: &Forces<'_>) {
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
        cells.sorted[i] = forces.displacement(sum, pos[i]);
    }
    apply(cells, n, forces.domain);
}

fn apply(cells: &mut CellSlices<'_, Plane>, n: usize, domain: &Domain) {
    for (p, d) in cells.pos[..n].iter_mut().zip(&cells.sorted[..n]) {
        for c in 0..2 {
            p[c] = domain.confine(c, i64::from(p[c]) + i64::from(d[c]));
        }
    }
}
