//! Relaxation on a surface (MClone thesis, Secs. 3.2.1.1 and 4.1: the cells
//! on the object itself): the plane's force law
//! ρ_pq·(r − d)·(p − q)/d ([`crate::mosaic::force`]) by 3D distance
//! d < r, summed over the neighbours that the scan shared with the plane
//! ([`crate::mosaic::scan`]) finds in a grid of cubes, blended with the
//! anisotropy field of the cell's face (w_a) and scaled by w_d as on the
//! plane, taken into the cell's tangent plane and walked along the mesh
//! ([`Mesh::walk`]). A Jacobi step on integer sums: the same result in any
//! order.
//!
//! The grid bins space into cubes at least r wide, so a cell's neighbours
//! lie in the (at most 27) cubes its sphere of radius r touches; the cubes
//! are folded into a fixed number of buckets ([`CubeGrid`]; a surface fills
//! few cubes of its box), so memory stays bounded whatever the mesh's
//! size. Cells of other cubes that share a bucket are rejected by distance.

use core::num::NonZeroU32;
use core::ops::Range;

use crate::mosaic::force::Step;
use crate::mosaic::ground::{CellSlices, Ground};
use crate::mosaic::mesh::{Mesh, Place, per_axis};
use crate::mosaic::params::MAX_TYPES;
use crate::mosaic::scan::{Bins, Probe, Scan};

/// The constants of one relaxation step on a surface.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceForces<'a> {
    /// The mesh.
    pub mesh: &'a Mesh<'a>,
    /// The repulsion radius r (Q16).
    pub radius: i32,
    /// The repulsion ρ of each pair of types (Q16).
    pub repel: [[i32; MAX_TYPES]; MAX_TYPES],
    /// w_d (Q16).
    pub push_weight: i32,
    /// w_a (Q16).
    pub anisotropy_weight: i32,
    /// The anisotropy field at each face (Q14, in its plane), if any.
    pub field: Option<&'a [[i32; 3]]>,
    /// β (Q16, below 1).
    pub momentum: i32,
}

/// Cubes of side ≥ r over the mesh's bounding box, folded into the
/// buckets: cube (x, y, z) goes to bucket (x mod A, y mod B, z mod C)
/// (row-major, x fastest), A·B·C at most the buckets. A cell's window
/// (|d| < r on each axis) meets 2 or 3 cubes along each axis, and a row of
/// them is a run of consecutive buckets (two at the fold); cells of cubes
/// folded onto the same bucket are rejected by distance. The side grows
/// from r in steps of r/4 up to 2r while the box has more cubes than
/// buckets: fewer cubes to scan and fewer folded strangers in them, for
/// more cells in the window.
#[derive(Clone, Copy, Debug)]
pub struct CubeGrid {
    origin: [i32; 3],
    /// 2^32 / side.
    scale: u64,
    /// A, B, C.
    modulus: [NonZeroU32; 3],
}

impl CubeGrid {
    /// A grid for radius `radius` over the mesh with at most `buckets`
    /// buckets.
    #[must_use]
    pub fn plan(mesh: &Mesh<'_>, radius: i32, buckets: usize) -> CubeGrid {
        let r = i64::from(radius.max(1));
        let [lo, hi] = mesh.bounds();
        let buckets = buckets.clamp(1, 1 << 30) as u64;
        let product = |m: &[u32; 3]| m.iter().map(|&x| u64::from(x)).product::<u64>();
        let cubes = |side: i64| {
            [0, 1, 2].map(|c| {
                ((i64::from(hi[c]) - i64::from(lo[c])) / side + 1).clamp(1, 1 << 10) as u32
            })
        };
        // A margin of 1/64 + 1 LSB keeps every cube wider than the radius
        // despite the truncated scale factor; r < 2^31, so side < 2^33.
        let side_of = |quarters: i64| r + quarters * (r >> 2) + (r >> 6) + 1;
        let quarters = (0..4)
            .find(|&q| product(&cubes(side_of(q))) <= buckets)
            .unwrap_or(4);
        let side = side_of(quarters);
        let mut modulus = cubes(side);
        while product(&modulus) > buckets {
            let c = (0..3).max_by_key(|&c| modulus[c]).unwrap_or(0);
            if modulus[c] <= 1 {
                break;
            }
            modulus[c] -= 1;
        }
        CubeGrid {
            origin: lo,
            scale: (1u64 << 32) / side as u64,
            modulus: modulus.map(|m| NonZeroU32::new(m).unwrap_or(NonZeroU32::MIN)),
        }
    }

