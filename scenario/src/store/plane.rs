//! The plane's step on all cores: cells binned in the grid of the core's
//! plane kernel ([`Grid`]), each pair once, moved in slot order.

use morphogen::mosaic::kernels::plane::{self as relaxation, Grid};
use morphogen::mosaic::{CellSlices, Forces, Plane};
use rayon::prelude::*;

use super::shares::{RELAX_CHUNK, place_in_parts, sum_in_shares};
use super::{AllCores, Carried};

impl AllCores for Plane {
    type Sum = [i64; 2];
    /// The last moves gathered into the grid slots of a step.
    type Scratch = Vec<[i32; 2]>;

    /// One bin per two cells, twice the MCU's: the fewest instructions per
    /// relaxation step on the croton bench (one bin per 4 cells or per
    /// cell cost 1 % more; integer sums: the same positions whatever the
    /// grid).
    fn bins(cells: usize) -> usize {
        cells / 2 + 1
    }

    fn momentum(forces: &Forces<'_>) -> bool {
        forces.momentum != 0
    }

    fn relax_pairs(
        cells: &mut CellSlices<'_, Plane>,
        n: usize,
        forces: &Forces<'_>,
        sums: &mut [[i64; 2]],
    ) {
        relaxation::relax_pairs(cells, n, forces, sums);
    }

    fn relax_carried(
        cells: &mut CellSlices<'_, Plane>,
        carried: &mut Carried<Plane>,
        sums: &mut [[i64; 2]],
        forces: &Forces<'_>,
        momentum: bool,
    ) {
        let n = sums.len();
        let grid: &Grid = forces.grid;
        if carried.scratch.len() < n {
            carried.scratch.resize(n, [0; 2]);
        }
        // The bin of each carried cell into `order`, its slot's cell
        // (index into the carried arrays) into the sorted scratch...
        let (order, sorted) = (&mut cells.order[..n], &mut cells.sorted[..n]);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.at[..n].par_chunks(RELAX_CHUNK))
            .for_each(|(bins, pos)| grid.bin_cells(pos, bins));
        let threads = rayon::current_num_threads();
        if threads == 1 {
            grid.place(order, cells.bins, sorted);
        } else {
            // i < n ≤ i32::MAX, as `Grid::place`.
            let put = |slot: &mut [i32; 2], i: u32| slot[0] = i as i32;
            place_in_parts(threads, grid.bins(), order, cells.bins, sorted, put);
        }
        // ...then each slot's cell index, position and last move.
        let (id, pos, velocity) = (&carried.id, &carried.at, &carried.velocity);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(sorted.par_chunks_mut(RELAX_CHUNK))
            .zip(carried.scratch[..n].par_chunks_mut(RELAX_CHUNK))
            .for_each(|((order, sorted), last)| {
                for ((i, p), v) in order.iter_mut().zip(sorted).zip(last) {
                    let from = p[0] as usize; // a carried cell, < n
                    *i = id[from];
                    *p = pos[from];
                    if momentum {
                        *v = velocity[from];
                    }
                }
            });
        let (snapshot, _) = relaxation::sorted_snapshot(cells, n, forces);
        sum_in_shares(sums, |slots, sums, past| {
            snapshot.pair_sums(slots, sums, &mut |slot, push| past.push((slot, push)));
        });
        // The cells move in slot order and stay in it.
        let (to, made) = (&mut carried.at[..n], &mut carried.velocity[..n]);
        let last: &[[i32; 2]] = if momentum { &carried.scratch[..n] } else { &[] };
        to.par_chunks_mut(RELAX_CHUNK)
            .zip(made.par_chunks_mut(RELAX_CHUNK))
            .zip(sums.par_chunks(RELAX_CHUNK))
            .enumerate()
            .for_each(|(chunk, ((to, made), sums))| {
                let first = chunk * RELAX_CHUNK;
                let last = last.get(first..first + sums.len()).unwrap_or(&[]);
                snapshot.move_slots(first, sums, last, to, made);
            });
    }
}
