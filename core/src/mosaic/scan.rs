//! The neighbour scan of one relaxation step, the same on the plane and
//! on a mesh (thesis Sec. 3.2.1.1): each cell's neighbours within the
//! repulsion radius r, found in the runs of grid slots that its ground's
//! bins name ([`Bins`]: the plane's grid of bins, a mesh's grid of
//! cubes), push it by the force law ([`force`]), summed cell by cell
//! ([`Scan::pushes`]) or each pair once, from its lower slot, on both of
//! its cells ([`Scan::pair_sums`]). All pushes are computed from the
//! snapshot of the points before any cell moves (a Jacobi step), so the
//! order of the loops does not matter and integer sums make the result
//! exact on every machine.

use core::ops::Range;

use super::force;
use super::params::MAX_TYPES;

/// How a ground finds the cells that may lie within r of a cell: runs of
/// consecutive grid slots, and the offset of a candidate on each axis.
pub(super) trait Bins<const D: usize> {
    /// Folds `visit(acc, edge, run)` from `init` over each run of grid
    /// slots that holds cells of the bins within r of the probed cell,
    /// with `edge`: the probe's point less r − 1 on each axis, as the
    /// run's cells are stored (wrapped to u32; [`Bins::offsets`]).
    fn runs<A>(
        &self,
        probe: &Probe<'_, D>,
        init: A,
        visit: impl FnMut(A, [u32; D], Range<usize>) -> A,
    ) -> A;

    /// The displacement d = p − q (Q16) of a candidate at `q` from the
    /// probed cell, with its square (Q32), if it lies within the radius.
    /// Most candidates lie beyond it and cost a comparison or two: |d| < r
    /// ⇔ r − 1 − d ∈ [0, 2r − 1), one unsigned comparison an axis
    /// ([`Probe::reaches`]), the axes one after another.
    fn offsets(&self, probe: &Probe<'_, D>, edge: [u32; D], q: [i32; D])
    -> Option<([i64; D], i64)>;
}

/// One step's cells as the scan reads them: their points in grid-slot
/// order (neighbours are read from contiguous memory), each slot's cell
/// and the cells' types; the ground's bins are given to each scan.
#[derive(Debug)]
pub(super) struct Scan<'s, const D: usize> {
    /// The points in slot order (Q16).
    pub sorted: &'s [[i32; D]],
    /// Each slot's cell index.
    pub order: &'s [u32],
    /// Each cell's type.
    pub kind: &'s [u8],
    /// The repulsion ρ of each pair of types (Q16).
    pub repel: &'s [[i32; MAX_TYPES]; MAX_TYPES],
    /// The repulsion radius r (Q16).
    pub radius: i32,
}

/// The cell whose neighbours a scan sums, and what each candidate is
/// compared with, computed once per cell.
#[derive(Debug)]
pub(super) struct Probe<'f, const D: usize> {
    /// The cell's index.
    pub cell: usize,
    /// Its type, as an index into the repulsion table.
    kind: usize,
    /// Its point.
    pub p: [i32; D],
    /// r − 1.
    pub reach: i32,
    /// 2r − 1 (wrapping u32).
    pub width: u32,
    /// r² (Q32).
    pub r2: i64,
    /// The repulsion between its type and each other.
    repel: &'f [i32; MAX_TYPES],
}

