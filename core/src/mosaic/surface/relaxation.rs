//! Relaxation on a surface: the plane's pushes
//! ρ_pq·(r − d)·(p − q)/d by 3D distance d < r
//! ([`crate::mosaic::relaxation`]), summed over the neighbours a hashed
//! grid finds, blended with the anisotropy field of the cell's face
//! (w_a) and scaled by w_d as on the plane, taken into the cell's tangent
//! plane and walked along the mesh ([`Mesh::walk`]). A Jacobi step on integer sums:
//! the same result in any order.
//!
//! The grid bins space into cubes at least r wide, so a cell's neighbours
//! lie in the (at most 27) cubes its sphere of radius r touches; a cube is
//! hashed to one of a fixed number of buckets (a surface fills few of
//! them), so memory stays bounded whatever the mesh's size. Cells of other
//! cubes that share a bucket are rejected by distance.

use crate::fx::root::{isqrt_u32, isqrt_u64};
use crate::mosaic::mesh::{Mesh, Place};
use crate::mosaic::params::MAX_TYPES;

use super::store::SurfaceSlices;

/// Q16 one.
const ONE: i64 = 1 << 16;

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

/// Cubes of side ≥ r hashed to buckets.
#[derive(Clone, Copy, Debug)]
pub struct HashGrid {
    origin: [i32; 3],
    /// 2^32 / side.
    scale: u64,
    buckets: u32,
}

impl HashGrid {
    /// A grid for radius `radius` over the mesh with `buckets` buckets.
    #[must_use]
    pub fn plan(mesh: &Mesh<'_>, radius: i32, buckets: usize) -> HashGrid {
        let r = i64::from(radius.max(1));
        let side = (r + (r >> 6) + 1) as u64;
        HashGrid {
            origin: mesh.bounds()[0],
            scale: (1u64 << 32) / side,
            buckets: buckets.clamp(1, u32::MAX as usize) as u32,
        }
    }

    /// The cube index of `x` along axis `c` (0 below the origin).
    #[inline]
    fn cube(&self, c: usize, x: i64) -> u32 {
        let off = (x - i64::from(self.origin[c])).max(0) as u64;
        ((off * self.scale) >> 32) as u32
    }

    /// The bucket of cube `(x, y, z)`.
    #[inline]
    fn bucket(&self, x: u32, y: u32, z: u32) -> usize {
        let mut h =
            x.wrapping_mul(0x9E37_79B1) ^ y.wrapping_mul(0x85EB_CA77) ^ z.wrapping_mul(0xC2B2_AE3D);
        h ^= h >> 15;
        h = h.wrapping_mul(0x2C1B_3C6D);
        h ^= h >> 12;
        ((u64::from(h) * u64::from(self.buckets)) >> 32) as usize
    }

    #[inline]
    fn bucket_of(&self, p: [i32; 3]) -> usize {
        let [x, y, z] = [0, 1, 2].map(|c| self.cube(c, i64::from(p[c])));
        self.bucket(x, y, z)
    }

    /// Counting-sorts the `places` into `order` and their points into
    /// `sorted` by bucket; `offsets` ends as each bucket's first slot (and
    /// one past the last).
    pub fn build(
        &self,
        places: &[Place],
        order: &mut [u32],
        offsets: &mut [u32],
        sorted: &mut [[i32; 3]],
    ) {
        let b = self.buckets as usize;
        let offsets = &mut offsets[..=b];
        offsets.fill(0);
        for at in places {
            offsets[self.bucket_of(at.p) + 1] += 1;
        }
        for k in 1..=b {
            offsets[k] += offsets[k - 1];
        }
        for (i, at) in places.iter().enumerate() {
            let k = self.bucket_of(at.p);
            let slot = offsets[k] as usize;
            offsets[k] += 1;
            if let (Some(o), Some(s)) = (order.get_mut(slot), sorted.get_mut(slot)) {
                *o = i as u32;
                *s = at.p;
            }
        }
        // Each entry now ends its bucket: move them one on.
        offsets.copy_within(0..b, 1);
        offsets[0] = 0;
    }
}