    /// The buckets it uses.
    #[must_use]
    pub fn buckets(&self) -> usize {
        self.modulus.iter().map(|&m| m.get() as usize).product()
    }

    /// The cube index of `x` along axis `c` (0 below the origin).
    #[inline]
    fn cube(&self, c: usize, x: i64) -> u32 {
        let off = (x - i64::from(self.origin[c])).max(0) as u64;
        ((off * self.scale) >> 32) as u32
    }

    /// The bucket of the point `p`.
    #[inline]
    #[must_use]
    pub fn bucket_of(&self, p: [i32; 3]) -> usize {
        let [x, y, z] = per_axis(|c| self.cube(c, i64::from(p[c])) % self.modulus[c]);
        ((z * self.modulus[1].get() + y) * self.modulus[0].get() + x) as usize
    }

    /// Counting-sorts the `places` into `order` and their points into
    /// `sorted` by bucket; `offsets` ends as each bucket's first slot (and
    /// one past the last). Each cell's bucket is found once: `order` holds
    /// the buckets until the cells have their slots, `sorted` the indices
    /// until `order` is free.
    pub fn build(
        &self,
        places: &[Place],
        order: &mut [u32],
        offsets: &mut [u32],
        sorted: &mut [[i32; 3]],
    ) {
        let b = self.buckets().min(offsets.len().saturating_sub(1));
        let offsets = &mut offsets[..=b];
        offsets.fill(0);
        for (at, bucket) in places.iter().zip(order.iter_mut()) {
            let k = self.bucket_of(at.p);
            *bucket = k as u32; // < 2^30 buckets
            if let Some(o) = offsets.get_mut(k + 1) {
                *o += 1;
            }
        }
        for k in 1..=b {
            offsets[k] += offsets[k - 1];
        }
        for (i, &bucket) in order.iter().enumerate() {
            let Some(o) = offsets.get_mut(bucket as usize) else {
                continue;
            };
            let slot = *o as usize;
            *o += 1;
            if let Some(s) = sorted.get_mut(slot) {
                s[0] = i as i32; // i < places.len() ≤ 2^31
            }
        }
        for (o, s) in order.iter_mut().zip(sorted.iter_mut()) {
            let i = s[0] as u32;
            *o = i;
            *s = match places.get(i as usize) {
                Some(at) => at.p,
                None => [0; 3],
            };
        }
        // Each entry now ends its bucket: move them one on.
        offsets.copy_within(0..b, 1);
        offsets[0] = 0;
    }

    /// The residues along axis `c` of the cubes `first..=last`, each once:
    /// `(start, count)` of one run of consecutive ones, or of two where
    /// they wrap past the modulus, and how many runs.
    #[inline]
    fn runs(&self, c: usize, first: u32, last: u32) -> ([(u32, u32); 2], usize) {
        let m = self.modulus[c];
        let span = last.saturating_sub(first);
        if span >= m.get() - 1 {
            return ([(0, m.get()), (0, 0)], 1);
        }
        // last % m, from first's residue: a + span < 2m.
        let a = first % m;
        match (a + span).checked_sub(m.get()) {
            None => ([(a, span + 1), (0, 0)], 1),
            Some(b) => ([(a, m.get() - a), (0, b + 1)], 2),
        }
    }
}