impl<const D: usize> Scan<'_, D> {
    /// The type of cell `i`, as an index into the repulsion table.
    #[inline(always)]
    fn kind_of(&self, i: usize) -> usize {
        self.kind.get(i).map_or(0, |&k| k as usize % MAX_TYPES)
    }

    /// The cell in grid slot `slot` as the scan sees it, or `None` past
    /// the cells.
    #[inline(always)]
    fn probe(&self, slot: usize) -> Option<Probe<'_, D>> {
        let (Some(&p), Some(&cell)) = (self.sorted.get(slot), self.order.get(slot)) else {
            return None;
        };
        let (r, cell) = (self.radius, cell as usize);
        let kind = self.kind_of(cell);
        Some(Probe {
            cell,
            kind,
            p,
            reach: r.wrapping_sub(1),
            width: (r as u32).wrapping_mul(2).wrapping_sub(1),
            r2: i64::from(r) * i64::from(r),
            repel: &self.repel[kind],
        })
    }

    /// The sum of the pushes (Q32) on the cell in grid slot `slot` of its
    /// neighbours within the radius.
    #[inline(always)]
    pub fn pushes<B: Bins<D>>(&self, bins: &B, slot: usize) -> [i64; D] {
        let Some(probe) = self.probe(slot) else {
            return [0; D];
        };
        bins.runs(&probe, [0; D], |sum, edge, run| {
            self.run_pushes(bins, &probe, edge, run, sum)
        })
    }

    /// Adds to `sums` the pushes (Q32) of every pair of cells within the
    /// radius whose lower slot is in `slots`, on both of its cells
    /// ([`force::pair_pushes`]): each pair is found once, from its lower
    /// slot, so a step costs half the roots and half the candidates of
    /// [`Scan::pushes`] for every cell. `sums[k]` is slot `slots.start +
    /// k`'s; a push on a later slot past the end of `sums` goes to
    /// `beyond(slot, push)` instead, so that threads can each take a share
    /// of the slots with its own part of the sums (only pairs across a
    /// share's end, a few rows of cells, go beyond). Over all slots the
    /// sums are exactly those of [`Scan::pushes`]: integer sums do not
    /// depend on their order.
    pub fn pair_sums<B: Bins<D>>(
        &self,
        bins: &B,
        slots: Range<usize>,
        sums: &mut [[i64; D]],
        beyond: &mut impl FnMut(usize, [i64; D]),
    ) {
        // All of them from the first (one thread): no share to leave.
        if slots.start == 0 && sums.len() >= self.sorted.len() {
            self.pair_sums_in::<B, true>(bins, slots, sums, beyond);
        } else {
            self.pair_sums_in::<B, false>(bins, slots, sums, beyond);
        }
    }

    /// [`Scan::pair_sums`]; `WHOLE`: `sums` holds every slot's sum. Out of
    /// line, each of the two: its scan of the runs stays inlined.
    #[inline(never)]
    fn pair_sums_in<B: Bins<D>, const WHOLE: bool>(
        &self,
        bins: &B,
        slots: Range<usize>,
        sums: &mut [[i64; D]],
        beyond: &mut impl FnMut(usize, [i64; D]),
    ) {
        let base = slots.start;
        // One past the last slot whose sum is in `sums`.
        let held = base + sums.len();
        for slot in base..slots.end.min(self.sorted.len()).min(held) {
            let Some(probe) = self.probe(slot) else {
                return;
            };
            let own = bins.runs(&probe, [0; D], |own, edge, run| {
                // The slots after this one: the pairs not yet found.
                let later = run.start.max(slot + 1)..run.end;
                if later.is_empty() {
                    return own;
                }
                if WHOLE {
                    // base = 0: slots index the sums.
                    return match sums.get_mut(later.clone()) {
                        Some(sums) => self.run_pairs(bins, &probe, edge, later.start, own, sums),
                        None => own,
                    };
                }
                if later.end > held {
                    return self.run_across(bins, &probe, edge, later, own, sums, base, beyond);
                }
                // base ≤ slot < later.start < later.end: no underflow.
                let local = later.start - base..later.end - base;
                match sums.get_mut(local) {
                    Some(sums) => self.run_pairs(bins, &probe, edge, later.start, own, sums),
                    None => own,
                }
            });
            let sum = &mut sums[slot - base];
            *sum = add(*sum, own);
        }
    }

    /// [`Scan::run_pairs`] for the slots `later` (base ≤ the probe's slot
    /// < `later.start`) that reach past the slots whose sums are in
    /// `sums`: those past go `beyond` (rare: out of line).
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)] // one of run_pairs', rarely called
    fn run_across<B: Bins<D>>(
        &self,
        bins: &B,
        probe: &Probe<'_, D>,
        edge: [u32; D],
        later: Range<usize>,
        mut own: [i64; D],
        sums: &mut [[i64; D]],
        base: usize,
        beyond: &mut impl FnMut(usize, [i64; D]),
    ) -> [i64; D] {
        // base < later.start ≤ split < later.end: no underflow.
        let split = (base + sums.len()).max(later.start);
        if let Some(sums) = sums.get_mut(later.start - base..split - base) {
            own = self.run_pairs(bins, probe, edge, later.start, own, sums);
        }
        let run = split..later.end;
        let points = self.sorted.get(run.clone()).unwrap_or_default();
        let order = self.order.get(run.clone()).unwrap_or_default();
        for (k, (q, &j)) in run.zip(points.iter().zip(order)) {
            let Some([on_p, on_q]) = self.pair(bins, probe, edge, *q, j) else {
                continue;
            };
            own = add(own, on_p);
            beyond(k, on_q);
        }
        own
    }

    /// `sum` plus the pushes on the probed cell of the cells in the slots
    /// `run` within the radius.
    #[inline(always)]
    fn run_pushes<B: Bins<D>>(
        &self,
        bins: &B,
        probe: &Probe<'_, D>,
        edge: [u32; D],
        run: Range<usize>,
        mut sum: [i64; D],
    ) -> [i64; D] {
        let (Some(points), Some(order)) = (self.sorted.get(run.clone()), self.order.get(run))
        else {
            return sum;
        };
        for (q, &j) in points.iter().zip(order) {
            let Some((d, d2)) = bins.offsets(probe, edge, *q) else {
                continue;
            };
            let j = j as usize;
            if d2 == 0 && j == probe.cell {
                continue; // the cell itself
            }
            let repel = probe.repel[self.kind_of(j)];
            let r = i64::from(self.radius);
            sum = add(sum, force::push(probe.cell, j, d, d2, r, i64::from(repel)));
        }
        sum
    }

    /// `own` plus the pushes on the probed cell of the cells in the slots
    /// from `first` on (all after its own), as many as `sums`, within the
    /// radius, their pushes from it added to their `sums`.
    #[inline(always)]
    fn run_pairs<B: Bins<D>>(
        &self,
        bins: &B,
        probe: &Probe<'_, D>,
        edge: [u32; D],
        first: usize,
        mut own: [i64; D],
        sums: &mut [[i64; D]],
    ) -> [i64; D] {
        let run = first..first + sums.len();
        let (Some(points), Some(order)) = (self.sorted.get(run.clone()), self.order.get(run))
        else {
            return own;
        };
        for ((q, &j), sum) in points.iter().zip(order).zip(sums) {
            let Some([on_p, on_q]) = self.pair(bins, probe, edge, *q, j) else {
                continue;
            };
            own = add(own, on_p);
            *sum = add(*sum, on_q);
        }
        own
    }

    /// The pushes of the probed cell and of cell `j` at `q` on each other,
    /// if `q` lies within the radius.
    #[inline(always)]
    fn pair<B: Bins<D>>(
        &self,
        bins: &B,
        probe: &Probe<'_, D>,
        edge: [u32; D],
        q: [i32; D],
        j: u32,
    ) -> Option<[[i64; D]; 2]> {
        let (d, d2) = bins.offsets(probe, edge, q)?;
        let j = j as usize;
        let kind = self.kind_of(j);
        let repel = [probe.repel[kind], self.repel[kind][probe.kind]];
        let r = i64::from(self.radius);
        Some(force::pair_pushes(probe.cell, j, d, d2, r, repel))
    }
}

