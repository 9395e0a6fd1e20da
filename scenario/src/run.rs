//! Running a [`Preset`] on a computer: every model in the core's
//! [`Runner`] (the MCU's fixed capacity), except mosaics, whose cells go in
//! a [`VecStore`] sized for the run, bodies, with room for a user's
//! [`USER_CYLINDERS`] cylinders, context-sensitive L-systems, derived in
//! two heap buffers, and bones, with the MCU's mesh capacity and a field
//! cache ([`HOST_FIELD_CACHE`]) the MCU has no RAM for (a context-sensitive
//! skeleton grammar, too, derived in two heap buffers). Both use the core's one run loop
//! ([`morphogen::preset::drive`]), so the stream is the same bytes the
//! firmware writes.

use morphogen::body::Body;
use morphogen::bones::{Bones, HOST_FIELD_CACHE, MCU_TRIANGLES, MCU_VERTICES};
use morphogen::lsys::{Buffered, Grammar, LSystem, LsysError, Module, Neighbours};
use morphogen::mosaic::kernels::mesh::{self as surface_relaxation, CubeGrid};
use morphogen::mosaic::kernels::plane::{self as relaxation, Grid};
use morphogen::mosaic::{
    CellSlices, CellStore, Forces, MAX_FACES, MAX_VERTICES, MeshArrays, MeshBuffers, MeshError,
    MeshParts, MeshStore, Mosaic, MosaicError, OnMesh, Params as MosaicParams, Place, Plane, Relax,
    SurfaceForces, SurfaceMosaic, host_capacity,
};
use morphogen::preset::{self, Model, Preset, Runner};
use morphogen::sim::{Progress, Start};
use morphogen::stream::Sink;
use std::ops::Range;

use rayon::prelude::*;

use crate::body_files::USER_CYLINDERS;

/// A cell store on the heap, its capacity chosen at run time, whose
/// relaxation finds each pair of neighbours once, on all cores (rayon),
/// and keeps the cells in grid order between the steps of a day.
#[derive(Debug, Default)]
pub struct VecStore {
    cells: Cells,
    carried: Carried,
    /// The sums of pair pushes of a relaxation step, one a grid slot,
    /// grown on first use.
    sums: Vec<[i64; 2]>,
}

/// The arrays of a [`VecStore`].
#[derive(Debug, Default)]
struct Cells {
    pos: Vec<[i32; 2]>,
    kind: Vec<u8>,
    next_division: Vec<u16>,
    order: Vec<u32>,
    push: Vec<[i32; 2]>,
    bins: Vec<u32>,
    velocity: Vec<[i32; 2]>,
}

impl Cells {
    fn slices(&mut self) -> CellSlices<'_, Plane> {
        CellSlices {
            pos: &mut self.pos,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.push,
            bins: &mut self.bins,
            velocity: &mut self.velocity,
        }
    }
}

/// The cells between the relaxation steps of a day, in the grid order of
/// the last step: each step's counting sort then starts from cells that
/// are almost in place, and the cells move in slot order, so that every
/// pass reads and writes its arrays in sequence. (Moving them in index
/// order read each one's sum through the grid's permutation: on two
/// cores that took as long as the whole move on one.) They go back to
/// index order after the day's last step.
#[derive(Debug, Default)]
struct Carried {
    /// Each cell's index.
    id: Vec<u32>,
    /// Each cell's position.
    pos: Vec<[i32; 2]>,
    /// Each cell's last move (with momentum).
    velocity: Vec<[i32; 2]>,
    /// The last moves gathered into the grid slots of a step.
    sorted_velocity: Vec<[i32; 2]>,
}

/// Cells a thread takes at a time: small enough to share out a 2 000-cell
/// step, large enough that handing out chunks costs little. Fewer cells
/// than this relax in index order, a step at a time.
const RELAX_CHUNK: usize = 512;