/// What one step reads: the points in bucket order, the grid, the forces.
#[derive(Debug)]
pub struct Snapshot<'s> {
    scan: Scan<'s, 3>,
    bins: CubeBins<'s>,
    forces: &'s SurfaceForces<'s>,
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

    /// The index of the cell in slot `slot`.
    #[must_use]
    pub fn cell(&self, slot: usize) -> usize {
        self.scan.order[slot] as usize
    }

    /// Adds to `sums` the pushes (Q32) of every pair of cells within the
    /// radius whose lower slot is in `slots`, on both of its cells, each
    /// pair once; a push on a later slot past the end of `sums` goes to
    /// `beyond(slot, push)`, as on the plane. The 3D pushes of a pair are
    /// equal and opposite up to their floors, which the force law takes
    /// from one product for both.
    pub fn pair_sums(
        &self,
        slots: Range<usize>,
        sums: &mut [[i64; 3]],
        beyond: &mut impl FnMut(usize, [i64; 3]),
    ) {
        self.scan.pair_sums(&self.bins, slots, sums, beyond);
    }

    /// The new place of a cell at `from`, pushed by `sum` (Q32, as
    /// [`Snapshot::pair_sums`] sums them) and last moved by `last`, and
    /// the move it made.
    #[must_use]
    pub fn moved_by(&self, sum: [i64; 3], from: Place, last: [i32; 3]) -> (Place, [i32; 3]) {
        let forces = self.forces;
        let step = Step {
            r: i64::from(forces.radius),
            push_weight: i64::from(forces.push_weight),
            anisotropy_weight: i64::from(forces.anisotropy_weight),
            momentum: i64::from(forces.momentum),
        };
        // Without w_a the blend is Σ itself, whatever the field.
        let v = (step.anisotropy_weight != 0).then(|| {
            forces
                .field
                .and_then(|f| f.get(from.face as usize))
                .copied()
                .unwrap_or([0; 3])
        });
        let push = step.displacement(sum, v);
        let d = if step.momentum == 0 {
            push // no carry: (0 + 2^15) >> 16 = 0
        } else {
            step.carried(push, last)
        };
        let to = forces.mesh.walk(from, d);
        let step = per_axis(|c| to.p[c].wrapping_sub(from.p[c]));
        (to, step)
    }
}

/// A mesh's bins for the scan: the buckets of the cubes that a probe's
/// window (|d| < r on each axis) meets.
#[derive(Debug)]
struct CubeBins<'s> {
    grid: CubeGrid,
    /// Each bucket's first slot (and one past the last).
    offsets: &'s [u32],
}

impl Bins<3> for CubeBins<'_> {
    /// Each row of buckets is one run of consecutive slots (two at the
    /// fold).
    #[inline(always)]
    fn runs<A>(
        &self,
        probe: &Probe<'_, 3>,
        init: A,
        mut visit: impl FnMut(A, [u32; 3], Range<usize>) -> A,
    ) -> A {
        let mut acc = init;
        let g = &self.grid;
        let (p, reach) = (probe.p, probe.reach);
        let edge = p.map(|x| x.wrapping_sub(reach) as u32);
        let runs = |c: usize| {
            let x = i64::from(p[c]);
            let reach = i64::from(reach);
            g.runs(c, g.cube(c, x - reach), g.cube(c, x + reach))
        };
        let ((xs, nx), (ys, ny), (zs, nz)) = (runs(0), runs(1), runs(2));
        let (xs, ys, zs) = (&xs[..nx.min(2)], &ys[..ny.min(2)], &zs[..nz.min(2)]);
        let [ma, mb] = [g.modulus[0].get(), g.modulus[1].get()];
        for &(z, nz) in zs {
            for z in z..z + nz {
                for &(y, ny) in ys {
                    for y in y..y + ny {
                        let row = (z * mb + y) * ma;
                        for &(x, nx) in xs {
                            let first = (row + x) as usize;
                            let (Some(&start), Some(&end)) = (
                                self.offsets.get(first),
                                self.offsets.get(first + nx as usize),
                            ) else {
                                continue;
                            };
                            acc = visit(acc, edge, start as usize..end as usize);
                        }
                    }
                }
            }
        }
        acc
    }

    /// q − `edge` on each axis: no subtraction first. Points lie on the
    /// mesh, within ±2^26 (Q16), so r − 1 − d stays in (−2^27, 2^31 +
    /// 2^27): exact in wrapping u32.
    #[inline(always)]
    fn offsets(
        &self,
        probe: &Probe<'_, 3>,
        edge: [u32; 3],
        q: [i32; 3],
    ) -> Option<([i64; 3], i64)> {
        let offset = |axis: usize| (q[axis] as u32).wrapping_sub(edge[axis]);
        // |dx| ≥ r: beyond the radius whatever dy and dz are.
        let ox = offset(0);
        if !probe.reaches(ox) {
            return None;
        }
        let oy = offset(1);
        if !probe.reaches(oy) {
            return None;
        }
        let oz = offset(2);
        if !probe.reaches(oz) {
            return None;
        }
        // Axis by axis, not by `map`: at opt-level "s" that stays a loop
        // through memory, and the squares below lose that d fits an i32.
        let (dx, dy, dz) = (
            probe.displacement(ox),
            probe.displacement(oy),
            probe.displacement(oz),
        );
        let d2 = dx * dx + dy * dy + dz * dz; // < 3·r², Q32
        (d2 < probe.r2).then_some(([dx, dy, dz], d2))
    }
}

