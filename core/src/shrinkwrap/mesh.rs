//! The shrinkwrap mesh: a closed triangle mesh in fixed-capacity buffers,
//! started as a UV sphere (bones paper, Sec. 5: m meridians, a multiple of
//! 4, p parallels, odd, m·p + 2 vertices) and refined only by splitting
//! edges at their midpoints (Sec. 5, "adaptive triangulation").
//!
//! Both operations keep it a closed, consistently wound 2-manifold of genus
//! 0: the sphere is one, and an edge split inserts its midpoint into both
//! triangles of the edge.

use heapless::Vec;
use nalgebra::Vector3;

use crate::Error;
use crate::fx::{Angle, Real};

use super::ShrinkwrapError;

/// A vertex index.
pub type VertexId = u16;

/// A closed triangle mesh of at most `V` vertices and `T` triangles
/// (a closed genus-0 mesh of v vertices has 2v − 4 triangles).
#[derive(Debug)]
pub struct Mesh<R: Real, const V: usize, const T: usize> {
    vertices: Vec<Vector3<R>, V>,
    triangles: Vec<[VertexId; 3], T>,
    /// The edges split by the current [`Mesh::refine`] pass: (edge key,
    /// midpoint), sorted by key before the triangles are cut.
    splits: Vec<(u32, VertexId), V>,
}

/// The key of the undirected edge `a`–`b`.
fn edge_key(a: VertexId, b: VertexId) -> u32 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    (lo as u32) << 16 | hi as u32
}

/// The vertices that end a split edge of a [`Mesh::refine`] pass, as a
/// 256-bit filter on the low byte of their id: an edge with an end
/// outside it was not split, which spares most edges of the pass the
/// binary search of the splits (a pass splits a few dozen edges of
/// thousands). 32 B of stack.
struct SplitEnds([u32; 8]);

impl SplitEnds {
    fn add(&mut self, v: VertexId) {
        // (v >> 5) & 7 < 8: no bounds check, no panic.
        self.0[usize::from(v >> 5) & 7] |= 1 << (v & 31);
    }

    /// False only for a vertex that ends no split edge.
    fn may_hold(&self, v: VertexId) -> bool {
        self.0[usize::from(v >> 5) & 7] & (1 << (v & 31)) != 0
    }
}

/// Sorts `splits` by edge key, in place, with a heapsort: a few hundred
/// bytes of code where `sort_unstable` brings some 5 KB to the firmware.
/// The keys are distinct (each edge is split at most once per pass), so
/// the order is the one every sort gives.
fn sort_by_edge(splits: &mut [(u32, VertexId)]) {
    /// Moves `splits[root]` down the max-heap `splits[..end]`.
    fn sift_down(splits: &mut [(u32, VertexId)], mut root: usize, end: usize) {
        loop {
            // root < end ≤ V ≤ 2¹⁶: no overflow.
            let mut child = 2 * root + 1;
            if child >= end {
                return;
            }
            if child + 1 < end && splits[child].0 < splits[child + 1].0 {
                child += 1;
            }
            if splits[root].0 >= splits[child].0 {
                return;
            }
            splits.swap(root, child);
            root = child;
        }
    }
    let n = splits.len();
    for root in (0..n / 2).rev() {
        sift_down(splits, root, n);
    }
    for end in (1..n).rev() {
        splits.swap(0, end);
        sift_down(splits, 0, end);
    }
}

impl<R: Real, const V: usize, const T: usize> Mesh<R, V, T> {
    /// Vertex ids are `u16`.
    const FITS: () = assert!(V <= 1 << 16, "vertex ids are u16");