/// Shares of the grid slots per thread when threads find pairs side by
/// side: more than one, so that a thread done early takes another.
const SHARES_PER_THREAD: usize = 4;

/// The pushes (`D` axes) of every pair of neighbours summed into `sums`,
/// one a grid slot, on all threads: each takes shares of the slots with
/// their part of the sums (`pair_sums(slots, part, past)`, the pushes on
/// slots past a share's end put in `past`), which are added after.
fn sum_in_shares<const D: usize>(
    sums: &mut [[i64; D]],
    pair_sums: impl Fn(Range<usize>, &mut [[i64; D]], &mut Vec<(usize, [i64; D])>) + Sync,
) {
    // One thread: one share, all the slots in one pass (nothing beyond).
    let shares = match rayon::current_num_threads() {
        1 => 1,
        threads => threads * SHARES_PER_THREAD,
    };
    let share = sums.len().div_ceil(shares).max(1);
    let past: Vec<Vec<(usize, [i64; D])>> = sums
        .par_chunks_mut(share)
        .enumerate()
        .map(|(part, sums)| {
            sums.fill([0; D]);
            let mut past = Vec::new();
            let first = part * share;
            pair_sums(first..first + sums.len(), sums, &mut past);
            past
        })
        .collect();
    for (slot, push) in past.into_iter().flatten() {
        if let Some(sum) = sums.get_mut(slot) {
            for (s, p) in sum.iter_mut().zip(push) {
                *s += p;
            }
        }
    }
}

/// The counting sort of [`Grid::place`] (each bin's first slot into
/// `bins`, the cells' number after the last; each slot's cell, by
/// `put(slot, cell)`, into `slots`) of cells nearly in bin order (carried
/// from the last step) in `parts` parts side by side: each part takes a
/// range of the `nb` bins, split where the cells' order splits evenly, and
/// the range of slots they fill. Each part reads every cell's bin
/// (`bin_of`) twice, to count and to place those in its bins (in the
/// cells' order, as `Grid::place`: the same slots), and writes only its
/// own bins and slots.
fn place_in_parts<T: Send>(
    parts: usize,
    nb: usize,
    bin_of: &[u32],
    bins: &mut [u32],
    slots: &mut [T],
    put: impl Fn(&mut T, u32) + Sync,
) {
    let n = bin_of.len();
    let Some(bins) = bins.get_mut(..=nb) else {
        return;
    };
    bins[nb] = n as u32;
    // Where the bin ranges split: the bins of evenly spaced cells.
    let mut splits: Vec<usize> = (1..parts)
        .map(|k| (bin_of[k * n / parts] as usize).min(nb))
        .collect();
    splits.insert(0, 0);
    splits.push(nb);
    for k in 1..splits.len() {
        splits[k] = splits[k].max(splits[k - 1]);
    }
    let mut ranges: Vec<(usize, &mut [u32])> = Vec::with_capacity(parts);
    let mut rest = &mut bins[..nb];
    for w in splits.windows(2) {
        let (part, tail) = rest.split_at_mut(w[1] - w[0]);
        ranges.push((w[0], part));
        rest = tail;
    }
    // Each range's cells, counted into its bins.
    let counts: Vec<u32> = ranges
        .par_iter_mut()
        .map(|(first, bins)| {
            bins.fill(0);
            let mut count = 0;
            for &b in bin_of {
                if let Some(c) = (b as usize)
                    .checked_sub(*first)
                    .and_then(|k| bins.get_mut(k))
                {
                    *c += 1;
                    count += 1;
                }
            }
            count
        })
        .collect();
    // Each range's slots, then its cells placed into them.
    let mut parts_of_sorted = Vec::with_capacity(parts);
    let mut rest = slots;
    for &count in &counts {
        let (part, tail) = rest.split_at_mut(count as usize);
        parts_of_sorted.push(part);
        rest = tail;
    }
    let mut start = 0u32;
    let starts: Vec<u32> = counts
        .iter()
        .map(|c| {
            start += c;
            start - c
        })
        .collect();
    ranges
        .into_par_iter()
        .zip(parts_of_sorted)
        .zip(starts)
        .for_each(|(((first, bins), sorted), start)| {
            let mut end = start;
            for b in bins.iter_mut() {
                end += *b;
                *b = end; // end of the bin
            }
            for (i, &b) in bin_of.iter().enumerate().rev() {
                if let Some(end) = (b as usize)
                    .checked_sub(first)
                    .and_then(|k| bins.get_mut(k))
                {
                    *end -= 1; // ends as the start of the bin
                    if let Some(slot) = sorted.get_mut((*end - start) as usize) {
                        put(slot, i as u32); // i < n ≤ u32::MAX
                    }
                }
            }
        });
}