/// Takes the snapshot of one step over the first `n` cells: plans the
/// grid, sorts the points into it.
pub fn snapshot<'s>(
    cells: &'s mut CellSlices<'_, OnMesh>,
    n: usize,
    forces: &'s SurfaceForces<'s>,
) -> (Snapshot<'s>, &'s mut [Place], &'s mut [[i32; 3]]) {
    let grid = CubeGrid::plan(
        forces.mesh,
        forces.radius,
        cells.bins.len().saturating_sub(1),
    );
    grid.build(
        &cells.pos[..n],
        &mut cells.order[..n],
        cells.bins,
        &mut cells.sorted[..n],
    );
    let snapshot = sorted_snapshot(
        grid,
        &cells.order[..n],
        &cells.sorted[..n],
        cells.bins,
        &cells.kind[..n],
        forces,
    );
    let velocity = match cells.velocity.get_mut(..n) {
        Some(v) => v,
        None => &mut [],
    };
    (snapshot, &mut cells.pos[..n], velocity)
}

/// [`snapshot`] of cells the caller has sorted into `grid`'s buckets
/// (planned for `forces`, at most `offsets.len() − 1` buckets): each
/// slot's cell index in `order`, its point in `sorted`, each bucket's
/// first slot in `offsets` (and the cells' number after the last), as a
/// computer that keeps its cells in bucket order between steps does.
#[must_use]
pub fn sorted_snapshot<'s>(
    grid: CubeGrid,
    order: &'s [u32],
    sorted: &'s [[i32; 3]],
    offsets: &'s [u32],
    kind: &'s [u8],
    forces: &'s SurfaceForces<'s>,
) -> Snapshot<'s> {
    let buckets = grid.buckets().min(offsets.len().saturating_sub(1));
    Snapshot {
        scan: Scan {
            sorted,
            order,
            kind,
            repel: &forces.repel,
            radius: forces.radius,
        },
        bins: CubeBins {
            grid,
            offsets: &offsets[..=buckets],
        },
        forces,
    }
}

/// A triangle mesh: its cells [`Place`]s on the faces, found through a
/// grid of cubes ([`CubeGrid`]), pushed in their tangent planes and walked
/// along the surface ([`Mesh::walk`]).
#[derive(Clone, Copy, Debug)]
pub struct OnMesh;

impl Ground for OnMesh {
    type At = Place;
    type Point = [i32; 3];
    type Forces<'f> = SurfaceForces<'f>;
    const NO_PLACE: Place = Place { face: 0, p: [0; 3] };
    const ZERO: [i32; 3] = [0; 3];
    const NAME: &'static str = "OnMesh";

    fn relax_step(cells: &mut CellSlices<'_, OnMesh>, n: usize, forces: &SurfaceForces<'_>) {
        relax(cells, n, forces);
    }
}

/// One relaxation step over the first `n` cells, one after another.
pub fn relax(cells: &mut CellSlices<'_, OnMesh>, n: usize, forces: &SurfaceForces<'_>) {
    let (snapshot, places, velocity) = snapshot(cells, n, forces);
    for slot in 0..snapshot.len() {
        let i = snapshot.cell(slot);
        let last = velocity.get(i).copied().unwrap_or([0; 3]);
        let sum = snapshot.scan.pushes(&snapshot.bins, slot);
        let (to, step) = snapshot.moved_by(sum, places[i], last);
        places[i] = to;
        if let Some(v) = velocity.get_mut(i) {
            *v = step;
        }
    }
}