/// What one step reads: the points in bucket order, the grid, the forces.
#[derive(Debug)]
pub struct Snapshot<'s> {
    sorted: &'s [[i32; 3]],
    order: &'s [u32],
    offsets: &'s [u32],
    kind: &'s [u8],
    grid: HashGrid,
    forces: &'s SurfaceForces<'s>,
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

    /// The index of the cell in slot `slot`.
    #[must_use]
    pub fn cell(&self, slot: usize) -> usize {
        self.order[slot] as usize
    }

    fn kind_of(&self, i: usize) -> usize {
        self.kind.get(i).map_or(0, |&k| k as usize % MAX_TYPES)
    }

    /// The sum of the pushes (Q32) on the cell in slot `slot`.
    fn pushes(&self, slot: usize) -> [i64; 3] {
        let mut sum = [0i64; 3];
        let Some(&p) = self.sorted.get(slot) else {
            return sum;
        };
        let i = self.cell(slot);
        let r = i64::from(self.forces.radius);
        let r2 = r * r;
        let repel = &self.forces.repel[self.kind_of(i)];
        let g = &self.grid;
        let span =
            |c: usize| g.cube(c, i64::from(p[c]) - r + 1)..=g.cube(c, i64::from(p[c]) + r - 1);
        let mut seen = [usize::MAX; 27];
        let mut count = 0;
        for z in span(2) {
            for y in span(1) {
                for x in span(0) {
                    let b = g.bucket(x, y, z);
                    if seen[..count].contains(&b) {
                        continue;
                    }
                    if let Some(s) = seen.get_mut(count) {
                        *s = b;
                        count += 1;
                    }
                    let run = self.offsets.get(b).map_or(0, |&o| o as usize)
                        ..self.offsets.get(b + 1).map_or(0, |&o| o as usize);
                    let (Some(points), Some(ids)) =
                        (self.sorted.get(run.clone()), self.order.get(run))
                    else {
                        continue;
                    };
                    for (q, &j) in points.iter().zip(ids) {
                        let d = [0, 1, 2].map(|c| i64::from(p[c]) - i64::from(q[c]));
                        if d.iter().any(|x| x.abs() >= r) {
                            continue;
                        }
                        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        let j = j as usize;
                        if d2 >= r2 || j == i {
                            continue;
                        }
                        let f = push(i, j, d, d2, r, i64::from(repel[self.kind_of(j)]));
                        sum = [0, 1, 2].map(|c| sum[c] + f[c]);
                    }
                }
            }
        }
        sum
    }

    /// The new place of the cell in slot `slot`, which was at `from` and
    /// last moved by `last` (zero without momentum), and the move it made.
    #[must_use]
    pub fn moved(&self, slot: usize, from: Place, last: [i32; 3]) -> (Place, [i32; 3]) {
        let sum = self.pushes(slot);
        let forces = self.forces;
        let r = i64::from(forces.radius);
        let (wd, beta) = (i64::from(forces.push_weight), i64::from(forces.momentum));
        let wa = i64::from(forces.anisotropy_weight);
        let v = forces
            .field
            .and_then(|f| f.get(from.face as usize))
            .copied()
            .unwrap_or([0; 3]);
        let s = sum.map(|x| (x + (ONE >> 1)) >> 16); // Q16
        // (Σ·v)·v as on the plane ([`crate::mosaic::relaxation`]).
        let along = (0..3).map(|c| s[c] * i64::from(v[c])).sum::<i64>() >> 14;
        let d = [0, 1, 2].map(|c| {
            let steer = (along * i64::from(v[c])) >> 14;
            let blend = ((ONE - wa) * s[c] + wa * steer + (ONE >> 1)) >> 16;
            let push = ((wd * blend + (ONE >> 1)) >> 16).max(-r).min(r);
            let carry = (beta * i64::from(last[c]) + (ONE >> 1)) >> 16;
            (push + carry).max(-r).min(r)
        });
        let to = forces.mesh.walk(from, d);
        let step = [0, 1, 2].map(|c| to.p[c].wrapping_sub(from.p[c]));
        (to, step)
    }
}