impl VecStore {
    /// A store of `cells` cells (with their last moves, for momentum) and
    /// `cells / 2 + 1` grid bin offsets: one bin per two cells, twice the
    /// MCU's, the fewest instructions per relaxation step on the croton
    /// bench (one bin per 4 cells or per cell cost 1 % more; integer sums:
    /// the same positions whatever the grid).
    #[must_use]
    pub fn new(cells: usize) -> VecStore {
        VecStore {
            cells: Cells {
                pos: vec![[0; 2]; cells],
                kind: vec![0; cells],
                next_division: vec![0; cells],
                order: vec![0; cells],
                push: vec![[0; 2]; cells],
                bins: vec![0; cells / 2 + 1],
                velocity: vec![[0; 2]; cells],
            },
            carried: Carried::default(),
            sums: Vec::new(),
        }
    }

    /// One step over the `n` carried cells (`momentum`: with their last
    /// moves): the grid built from their order, each pair of neighbours
    /// once into the slots' sums (in shares on several threads), the
    /// cells moved and carried on in the new slot order.
    fn relax_carried(&mut self, n: usize, forces: &Forces<'_>, momentum: bool) {
        let grid: &Grid = forces.grid;
        let carried = &mut self.carried;
        let mut cells = self.cells.slices();
        // The bin of each carried cell into `order`, its slot's cell
        // (index into the carried arrays) into the push scratch...
        let (order, sorted) = (&mut cells.order[..n], &mut cells.sorted[..n]);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.pos[..n].par_chunks(RELAX_CHUNK))
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
        let (id, pos, velocity) = (&carried.id, &carried.pos, &carried.velocity);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(sorted.par_chunks_mut(RELAX_CHUNK))
            .zip(carried.sorted_velocity[..n].par_chunks_mut(RELAX_CHUNK))
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
        let (snapshot, _) = relaxation::sorted_snapshot(&mut cells, n, forces);
        let sums = &mut self.sums[..n];
        sum_in_shares(sums, |slots, sums, past| {
            snapshot.pair_sums(slots, sums, &mut |slot, push| past.push((slot, push)));
        });
        // The cells move in slot order and stay in it.
        let (to, made) = (&mut carried.pos[..n], &mut carried.velocity[..n]);
        let last: &[[i32; 2]] = if momentum {
            &carried.sorted_velocity[..n]
        } else {
            &[]
        };
        to.par_chunks_mut(RELAX_CHUNK)
            .zip(made.par_chunks_mut(RELAX_CHUNK))
            .zip(sums.par_chunks(RELAX_CHUNK))
            .enumerate()
            .for_each(|(chunk, ((to, made), sums))| {
                let first = chunk * RELAX_CHUNK;
                let last = last.get(first..first + sums.len()).unwrap_or(&[]);
                snapshot.move_slots(first, sums, last, to, made);
            });
        // The slots' cell indices are the carried order of the next step.
        std::mem::swap(&mut carried.id, &mut self.cells.order);
    }
}

impl CellStore for VecStore {
    fn capacity(&self) -> usize {
        self.cells.pos.len()
    }