/// One relaxation step over the first `n` cells, each pair of neighbours
/// found once ([`Snapshot::pair_sums`]) with the pushes summed in `sums`
/// (one per cell, 24 B, which a computer has and an MCU's store does not;
/// fewer than `n`: as [`relax`]). The same places as [`relax`].
pub fn relax_pairs(
    cells: &mut CellSlices<'_, OnMesh>,
    n: usize,
    forces: &SurfaceForces<'_>,
    sums: &mut [[i64; 3]],
) {
    let Some(sums) = sums.get_mut(..n) else {
        relax(cells, n, forces);
        return;
    };
    let (snapshot, places, velocity) = snapshot(cells, n, forces);
    sums.fill([0; 3]);
    // Every later slot's sum is in `sums`: nothing goes beyond.
    snapshot.pair_sums(0..n, sums, &mut |_, _| {});
    for (sum, &i) in sums.iter().zip(snapshot.scan.order) {
        let i = i as usize;
        let Some(place) = places.get_mut(i) else {
            continue;
        };
        let last = velocity.get(i).copied().unwrap_or([0; 3]);
        let (to, step) = snapshot.moved_by(*sum, *place, last);
        *place = to;
        if let Some(v) = velocity.get_mut(i) {
            *v = step;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fx::Fx;
    use crate::mosaic::force;
    use crate::mosaic::mesh::{MeshParts, Place};
    use crate::mosaic::shapes::{Shape, Tessellation};
    use crate::mosaic::store::{ArrayStore, CellStore};
    use crate::rng::KeyedRng;

    /// Calls `test` with a ribbed stem's mesh and a store of 600 cells
    /// placed at random on it, of types 0 and 1 in turn.
    fn on_a_stem(test: impl FnOnce(&Mesh<'_>, &mut ArrayStore<600, 97, OnMesh>)) {
        let t = Tessellation {
            shape: Shape::Stem {
                radius: Fx::from_int(4),
                length: Fx::from_int(12),
                ribs: 6,
                depth: Fx::from_ratio(1, 8),
            },
            rings: 16,
            segments: 48,
        };
        let (nv, nf) = t.counts();
        let (mut v, mut f) = (vec![[0; 3]; nv], vec![[0; 3]; nf]);
        t.build(&mut v, &mut f);
        let (mut nb, mut normals, mut edges) =
            (vec![[0; 3]; nf], vec![[0; 3]; nf], vec![0; 3 * nf]);
        let mut inward = vec![[[0; 3]; 3]; nf];
        let parts = MeshParts {
            neighbours: &mut nb,
            normals: &mut normals,
            inward: &mut inward,
            edges: &mut edges,
        };
        let mesh = Mesh::new_checked(&v, &f, parts).unwrap();
        let mut store = <ArrayStore<600, 97, OnMesh>>::EMPTY;
        let mut rng = KeyedRng::new(5, 1);
        {
            let cells = store.slices();
            for i in 0..600 {
                let face = rng.below(nf as u32);
                let (a, b) = (i64::from(rng.below(1 << 15)), i64::from(rng.below(1 << 15)));
                cells.pos[i] = Place {
                    face,
                    p: mesh.at(face, [(1 << 16) - a - b, a, b]),
                };
                cells.kind[i] = (i % 2) as u8;
            }
        }
        test(&mesh, &mut store);
    }

    #[test]
    fn pairs_found_once_move_cells_as_the_per_cell_step_does() {
        // As on the plane: each pair's pushes from its lower slot, both
        // floors from one product, give the per-cell step's places, with a
        // repulsion that is not symmetric (a swapped pair would show), a
        // child on its parent and radii of 3 (squares past 32 bits) and ½.
        for radius in [3 << 16, 1 << 15] {
            on_a_stem(|mesh, store| {
                let n = 600;
                store.slices().pos[n - 1] = store.positions()[0];
                let mut other = <ArrayStore<600, 97, OnMesh>>::EMPTY;
                {
                    let (copy, cells) = (other.slices(), store.slices());
                    copy.pos.copy_from_slice(cells.pos);
                    copy.kind.copy_from_slice(cells.kind);
                }
                let forces = SurfaceForces {
                    mesh,
                    radius,
                    repel: [
                        [1 << 16, 3 << 16, 0, 0],
                        [1 << 15, 1 << 16, 0, 0],
                        [0; 4],
                        [0; 4],
                    ],
                    push_weight: 1 << 15,
                    anisotropy_weight: 0,
                    field: None,
                    momentum: 0,
                };
                let mut sums = vec![[0i64; 3]; n];
                for step in 0..3 {
                    let before = store.positions()[..n].to_vec();
                    relax(&mut store.slices(), n, &forces);
                    relax_pairs(&mut other.slices(), n, &forces, &mut sums);
                    assert_eq!(
                        store.positions()[..n],
                        other.positions()[..n],
                        "r {radius} step {step}"
                    );
                    assert_ne!(store.positions()[..n], before[..], "the cells move");
                }
            });
        }
    }

    #[test]
    fn shares_of_the_slots_and_their_spills_give_the_sums_of_one_pass() {
        // As on the plane: any split of the slots into shares, with the
        // pushes past each share's end added after, gives one pass's sums.
        on_a_stem(|mesh, store| {
            let n = 600;
            let forces = SurfaceForces {
                mesh,
                radius: 1 << 16,
                repel: [[1 << 16; 4]; 4],
                push_weight: 1 << 15,
                anisotropy_weight: 0,
                field: None,
                momentum: 0,
            };
            let mut cells = store.slices();
            let (snapshot, _, _) = snapshot(&mut cells, n, &forces);
            let mut whole = vec![[0i64; 3]; n];
            snapshot.pair_sums(0..n, &mut whole, &mut |slot, _| panic!("slot {slot}"));
            assert!(whole.iter().filter(|s| **s != [0; 3]).count() > n / 2);
            for shares in [2, 5, n] {
                let share = n.div_ceil(shares);
                let mut sums = vec![[0i64; 3]; n];
                let mut spilt = Vec::new();
                for (k, part) in sums.chunks_mut(share).enumerate() {
                    let first = k * share;
                    snapshot.pair_sums(first..first + part.len(), part, &mut |slot, push| {
                        spilt.push((slot, push));
                    });
                }
                assert!(!spilt.is_empty(), "pairs across shares");
                for (slot, push) in spilt {
                    sums[slot] = per_axis(|c| sums[slot][c] + push[c]);
                }
                assert_eq!(sums, whole, "{shares} shares");
            }
        });
    }

    #[test]
    fn the_cube_grid_finds_every_neighbour() {
        on_a_stem(|mesh, store| {
            let n = 600;
            let forces = SurfaceForces {
                mesh,
                radius: 3 << 16,
                repel: [
                    [1 << 16, 3 << 16, 0, 0],
                    [3 << 16, 1 << 16, 0, 0],
                    [0; 4],
                    [0; 4],
                ],
                push_weight: 1 << 16,
                anisotropy_weight: 0,
                field: None,
                momentum: 0,
            };
            let places: Vec<Place> = store.positions()[..n].to_vec();
            let mut cells = store.slices();
            let (snapshot, _, _) = snapshot(&mut cells, n, &forces);
            let r = i64::from(forces.radius);
            for slot in 0..n {
                let i = snapshot.cell(slot);
                let mut naive = [0i64; 3];
                for (j, q) in places.iter().enumerate() {
                    let d = [0, 1, 2].map(|c| i64::from(places[i].p[c]) - i64::from(q.p[c]));
                    let d2 = d.iter().map(|x| x * x).sum::<i64>();
                    if j == i || d2 >= r * r {
                        continue;
                    }
                    let repel = i64::from(forces.repel[i % 2][j % 2]);
                    let f = force::push(i, j, d, d2, r, repel);
                    naive = [0, 1, 2].map(|c| naive[c] + f[c]);
                }
                let sum = snapshot.scan.pushes(&snapshot.bins, slot);
                assert_eq!(sum, naive, "cell {i}");
            }
        });
    }
}