    /// An empty mesh (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Mesh<R, V, T> {
        let () = Self::FITS;
        Mesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
            splits: Vec::new(),
        }
    }

    /// The vertex positions.
    #[must_use]
    pub fn vertices(&self) -> &[Vector3<R>] {
        &self.vertices
    }

    /// The vertex positions, to move them (the topology stays).
    pub fn vertices_mut(&mut self) -> &mut [Vector3<R>] {
        &mut self.vertices
    }

    /// The triangles, counter-clockwise seen from outside.
    #[must_use]
    pub fn triangles(&self) -> &[[VertexId; 3]] {
        &self.triangles
    }

    fn push_vertex(&mut self, p: Vector3<R>) -> Result<VertexId, Error> {
        let id = self.vertices.len() as VertexId;
        self.vertices.push(p).map_err(|_| Error::Capacity {
            limit: "shrinkwrap mesh vertices (V)",
            capacity: V as u32,
        })?;
        Ok(id)
    }

    fn push_triangle(&mut self, t: [VertexId; 3]) -> Result<(), Error> {
        self.triangles.push(t).map_err(|_| Error::Capacity {
            limit: "shrinkwrap mesh triangles (T)",
            capacity: T as u32,
        })
    }

    /// Replaces the mesh by a UV sphere around `centre`: the poles on the
    /// y axis (vertices 0 and m·p + 1), parallel j (1..=p) at polar angle
    /// j·180°/(p + 1), meridian i at azimuth i·360°/m.
    ///
    /// # Errors
    /// [`ShrinkwrapError::Sphere`] unless m is a positive multiple of 4 and
    /// p is odd; a capacity when m·p + 2 vertices do not fit.
    pub fn sphere(
        &mut self,
        centre: Vector3<R>,
        radius: R,
        meridians: u8,
        parallels: u8,
    ) -> Result<(), Error> {
        let (m, p) = (meridians as u16, parallels as u16);
        if m == 0 || m % 4 != 0 || p % 2 == 0 {
            return Err(ShrinkwrapError::Sphere {
                meridians,
                parallels,
            }
            .into());
        }
        self.vertices.clear();
        self.triangles.clear();
        self.push_vertex(centre + Vector3::new(R::zero(), radius, R::zero()))?;
        for j in 1..=p {
            let polar = Angle::from_turn_ratio(j as i64, 2 * (p as i64 + 1));
            let (ring, y) = (radius * R::sin(polar), radius * R::cos(polar));
            for i in 0..m {
                let azimuth = Angle::from_turn_ratio(i as i64, m as i64);
                let offset = Vector3::new(ring * R::cos(azimuth), y, ring * R::sin(azimuth));
                self.push_vertex(centre + offset)?;
            }
        }
        let south = self.push_vertex(centre - Vector3::new(R::zero(), radius, R::zero()))?;
        let at = |j: u16, i: u16| 1 + (j - 1) * m + i % m;
        for i in 0..m {
            self.push_triangle([0, at(1, i + 1), at(1, i)])?;
            for j in 1..p {
                let (a, b) = (at(j, i), at(j, i + 1));
                let (c, d) = (at(j + 1, i), at(j + 1, i + 1));
                self.push_triangle([a, d, c])?;
                self.push_triangle([a, b, d])?;
            }
            self.push_triangle([at(p, i), at(p, i + 1), south])?;
        }
        Ok(())
    }

    /// The midpoint inserted into edge `a`–`b` by this pass, if any;
    /// `ends` holds the ends of the split edges ([`SplitEnds`]).
    fn midpoint(&self, ends: &SplitEnds, a: VertexId, b: VertexId) -> Option<VertexId> {
        if !ends.may_hold(a) || !ends.may_hold(b) {
            return None;
        }
        let key = edge_key(a, b);
        self.splits
            .binary_search_by_key(&key, |s| s.0)
            .ok()
            .and_then(|k| self.splits.get(k))
            .map(|s| s.1)
    }

    /// One adaptive-triangulation pass: `split(a, pa, b, pb)` is asked once
    /// for every edge a–b (in triangle order; `pa`, `pb` the positions) and
    /// returns the new vertex to insert into it, if the edge must be split; then every triangle with split
    /// edges is cut into 2, 3 or 4, keeping its winding. Returns the number
    /// of edges split.
    ///
    /// # Errors
    /// A capacity (the mesh is then unchanged in topology but may hold
    /// unused vertices).
    pub fn refine(
        &mut self,
        mut split: impl FnMut(VertexId, &Vector3<R>, VertexId, &Vector3<R>) -> Option<Vector3<R>>,
    ) -> Result<usize, Error> {
        self.splits.clear();
        let count = self.triangles.len();
        for t in 0..count {
            let tri = self.triangles[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                // Each edge is a < b in exactly one of its two triangles.
                if a > b {
                    continue;
                }
                let (pa, pb) = (self.vertices[a as usize], self.vertices[b as usize]);
                if let Some(p) = split(a, &pa, b, &pb) {
                    let mid = self.push_vertex(p)?;
                    // As many splits as new vertices: this cannot fail.
                    let _ = self.splits.push((edge_key(a, b), mid));
                }
            }
        }
        if self.splits.is_empty() {
            return Ok(0);
        }
        sort_by_edge(&mut self.splits);
        let mut ends = SplitEnds([0; 8]);
        for &(key, _) in &self.splits {
            ends.add((key >> 16) as VertexId);
            ends.add(key as VertexId); // the low half: hi
        }
        for t in 0..count {
            self.cut(&ends, t)?;
        }
        Ok(self.splits.len())
    }

    /// Cuts triangle `t` along the midpoints of its split edges.
    fn cut(&mut self, ends: &SplitEnds, t: usize) -> Result<(), Error> {
        let v = self.triangles[t];
        let m = [
            self.midpoint(ends, v[0], v[1]),
            self.midpoint(ends, v[1], v[2]),
            self.midpoint(ends, v[2], v[0]),
        ];
        let children: [Option<[VertexId; 3]>; 4] = match m {
            [None, None, None] => return Ok(()),
            [Some(m0), Some(m1), Some(m2)] => [
                Some([v[0], m0, m2]),
                Some([m0, v[1], m1]),
                Some([m2, m1, v[2]]),
                Some([m0, m1, m2]),
            ],
            _ => {
                let split = m.iter().filter(|x| x.is_some()).count();
                // Rotate so that edge 0 (v0–v1) is split, and for two
                // splits edge 1 (v1–v2) too.
                let r = (0..3)
                    .find(|&r| m[r].is_some() && (split == 1 || m[(r + 1) % 3].is_some()))
                    .unwrap_or(0);
                let (v0, v1, v2) = (v[r], v[(r + 1) % 3], v[(r + 2) % 3]);
                match (m[r], m[(r + 1) % 3]) {
                    (Some(m0), Some(m1)) => {
                        // A corner and a quad v0 m0 m1 v2, cut along its
                        // shorter diagonal.
                        let p = |i: VertexId| self.vertices[i as usize];
                        let (d0, d1) = (p(v0) - p(m1), p(m0) - p(v2));
                        let quad = if R::dot(&d0, &d0) <= R::dot(&d1, &d1) {
                            [[v0, m0, m1], [v0, m1, v2]]
                        } else {
                            [[v0, m0, v2], [m0, m1, v2]]
                        };
                        [Some(quad[0]), Some([m0, v1, m1]), Some(quad[1]), None]
                    }
                    (Some(m0), None) => [Some([v0, m0, v2]), Some([m0, v1, v2]), None, None],
                    _ => return Ok(()),
                }
            }
        };
        let mut first = true;
        for c in children.into_iter().flatten() {
            if first {
                self.triangles[t] = c;
                first = false;
            } else {
                self.push_triangle(c)?;
            }
        }
        Ok(())
    }
}