    fn slices(&mut self) -> CellSlices<'_, Plane> {
        self.cells.slices()
    }

    fn positions(&self) -> &[[i32; 2]] {
        &self.cells.pos
    }

    fn kinds(&self) -> &[u8] {
        &self.cells.kind
    }
}

impl Relax for VecStore {
    /// Each pair of neighbours once ([`relaxation::relax_pairs`]), the
    /// cells kept in the grid order of the last step from one step to the
    /// next (so that every pass reads and writes in sequence) and put back
    /// in index order after the last; on
    /// several threads the grid's per-cell phases, the pairs (each thread
    /// a share of the grid slots into that share of the sums, the few
    /// pushes past its end kept aside and added after) and the moves run
    /// side by side. Integer sums: the same bits in any order of the cells
    /// and on any number of threads.
    fn relax(&mut self, n: usize, forces: &Forces<'_>, times: u16) {
        if self.sums.len() < n {
            self.sums.resize(n, [0; 2]);
        }
        if n < RELAX_CHUNK {
            for _ in 0..times {
                let mut cells = self.cells.slices();
                relaxation::relax_pairs(&mut cells, n, forces, &mut self.sums);
            }
            return;
        }
        let momentum = forces.momentum != 0 && self.cells.velocity.len() >= n;
        let carried = &mut self.carried;
        for v in [
            &mut carried.pos,
            &mut carried.velocity,
            &mut carried.sorted_velocity,
        ] {
            if v.len() < n {
                v.resize(n, [0; 2]);
            }
        }
        // As long as the store's own `order`, which it swaps with.
        carried.id.resize(self.cells.order.len(), 0);
        carried.pos[..n].copy_from_slice(&self.cells.pos[..n]);
        if momentum {
            carried.velocity[..n].copy_from_slice(&self.cells.velocity[..n]);
        }
        for (k, id) in (0u32..).zip(&mut carried.id[..n]) {
            *id = k;
        }
        for _ in 0..times {
            self.relax_carried(n, forces, momentum);
        }
        let (carried, cells) = (&self.carried, &mut self.cells);
        for ((&i, p), v) in carried.id[..n]
            .iter()
            .zip(&carried.pos)
            .zip(&carried.velocity)
        {
            let i = i as usize;
            cells.pos[i] = *p;
            if momentum {
                cells.velocity[i] = *v;
            }
        }
    }
}

/// A surface mosaic's cell store on the heap, relaxed on all cores, each
/// pair of neighbours once, the cells kept in bucket order through a
/// day's steps (as [`VecStore`]'s).
#[derive(Debug, Default)]
pub struct VecSurfaceStore {
    place: Vec<Place>,
    kind: Vec<u8>,
    next_division: Vec<u16>,
    order: Vec<u32>,
    sorted: Vec<[i32; 3]>,
    buckets: Vec<u32>,
    velocity: Vec<[i32; 3]>,
    carried: CarriedPlaces,
    /// The sums of pair pushes of a step, one a bucket slot.
    sums: Vec<[i64; 3]>,
}

/// The cells between the relaxation steps of a day, in the bucket order
/// of the last step ([`Carried`] on a surface).
#[derive(Debug, Default)]
struct CarriedPlaces {
    /// Each cell's index.
    id: Vec<u32>,
    /// Each cell's place.
    place: Vec<Place>,
    /// Each cell's last move.
    velocity: Vec<[i32; 3]>,
    /// Each cell's bucket.
    bucket: Vec<u32>,
    /// The places and last moves gathered into the slots of a step.
    sorted: Vec<(Place, [i32; 3])>,
}

impl VecSurfaceStore {
    /// A store of `cells` cells (with their last moves) and one grid
    /// bucket per cell.
    #[must_use]
    pub fn new(cells: usize) -> VecSurfaceStore {
        let nowhere = Place { face: 0, p: [0; 3] };
        VecSurfaceStore {
            place: vec![nowhere; cells],
            kind: vec![0; cells],
            next_division: vec![0; cells],
            order: vec![0; cells],
            sorted: vec![[0; 3]; cells],
            buckets: vec![0; cells + 1],
            velocity: vec![[0; 3]; cells],
            carried: CarriedPlaces::default(),
            sums: Vec::new(),
        }
    }

