//! A mesh's step on all cores: cells bucketed in the grid of cubes of the
//! core's mesh kernel ([`CubeGrid`]), each pair once, pushed in their
//! tangent planes and walked along the surface, in slot order.

use morphogen::mosaic::kernels::mesh::{self as surface_relaxation, CubeGrid};
use morphogen::mosaic::{CellSlices, Ground, OnMesh, Place, SurfaceForces};
use rayon::prelude::*;

use super::shares::{RELAX_CHUNK, place_in_parts, sum_in_shares};
use super::{AllCores, Carried};

/// What a mesh's carried step keeps between calls.
#[derive(Debug, Default)]
pub struct MeshScratch {
    /// Each carried cell's bucket.
    bucket: Vec<u32>,
    /// The places and last moves gathered into the slots of a step.
    sorted: Vec<(Place, [i32; 3])>,
}

impl AllCores for OnMesh {
    type Sum = [i64; 3];
    type Scratch = MeshScratch;

    /// One bucket per cell.
    fn bins(cells: usize) -> usize {
        cells + 1
    }

    /// On a mesh a cell always moves with its last move (w_m 0 weighs it
    /// nothing).
    fn momentum(_: &SurfaceForces<'_>) -> bool {
        true
    }

    fn relax_pairs(
        cells: &mut CellSlices<'_, OnMesh>,
        n: usize,
        forces: &SurfaceForces<'_>,
        sums: &mut [[i64; 3]],
    ) {
        surface_relaxation::relax_pairs(cells, n, forces, sums);
    }

    fn relax_carried(
        cells: &mut CellSlices<'_, OnMesh>,
        carried: &mut Carried<OnMesh>,
        sums: &mut [[i64; 3]],
        forces: &SurfaceForces<'_>,
        _: bool,
    ) {
        let n = sums.len();
        let scratch = &mut carried.scratch;
        if scratch.bucket.len() < n {
            scratch.bucket.resize(n, 0);
            scratch.sorted.resize(n, (OnMesh::NO_PLACE, [0; 3]));
        }
        let threads = rayon::current_num_threads();
        let grid = CubeGrid::plan(forces.mesh, forces.radius, cells.bins.len() - 1);
        scratch.bucket[..n]
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.at[..n].par_chunks(RELAX_CHUNK))
            .for_each(|(buckets, places)| {
                for (b, at) in buckets.iter_mut().zip(places) {
                    *b = grid.bucket_of(at.p) as u32; // < 2^30 buckets
                }
            });
        let (order, sorted) = (&mut cells.order[..n], &mut cells.sorted[..n]);
        let put = |slot: &mut u32, i: u32| *slot = i;
        place_in_parts(
            threads,
            grid.buckets(),
            &scratch.bucket[..n],
            cells.bins,
            order,
            put,
        );
        // Each slot's cell index, point, place and last move.
        let (id, place, velocity) = (&carried.id, &carried.at, &carried.velocity);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(sorted.par_chunks_mut(RELAX_CHUNK))
            .zip(scratch.sorted[..n].par_chunks_mut(RELAX_CHUNK))
            .for_each(|((order, sorted), from)| {
                for ((i, p), from) in order.iter_mut().zip(sorted).zip(from) {
                    let e = *i as usize; // a carried cell, < n
                    *i = id[e];
                    *p = place[e].p;
                    *from = (place[e], velocity[e]);
                }
            });
        let snapshot = surface_relaxation::sorted_snapshot(
            grid,
            &cells.order[..n],
            &cells.sorted[..n],
            cells.bins,
            &cells.kind[..n],
            forces,
        );
        sum_in_shares(sums, |slots, sums, past| {
            snapshot.pair_sums(slots, sums, &mut |slot, push| past.push((slot, push)));
        });
        // The cells move in slot order and stay in it.
        carried.at[..n]
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.velocity[..n].par_chunks_mut(RELAX_CHUNK))
            .zip(sums.par_chunks(RELAX_CHUNK))
            .zip(scratch.sorted[..n].par_chunks(RELAX_CHUNK))
            .for_each(|(((places, velocity), sums), from)| {
                for (((to, step), sum), &(at, last)) in
                    places.iter_mut().zip(velocity).zip(sums).zip(from)
                {
                    (*to, *step) = snapshot.moved_by(*sum, at, last);
                }
            });
    }
}