impl<R: Real, const V: usize, const T: usize> Default for Mesh<R, V, T> {
    fn default() -> Self {
        Mesh::new()
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
pub(crate) mod tests {
    use super::*;
    use std::collections::HashMap;

    /// The heapsort orders distinct keys as `sort_unstable` does, for
    /// every length up to 64 and shuffled, sorted and reversed inputs.
    #[test]
    fn sort_by_edge_sorts_like_sort_unstable() {
        let mut state = 0x9e37_79b9u32;
        for n in 0..=64u32 {
            let keys: std::vec::Vec<u32> = (0..n).map(|k| k * 7919 % 65_521 + k).collect();
            let mut orders = [keys.clone(), keys.clone(), keys];
            orders[1].sort_unstable();
            orders[2].sort_unstable_by(|a, b| b.cmp(a));
            for k in (1..orders[0].len()).rev() {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                orders[0].swap(k, (state >> 8) as usize % (k + 1));
            }
            for keys in orders {
                let mut splits: std::vec::Vec<(u32, VertexId)> =
                    keys.iter().map(|&k| (k, k as VertexId)).collect();
                let mut expected = splits.clone();
                expected.sort_unstable_by_key(|s| s.0);
                sort_by_edge(&mut splits);
                assert_eq!(splits, expected, "{n} keys");
            }
        }
    }

    /// Checks that `triangles` over `vertices` vertices form a closed,
    /// connected, consistently wound 2-manifold of genus 0: every directed
    /// edge once and its reverse once, V − E + F = 2. Returns E.
    pub(crate) fn assert_closed_genus_0(vertices: usize, triangles: &[[VertexId; 3]]) -> usize {
        let mut directed = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            assert!(
                tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0],
                "degenerate {t}"
            );
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                assert!(
                    directed.insert(e, t).is_none(),
                    "edge {e:?} twice in one direction"
                );
            }
        }
        for &(a, b) in directed.keys() {
            assert!(
                directed.contains_key(&(b, a)),
                "edge {a}-{b} has one triangle"
            );
        }
        // Connected: a flood fill over the edges reaches every vertex.
        let mut seen = vec![false; vertices];
        let mut stack = vec![0u16];
        let mut adjacency: HashMap<u16, std::vec::Vec<u16>> = HashMap::new();
        for &(a, b) in directed.keys() {
            adjacency.entry(a).or_default().push(b);
        }
        while let Some(v) = stack.pop() {
            if !std::mem::replace(&mut seen[v as usize], true) {
                stack.extend(adjacency.get(&v).into_iter().flatten());
            }
        }
        assert!(
            seen.iter().all(|&s| s),
            "mesh not connected (or unused vertices)"
        );
        let edges = directed.len() / 2;
        let euler = vertices as i64 - edges as i64 + triangles.len() as i64;
        assert_eq!(euler, 2, "V − E + F");
        edges
    }

    /// Outward winding: the signed volume is positive.
    pub(crate) fn signed_volume(vertices: &[Vector3<f64>], triangles: &[[VertexId; 3]]) -> f64 {
        triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| vertices[i as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn the_uv_sphere_has_m_p_plus_2_vertices_and_is_closed() {
        let mut mesh = Mesh::<f64, 256, 512>::new();
        mesh.sphere(Vector3::new(1.0, 2.0, 3.0), 2.0, 8, 5).unwrap();
        assert_eq!(mesh.vertices().len(), 8 * 5 + 2);
        assert_eq!(mesh.triangles().len(), 2 * 8 * 5);
        assert_closed_genus_0(mesh.vertices().len(), mesh.triangles());
        let centred: std::vec::Vec<_> = mesh
            .vertices()
            .iter()
            .map(|v| v - Vector3::new(1.0, 2.0, 3.0))
            .collect();
        let volume = signed_volume(&centred, mesh.triangles());
        // The inscribed polyhedron of a sphere of radius 2, seen outward.
        assert!(
            volume > 0.6 * 4.0 / 3.0 * std::f64::consts::PI * 8.0,
            "{volume}"
        );
        for v in &centred {
            assert!((<f64 as Real>::norm(v) - 2.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_bad_sphere_is_an_error() {
        let mut mesh = Mesh::<f64, 256, 512>::new();
        for (m, p) in [(6, 5), (8, 4), (0, 3)] {
            assert!(matches!(
                mesh.sphere(Vector3::zeros(), 1.0, m, p),
                Err(Error::Shrinkwrap(ShrinkwrapError::Sphere { .. }))
            ));
        }
    }

    #[test]
    fn any_pattern_of_splits_keeps_a_closed_consistent_manifold() {
        let mut mesh = Mesh::<f64, 4096, 8192>::new();
        mesh.sphere(Vector3::zeros(), 1.0, 4, 3).unwrap();
        // A deterministic pseudo-random choice of edges, over many passes.
        let mut state = 12345u32;
        for _ in 0..4 {
            mesh.refine(|_, a, _, b| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (state >> 30 != 0).then(|| {
                    let m = (a + b) / 2.0;
                    m / <f64 as Real>::norm(&m)
                })
            })
            .unwrap();
            assert_closed_genus_0(mesh.vertices().len(), mesh.triangles());
            assert!(signed_volume(mesh.vertices(), mesh.triangles()) > 0.0);
        }
        assert!(mesh.vertices().len() > 300, "{}", mesh.vertices().len());
    }

    #[test]
    fn a_full_mesh_is_an_error_naming_the_limit() {
        let mut mesh = Mesh::<f64, 20, 64>::new();
        mesh.sphere(Vector3::zeros(), 1.0, 4, 3).unwrap();
        let e = mesh.refine(|_, a, _, b| Some((a + b) / 2.0)).unwrap_err();
        assert!(matches!(e, Error::Capacity { limit, capacity: 20 } if limit.contains("vertices")));
    }
}