    /// One step over the `n` carried cells: the buckets built from their
    /// order, each pair of neighbours once into the slots' sums (in
    /// shares on several threads), the cells moved and carried on in the
    /// new slot order.
    fn relax_carried(&mut self, n: usize, forces: &SurfaceForces<'_>) {
        let threads = rayon::current_num_threads();
        let carried = &mut self.carried;
        let grid = CubeGrid::plan(forces.mesh, forces.radius, self.buckets.len() - 1);
        carried.bucket[..n]
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.place[..n].par_chunks(RELAX_CHUNK))
            .for_each(|(buckets, places)| {
                for (b, at) in buckets.iter_mut().zip(places) {
                    *b = grid.bucket_of(at.p) as u32; // < 2^30 buckets
                }
            });
        let (order, sorted) = (&mut self.order[..n], &mut self.sorted[..n]);
        let put = |slot: &mut u32, i: u32| *slot = i;
        place_in_parts(
            threads,
            grid.buckets(),
            &carried.bucket[..n],
            &mut self.buckets,
            order,
            put,
        );
        // Each slot's cell index, point, place and last move.
        let (id, place, velocity) = (&carried.id, &carried.place, &carried.velocity);
        order
            .par_chunks_mut(RELAX_CHUNK)
            .zip(sorted.par_chunks_mut(RELAX_CHUNK))
            .zip(carried.sorted[..n].par_chunks_mut(RELAX_CHUNK))
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
            &self.order[..n],
            &self.sorted[..n],
            &self.buckets,
            &self.kind[..n],
            forces,
        );
        let sums = &mut self.sums[..n];
        sum_in_shares(sums, |slots, sums, past| {
            snapshot.pair_sums(slots, sums, &mut |slot, push| past.push((slot, push)));
        });
        // The cells move in slot order and stay in it.
        carried.place[..n]
            .par_chunks_mut(RELAX_CHUNK)
            .zip(carried.velocity[..n].par_chunks_mut(RELAX_CHUNK))
            .zip(sums.par_chunks(RELAX_CHUNK))
            .zip(carried.sorted[..n].par_chunks(RELAX_CHUNK))
            .for_each(|(((places, velocity), sums), from)| {
                for (((to, step), sum), &(at, last)) in
                    places.iter_mut().zip(velocity).zip(sums).zip(from)
                {
                    (*to, *step) = snapshot.moved_by(*sum, at, last);
                }
            });
        // The slots' cell indices are the carried order of the next step.
        std::mem::swap(&mut carried.id, &mut self.order);
    }
}

impl CellStore<OnMesh> for VecSurfaceStore {
    fn capacity(&self) -> usize {
        self.place.len()
    }

    fn slices(&mut self) -> CellSlices<'_, OnMesh> {
        CellSlices {
            pos: &mut self.place,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.sorted,
            bins: &mut self.buckets,
            velocity: &mut self.velocity,
        }
    }

    fn positions(&self) -> &[Place] {
        &self.place
    }

    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}

