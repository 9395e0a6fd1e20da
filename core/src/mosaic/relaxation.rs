//! Relaxation on the plane (thesis Sec. 3.2.1.1, docs/mosaics.md): the
//! pushes of the force law ([`super::force`]) of every neighbour within
//! the repulsion radius r, found through a grid of bins at least r wide
//! ([`Grid`]) on the periodic or walled domain, summed into each cell's
//! step. All pushes are computed (a Jacobi step) before any cell moves, so
//! the order of the loops does not matter and integer sums make the result
//! exact on every machine.

use core::ops::Range;

use super::control::Field;
use super::domain::Domain;
use super::force::{self, Step};
use super::grid::Grid;
use super::ground::{CellSlices, Ground};
use super::params::MAX_TYPES;

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
            let (p, d) = self.displaced(slot, self.pushes::<SHIFTED>(slot));
            each(slot, p, d);
        }
    }

    /// The old position of the cell in grid slot `slot` (below
    /// [`Snapshot::len`]) and its displacement by the pushes `sum` (Q32)
    /// of its neighbours ([`Snapshot::pair_sums`]).
    #[must_use]
    pub fn displaced(&self, slot: usize, sum: [i64; 2]) -> ([i32; 2], [i32; 2]) {
        let p = self.sorted[slot];
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
    /// radius whose lower slot is in `slots`, on both of its cells
    /// (`Forces::pair_pushes`): each pair is found once, from its lower
    /// slot, so a step costs half the roots and half the candidates of
    /// [`Snapshot::sweep`]. `sums[k]` is slot `slots.start + k`'s; a push
    /// on a later slot past the end of `sums` goes to `beyond(slot, push)`
    /// instead, so that threads can each take a share of the slots with its
    /// own part of the sums (only pairs across a share's end, a few rows of
    /// cells, go beyond). Over all slots the sums are exactly those of the
    /// sweep: integer sums do not depend on their order.
    pub fn pair_sums(
        &self,
        slots: Range<usize>,
        sums: &mut [[i64; 2]],
        beyond: &mut impl FnMut(usize, [i64; 2]),
    ) {
        // All of them from the first (one thread): no share to leave.
        let whole = slots.start == 0 && sums.len() >= self.sorted.len();
        match (self.shifted, whole) {
            (true, true) => self.pair_sums_in::<true, true>(slots, sums, beyond),
            (true, false) => self.pair_sums_in::<true, false>(slots, sums, beyond),
            (false, true) => self.pair_sums_in::<false, true>(slots, sums, beyond),
            (false, false) => self.pair_sums_in::<false, false>(slots, sums, beyond),
        }
    }

    /// [`Snapshot::pair_sums`] with the displacements of `SHIFTED`
    /// ([`Snapshot::pushes`]); `WHOLE`: `sums` holds every slot's sum. Out
    /// of line, each of the four: its scan of the runs stays inlined.
    #[inline(never)]
    fn pair_sums_in<const SHIFTED: bool, const WHOLE: bool>(
        &self,
        slots: Range<usize>,
        sums: &mut [[i64; 2]],
        beyond: &mut impl FnMut(usize, [i64; 2]),
    ) {
        let base = slots.start;
        // One past the last slot whose sum is in `sums`.
        let held = base + sums.len();
        for slot in base..slots.end.min(self.sorted.len()).min(held) {
            let probe = self.probe(slot);
            let mut own = [0i64; 2];
            self.runs::<SHIFTED>(&probe, |edge, run| {
                // The slots after this one: the pairs not yet found.
                let later = run.start.max(slot + 1)..run.end;
                if later.is_empty() {
                    return;
                }
                if WHOLE {
                    // base = 0: slots index the sums.
                    if let Some(sums) = sums.get_mut(later.clone()) {
                        own = self.run_pairs::<SHIFTED>(&probe, edge, later.start, own, sums);
                    }
                    return;
                }
                if later.end > held {
                    own = self.run_across::<SHIFTED>(&probe, edge, later, own, sums, base, beyond);
                    return;
                }
                // base ≤ slot < later.start < later.end: no underflow.
                let local = later.start - base..later.end - base;
                if let Some(sums) = sums.get_mut(local) {
                    own = self.run_pairs::<SHIFTED>(&probe, edge, later.start, own, sums);
                }
            });
            let sum = &mut sums[slot - base];
            *sum = [sum[0] + own[0], sum[1] + own[1]];
        }
    }

    /// [`Snapshot::run_pairs`] for the slots `later` (base ≤ the probe's
    /// slot < `later.start`) that reach past the slots whose sums are in
    /// `sums`: those past go `beyond` (rare: out of line).
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)] // one of run_pairs', rarely called
    fn run_across<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        later: Range<usize>,
        mut own: [i64; 2],
        sums: &mut [[i64; 2]],
        base: usize,
        beyond: &mut impl FnMut(usize, [i64; 2]),
    ) -> [i64; 2] {
        // base < later.start ≤ split < later.end: no underflow.
        let split = (base + sums.len()).max(later.start);
        if let Some(sums) = sums.get_mut(later.start - base..split - base) {
            own = self.run_pairs::<SHIFTED>(probe, edge, later.start, own, sums);
        }
        let run = split..later.end;
        let cells = self.sorted.get(run.clone()).unwrap_or_default();
        let order = self.order.get(run.clone()).unwrap_or_default();
        for (k, (q, &j)) in run.zip(cells.iter().zip(order)) {
            let Some([on_p, on_q]) = self.pair::<SHIFTED>(probe, edge, *q, j) else {
                continue;
            };
            own = [own[0] + on_p[0], own[1] + on_p[1]];
            beyond(k, on_q);
        }
        own
    }

    /// The cell in grid slot `slot` (below [`Snapshot::len`]) as the
    /// neighbour search sees it.
    #[inline(always)]
    fn probe(&self, slot: usize) -> Probe<'_> {
        let r = self.forces.radius;
        let cell = self.cell(slot);
        let kind = self.kind_of(cell);
        Probe {
            cell,
            kind,
            p: self.sorted[slot],
            reach: r - 1,
            window: (r as u32).wrapping_mul(2).wrapping_sub(1),
            r2: i64::from(r) * i64::from(r),
            repel: &self.forces.repel[kind],
        }
    }

    /// The sum of the pushes on the cell in grid slot `slot`; `SHIFTED`:
    /// displacements from the bins' shifts ([`Grid::span`]), else from
    /// [`Domain::delta`](super::domain::Domain::delta).
    #[inline(always)]
    fn pushes<const SHIFTED: bool>(&self, slot: usize) -> [i64; 2] {
        let probe = self.probe(slot);
        let mut sum = [0i64; 2];
        self.runs::<SHIFTED>(&probe, |edge, run| {
            sum = self.run_pushes::<SHIFTED>(&probe, edge, run, sum);
        });
        sum
    }

    /// Calls `visit(edge, run)` for each run of grid slots that holds the
    /// cells of one row of the bins within the radius of the probed cell
    /// (a row's run of bins is one slice of the sorted positions), with
    /// `edge`, the cell's position less the run's shifts and r − 1
    /// ([`Snapshot::offsets`]).
    #[inline(always)]
    fn runs<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        mut visit: impl FnMut([u32; 2], Range<usize>),
    ) {
        let (grid, bins) = (self.grid, self.bins);
        let size = self.forces.domain.size.map(|s| s.to_bits());
        let (p, r) = (probe.p, self.forces.radius);
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
                    visit(edge, start as usize..end as usize);
                    first += stride;
                }
            }
        }
    }

    /// The displacement p − q of a cell at `q` from the probed cell, with
    /// its square (Q32), if it lies within the radius. Most candidates lie
    /// beyond it and cost a comparison or two: |d| < r ⇔ r − 1 − d ∈
    /// [0, 2r − 1), one unsigned comparison, exact in wrapping u32 as
    /// r − 1 − d stays within ±2^31. With shifts, r − 1 − d = q − `edge`
    /// ([`Snapshot::runs`]): no subtraction first.
    #[inline(always)]
    fn offsets<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        q: [i32; 2],
    ) -> Option<(i64, i64, i64)> {
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
        // |dx| ≥ r: beyond the radius whatever dy is.
        let ox = offset(0, q[0]);
        if ox >= probe.window {
            return None;
        }
        let oy = offset(1, q[1]);
        if oy >= probe.window {
            return None;
        }
        // |d| < r: the offsets are below 2r − 1 < 2^31.
        let dx = i64::from(probe.reach - ox as i32);
        let dy = i64::from(probe.reach - oy as i32);
        let d2 = dx * dx + dy * dy; // < 2·r² ≤ 2^61, Q32
        (d2 < probe.r2).then_some((dx, dy, d2))
    }

    /// `sum` plus the pushes on the probed cell of the cells in the slots
    /// `run` within the radius.
    #[inline(always)]
    fn run_pushes<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        run: Range<usize>,
        mut sum: [i64; 2],
    ) -> [i64; 2] {
        let (Some(cells), Some(order)) = (self.sorted.get(run.clone()), self.order.get(run)) else {
            return sum;
        };
        for (q, &j) in cells.iter().zip(order) {
            let Some((dx, dy, d2)) = self.offsets::<SHIFTED>(probe, edge, *q) else {
                continue;
            };
            let j = j as usize;
            if d2 == 0 && j == probe.cell {
                continue; // the cell itself
            }
            let repel = probe.repel[self.kind_of(j)];
            let f = force::push(probe.cell, j, [dx, dy], d2, self.radius(), i64::from(repel));
            sum = [sum[0] + f[0], sum[1] + f[1]];
        }
        sum
    }

    /// `own` plus the pushes on the probed cell of the cells in the slots
    /// from `first` on (all after its own), as many as `sums`, within the
    /// radius, their pushes on it added to their `sums`.
    #[inline(always)]
    fn run_pairs<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        first: usize,
        mut own: [i64; 2],
        sums: &mut [[i64; 2]],
    ) -> [i64; 2] {
        let run = first..first + sums.len();
        let (Some(cells), Some(order)) = (self.sorted.get(run.clone()), self.order.get(run)) else {
            return own;
        };
        for ((q, &j), sum) in cells.iter().zip(order).zip(sums) {
            let Some([on_p, on_q]) = self.pair::<SHIFTED>(probe, edge, *q, j) else {
                continue;
            };
            own = [own[0] + on_p[0], own[1] + on_p[1]];
            *sum = [sum[0] + on_q[0], sum[1] + on_q[1]];
        }
        own
    }

    /// The pushes of the probed cell and of cell `j` at `q` on each other,
    /// if `q` lies within the radius.
    #[inline(always)]
    fn pair<const SHIFTED: bool>(
        &self,
        probe: &Probe<'_>,
        edge: [u32; 2],
        q: [i32; 2],
        j: u32,
    ) -> Option<[[i64; 2]; 2]> {
        let (dx, dy, d2) = self.offsets::<SHIFTED>(probe, edge, q)?;
        let j = j as usize;
        let kind = self.kind_of(j);
        let repel = [probe.repel[kind], self.forces.repel[kind][probe.kind]];
        Some(force::pair_pushes(
            probe.cell,
            j,
            [dx, dy],
            d2,
            self.radius(),
            repel,
        ))
    }

    /// The repulsion radius r (Q16).
    #[inline(always)]
    fn radius(&self) -> i64 {
        i64::from(self.forces.radius)
    }

    /// The type of cell `i`, as an index into the repulsion table.
    #[inline(always)]
    fn kind_of(&self, i: usize) -> usize {
        self.kind.get(i).map_or(0, |&k| k as usize % MAX_TYPES)
    }
}

/// The cell whose neighbours [`Snapshot::offsets`] finds, and what each
/// candidate neighbour is compared with, computed once per cell.
#[derive(Debug)]
struct Probe<'f> {
    /// The cell's index.
    cell: usize,
    /// Its type, as an index into the repulsion table.
    kind: usize,
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

impl Moves<'_> {
    /// Moves the cell in grid slot `slot`, at `p`, by its displacement `d`
    /// ([`Snapshot::moved`]), or with its momentum ([`Snapshot::carried`]).
    #[inline]
    fn settle(&mut self, snapshot: &Snapshot<'_>, slot: usize, p: [i32; 2], d: [i32; 2]) {
        let i = snapshot.cell(slot);
        if snapshot.forces.momentum == 0 {
            self.pos[i] = snapshot.moved(p, d);
            return;
        }
        let last = self.velocity.get(i).copied().unwrap_or([0; 2]);
        let (to, step) = snapshot.carried(p, d, last);
        self.pos[i] = to;
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
        sorted: &cells.sorted[..n],
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
/// [`relax`] with half its roots and candidates (642 instructions a cell
/// for its 784 on the croton bench).
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