impl<const D: usize> Probe<'_, D> {
    /// Whether a candidate whose offset r − 1 − d on an axis is `o`
    /// (wrapped to u32) lies within the radius on it: |d| < r.
    #[inline(always)]
    pub fn reaches(&self, o: u32) -> bool {
        o < self.width
    }

    /// The displacement d = r − 1 − o on an axis where the candidate
    /// [`Probe::reaches`]: in (−r, r).
    #[inline(always)]
    pub fn displacement(&self, o: u32) -> i64 {
        i64::from(self.reach.wrapping_sub(o as i32))
    }
}

/// The sum of two pushes, axis by axis, written out for the plane's two
/// axes and a mesh's three: at opt-level "s" (the firmware's) a loop over
/// them is kept, with the sums in memory.
#[inline(always)]
fn add<const D: usize>(mut a: [i64; D], b: [i64; D]) -> [i64; D] {
    const { assert!(D <= 3, "a push has at most three axes") };
    if let (Some(s), Some(b)) = (a.get_mut(0), b.first()) {
        *s += b;
    }
    if let (Some(s), Some(b)) = (a.get_mut(1), b.get(1)) {
        *s += b;
    }
    if let (Some(s), Some(b)) = (a.get_mut(2), b.get(2)) {
        *s += b;
    }
    a
}