impl Relax<OnMesh> for VecSurfaceStore {
    /// Each pair of neighbours once, the cells kept in the bucket order
    /// of the last step from one step to the next and put back in index
    /// order after the last, on one thread or side by side, as on the
    /// plane ([`VecStore`]'s relaxation).
    fn relax(&mut self, n: usize, forces: &SurfaceForces<'_>, times: u16) {
        if self.sums.len() < n {
            self.sums.resize(n, [0; 3]);
        }
        if n < RELAX_CHUNK {
            let mut sums = std::mem::take(&mut self.sums);
            for _ in 0..times {
                surface_relaxation::relax_pairs(&mut self.slices(), n, forces, &mut sums);
            }
            self.sums = sums;
            return;
        }
        let carried = &mut self.carried;
        let nowhere = Place { face: 0, p: [0; 3] };
        // As long as the store's own `order`, which it swaps with.
        carried.id.resize(self.order.len(), 0);
        if carried.place.len() < n {
            carried.place.resize(n, nowhere);
            carried.velocity.resize(n, [0; 3]);
            carried.bucket.resize(n, 0);
            carried.sorted.resize(n, (nowhere, [0; 3]));
        }
        carried.place[..n].copy_from_slice(&self.place[..n]);
        carried.velocity[..n].copy_from_slice(&self.velocity[..n]);
        for (k, id) in (0u32..).zip(&mut carried.id[..n]) {
            *id = k;
        }
        for _ in 0..times {
            self.relax_carried(n, forces);
        }
        let carried = &self.carried;
        for ((&i, at), v) in carried.id[..n]
            .iter()
            .zip(&carried.place)
            .zip(&carried.velocity)
        {
            self.place[i as usize] = *at;
            self.velocity[i as usize] = *v;
        }
    }
}

/// The heap buffers of a surface's mesh, sized for each mesh, with its
/// inward normals and edge scratch (the fast build and walk), and its
/// anisotropy field.
#[derive(Debug, Default)]
pub struct MeshVecs {
    vertices: Vec<[i32; 3]>,
    faces: Vec<[u32; 3]>,
    neighbours: Vec<[u32; 3]>,
    normals: Vec<[i32; 3]>,
    inward: Vec<[[i32; 3]; 3]>,
    edges: Vec<u64>,
    field: Vec<[i32; 3]>,
}

impl MeshVecs {
    fn arrays(&self) -> MeshArrays<'_> {
        MeshArrays {
            vertices: &self.vertices,
            faces: &self.faces,
            neighbours: &self.neighbours,
            normals: &self.normals,
            inward: &self.inward,
        }
    }
}

impl MeshStore for MeshVecs {
    fn buffers(
        &mut self,
        vertices: usize,
        faces: usize,
    ) -> Result<(MeshBuffers<'_>, &mut [[i32; 3]]), morphogen::Error> {
        // Refused before the buffers (some 120 B a triangle) are allocated.
        if vertices > MAX_VERTICES || faces > MAX_FACES {
            return Err(MosaicError::Mesh(MeshError::TooLarge).into());
        }
        self.vertices.resize(vertices, [0; 3]);
        self.faces.resize(faces, [0; 3]);
        self.neighbours.resize(faces, [0; 3]);
        self.normals.resize(faces, [0; 3]);
        self.inward.resize(faces, [[0; 3]; 3]);
        self.edges.resize(3 * faces, 0);
        self.field.resize(faces, [0; 3]);
        let buffers = MeshBuffers {
            vertices: &mut self.vertices,
            faces: &mut self.faces,
            parts: MeshParts {
                neighbours: &mut self.neighbours,
                normals: &mut self.normals,
                inward: &mut self.inward,
                edges: &mut self.edges,
            },
        };
        Ok((buffers, &mut self.field))
    }

    fn arrays(&self) -> (MeshArrays<'_>, &[[i32; 3]]) {
        (MeshVecs::arrays(self), &self.field)
    }

    fn arrays_mut(&mut self) -> (MeshArrays<'_>, &mut [[i32; 3]]) {
        let arrays = MeshArrays {
            vertices: &self.vertices,
            faces: &self.faces,
            neighbours: &self.neighbours,
            normals: &self.normals,
            inward: &self.inward,
        };
        (arrays, &mut self.field)
    }
}

/// Modules in each of the two buffers of a context-sensitive L-system's
/// derivation on the host (32 MB each); the core's streaming derivation,
/// which the MCU uses, handles context-free grammars only.
pub const HOST_BUFFER_MODULES: usize = 1 << 21;