/// The push on cell `i` of cell `j` displaced by `d` (Q16) from it, at
/// squared distance `d2` < r² (Q32): ρ·(r − d)·d⃗/d as Q32.
#[inline]
fn push(i: usize, j: usize, d: [i64; 3], d2: i64, r: i64, repel: i64) -> [i64; 3] {
    if d2 == 0 {
        // Coincident cells: apart along x, the lower index towards −x.
        let s = if i < j { -1 } else { 1 };
        return [s * repel * r, 0, 0];
    }
    let dist = match u32::try_from(d2) {
        Ok(d2) => i64::from(isqrt_u32(d2)),
        Err(_) => isqrt_u64(d2 as u64) as i64,
    };
    let dist = dist.max(1);
    let k = ((r - dist) << 16) / dist;
    d.map(|x| ((k * x) >> 16) * repel)
}

/// Takes the snapshot of one step over the first `n` cells: plans the
/// grid, sorts the points into it.
pub fn snapshot<'s>(
    cells: &'s mut SurfaceSlices<'_>,
    n: usize,
    forces: &'s SurfaceForces<'s>,
) -> (Snapshot<'s>, &'s mut [Place], &'s mut [[i32; 3]]) {
    let buckets = cells.buckets.len().saturating_sub(1).max(1);
    let grid = HashGrid::plan(forces.mesh, forces.radius, buckets);
    grid.build(
        &cells.place[..n],
        &mut cells.order[..n],
        cells.buckets,
        &mut cells.sorted[..n],
    );
    let snapshot = Snapshot {
        sorted: &cells.sorted[..n],
        order: &cells.order[..n],
        offsets: &cells.buckets[..=buckets],
        kind: &cells.kind[..n],
        grid,
        forces,
    };
    let velocity = match cells.velocity.get_mut(..n) {
        Some(v) => v,
        None => &mut [],
    };
    (snapshot, &mut cells.place[..n], velocity)
}

/// One relaxation step over the first `n` cells, one after another.
pub fn relax(cells: &mut SurfaceSlices<'_>, n: usize, forces: &SurfaceForces<'_>) {
    let (snapshot, places, velocity) = snapshot(cells, n, forces);
    for slot in 0..snapshot.len() {
        let i = snapshot.cell(slot);
        let last = velocity.get(i).copied().unwrap_or([0; 3]);
        let (to, step) = snapshot.moved(slot, places[i], last);
        places[i] = to;
        if let Some(v) = velocity.get_mut(i) {
            *v = step;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fx::Fx;
    use crate::mosaic::mesh::{MeshParts, Place};
    use crate::mosaic::shapes::{Shape, Tessellation};
    use crate::mosaic::surface::store::{ArraySurfaceStore, SurfaceStore};
    use crate::rng::KeyedRng;

    #[test]
    fn the_hashed_grid_finds_every_neighbour() {
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
        let parts = MeshParts {
            neighbours: &mut nb,
            normals: &mut normals,
            edges: &mut edges,
        };
        let mesh = Mesh::new_checked(&v, &f, parts).unwrap();
        let mut store = ArraySurfaceStore::<600, 97>::EMPTY;
        let n = 600;
        let mut rng = KeyedRng::new(5, 1);
        {
            let cells = store.slices();
            for i in 0..n {
                let face = rng.below(nf as u32);
                let (a, b) = (i64::from(rng.below(1 << 15)), i64::from(rng.below(1 << 15)));
                cells.place[i] = Place {
                    face,
                    p: mesh.at(face, [(1 << 16) - a - b, a, b]),
                };
                cells.kind[i] = (i % 2) as u8;
            }
        }
        let forces = SurfaceForces {
            mesh: &mesh,
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
        let places: Vec<Place> = store.places()[..n].to_vec();
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
                let f = push(i, j, d, d2, r, repel);
                naive = [0, 1, 2].map(|c| naive[c] + f[c]);
            }
            assert_eq!(snapshot.pushes(slot), naive, "cell {i}");
        }
    }
}