/// Modules of each buffer of a context-sensitive bone grammar's
/// derivation: 8 × a skeleton string's limit
/// ([`morphogen::bones::MAX_SKELETON_MODULES`]), for strings that shrink.
pub const BONE_BUFFER_MODULES: usize = 8 * morphogen::bones::MAX_SKELETON_MODULES as usize;

/// Runs `preset` with `seed` into `sink`: header, then every step.
///
/// # Errors
/// The model's refusal of its parameters (naming the limit or parameter),
/// then the first error of a step or of the sink.
pub fn run(
    preset: &Preset<'_>,
    seed: u64,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), morphogen::Error> {
    let header = preset::header(preset.name, seed, preset.model.params_digest());
    match preset.model {
        Model::Mosaic(
            params @ &MosaicParams {
                surface: Some(_), ..
            },
        ) => {
            let store = VecSurfaceStore::new(host_capacity(params));
            let mut mosaic = SurfaceMosaic::on_mesh(store, MeshVecs::default());
            mosaic.start(params, seed)?;
            preset::drive(&mut mosaic, &header, sink, progress)
        }
        Model::Mosaic(params) => {
            let mut mosaic = Mosaic::new(VecStore::new(host_capacity(params)));
            mosaic.start(params, seed)?;
            preset::drive(&mut mosaic, &header, sink, progress)
        }
        Model::LSystem(text) => {
            let mut grammar = Box::new(Grammar::new());
            grammar
                .parse(text)
                .map_err(|e| morphogen::Error::Lsys(LsysError::Parse(e)))?;
            if grammar.needs_buffer() {
                let mut a = vec![Module::default(); HOST_BUFFER_MODULES];
                let mut b = vec![Module::default(); HOST_BUFFER_MODULES];
                let mut links = vec![Neighbours::default(); HOST_BUFFER_MODULES];
                let mut sim = Box::new(LSystem::<_>::with_derivation(Buffered::new(
                    &mut a, &mut b, &mut links,
                )));
                sim.start(text, seed)?;
                preset::drive(sim.as_mut(), &header, sink, progress)
            } else {
                let mut runner = Box::new(Runner::new());
                runner.start(&preset.model, seed)?;
                preset::drive(runner.as_mut(), &header, sink, progress)
            }
        }
        Model::Bones(params) => {
            let mut grammar = Box::new(Grammar::new());
            grammar
                .parse(params.grammar)
                .map_err(|e| morphogen::Error::Lsys(LsysError::Parse(e)))?;
            if grammar.needs_buffer() {
                // A context-sensitive skeleton grammar (the paper's, Sec. 3).
                let mut a = vec![Module::default(); BONE_BUFFER_MODULES];
                let mut b = vec![Module::default(); BONE_BUFFER_MODULES];
                let mut links = vec![Neighbours::default(); BONE_BUFFER_MODULES];
                let mut bones = Box::new(Bones::<
                    '_,
                    MCU_VERTICES,
                    MCU_TRIANGLES,
                    HOST_FIELD_CACHE,
                    Buffered<'_>,
                >::with_derivation(Buffered::new(
                    &mut a, &mut b, &mut links,
                )));
                bones.start(params, seed)?;
                preset::drive(bones.as_mut(), &header, sink, progress)
            } else {
                let mut bones =
                    Box::new(Bones::<'_, MCU_VERTICES, MCU_TRIANGLES, HOST_FIELD_CACHE>::new());
                bones.start(params, seed)?;
                preset::drive(bones.as_mut(), &header, sink, progress)
            }
        }
        Model::Body(params) => {
            let mut body = Box::new(Body::<'_, USER_CYLINDERS>::new());
            body.start(params, seed)?;
            preset::drive(body.as_mut(), &header, sink, progress)
        }
        model => {
            let mut runner = Box::new(Runner::new());
            runner.start(&model, seed)?;
            preset::drive(runner.as_mut(), &header, sink, progress)
        }
    }
}
