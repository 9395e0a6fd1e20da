//! A triangle mesh the cells live on (thesis Sec. 3.2: MClone grows its
//! cells on the model's own polygons, so the pattern needs no texture
//! mapping). Vertices are Q16, faces index them; each face's neighbour
//! across each edge, its unit normal and its edges' inward normals are
//! found once, at the door ([`Mesh::new_checked`]). A cell is a [`Place`], a face and a point on
//! it; [`Mesh::walk`] moves it along the surface, unfolding the move about
//! each edge it crosses onto the neighbouring face, and slides it along a
//! boundary edge. Everything is integer: the same moves on every machine.

use crate::fx::root::isqrt_u64;

/// The largest |coordinate| of a vertex, in Q16 bits (512 units): edge
/// vectors stay below 2^26, their cross products below 2^53.
pub const MAX_COORD: i32 = 512 << 16;
/// The most vertices (20-bit indices in the edge keys).
pub const MAX_VERTICES: usize = 1 << 20;
/// The most faces (22-bit indices in the edge keys).
pub const MAX_FACES: usize = 1 << 22;
/// The neighbour of a face across a boundary edge.
pub const NO_FACE: u32 = u32::MAX;
/// The most edges one move crosses; a longer walk stops where it is.
pub const MAX_CROSSINGS: usize = 16;

/// Twice a face's area must be at least this (Q32, 2^-16 square units).
const MIN_DOUBLE_AREA: u64 = 1 << 16;

/// Why a mesh cannot carry cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum MeshError {
    /// No face.
    Empty,
    /// More vertices or faces than [`MAX_VERTICES`] / [`MAX_FACES`], or
    /// than the buffers given for them hold.
    TooLarge,
    /// A vertex coordinate beyond ±[`MAX_COORD`] (512 units).
    Coordinate {
        /// The vertex index.
        vertex: u32,
    },
    /// A face names a vertex that does not exist, or one vertex twice.
    Index {
        /// The face index.
        face: u32,
    },
    /// A face of (almost) no area.
    Degenerate {
        /// The face index.
        face: u32,
    },
    /// An edge shared by more than two faces.
    NonManifold {
        /// A face on that edge.
        face: u32,
    },
}

impl core::fmt::Display for MeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MeshError::Empty => f.write_str("the mesh has no triangle"),
            MeshError::TooLarge => write!(
                f,
                "the mesh has more than {MAX_VERTICES} vertices or {MAX_FACES} triangles (or than its buffers hold)"
            ),
            MeshError::Coordinate { vertex } => {
                write!(f, "vertex {vertex} lies beyond ±512 units")
            }
            MeshError::Index { face } => {
                write!(
                    f,
                    "triangle {face} names a missing vertex or one vertex twice"
                )
            }
            MeshError::Degenerate { face } => write!(f, "triangle {face} has no area"),
            MeshError::NonManifold { face } => {
                write!(
                    f,
                    "an edge of triangle {face} is shared by more than two triangles"
                )
            }
        }
    }
}

impl core::error::Error for MeshError {}

/// The buffers a [`Mesh`] fills: one entry per face in `neighbours`,
/// `normals` and `inward`, three per face in `edges` (scratch for the edge
/// sort). `inward` and `edges` may be empty, as on the MCU (60 B a face
/// saved): the inward normals are then worked out where a walk needs them
/// (the same bits), and the neighbours are found by comparing every edge
/// with every other (quadratic: for meshes of a few hundred faces).
#[derive(Debug)]
pub struct MeshParts<'m> {
    /// The face across each edge (edge k runs from vertex k to k + 1), or
    /// [`NO_FACE`].
    pub neighbours: &'m mut [[u32; 3]],
    /// Unit normals, Q16.
    pub normals: &'m mut [[i32; 3]],
    /// Each edge turned a quarter turn about the normal, into the face
    /// (Q16, as long as the edge): what [`Mesh::walk`] measures the way
    /// out against.
    pub inward: &'m mut [[[i32; 3]; 3]],
    /// Scratch: edge keys.
    pub edges: &'m mut [u64],
}

/// What [`Mesh::new_checked`] found besides the arrays it filled: the
/// counts, the area and the bounding box. A store keeps it to view its
/// checked arrays as a [`Mesh`] again without checking them again; all
/// zero for no mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshInfo {
    vertices: u32,
    faces: u32,
    /// Total area, Q16 square units.
    area: u64,
    bounds: [[i32; 3]; 2],
}

/// The arrays of a mesh [`Mesh::new_checked`] filled, borrowed to be
/// viewed again ([`MeshInfo`]).
#[derive(Clone, Copy, Debug)]
pub struct MeshArrays<'m> {
    /// Vertices (Q16).
    pub vertices: &'m [[i32; 3]],
    /// Faces.
    pub faces: &'m [[u32; 3]],
    /// Neighbours.
    pub neighbours: &'m [[u32; 3]],
    /// Unit normals.
    pub normals: &'m [[i32; 3]],
    /// Inward edge normals (empty: worked out when needed).
    pub inward: &'m [[[i32; 3]; 3]],
}

/// A validated triangle mesh with its adjacency and normals.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'m> {
    vertices: &'m [[i32; 3]],
    faces: &'m [[u32; 3]],
    neighbours: &'m [[u32; 3]],
    normals: &'m [[i32; 3]],
    /// Empty when worked out on demand ([`MeshParts`]).
    inward: &'m [[[i32; 3]; 3]],
    info: MeshInfo,
}

/// Where a cell is: a face and a point on it (Q16).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    /// The face index.
    pub face: u32,
    /// The point.
    pub p: [i32; 3],
}

/// `[f(0), f(1), f(2)]`: one value per axis, built in place (an array's
/// `map` leaves a loop and its guard in the walk's hot path).
#[inline(always)]
pub(crate) fn per_axis<T>(f: impl Fn(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// a − b.
#[inline]
fn sub(a: [i32; 3], b: [i32; 3]) -> [i64; 3] {
    per_axis(|c| i64::from(a[c]) - i64::from(b[c]))
}

/// a × b, for components below 2^31 (each product below 2^62).
#[inline]
fn cross(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline]
fn dot(a: [i64; 3], b: [i64; 3]) -> i64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// (a × b) >> 16 for a Q16 unit vector `a` and a Q16 vector `b`: a Q16
/// vector as long as b's part across a.
#[inline]
fn cross_q16(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    let c = cross(a, b);
    per_axis(|k| c[k] >> 16)
}

/// `num / den` as Q16 for 0 < den, |num| ≤ 2^62, both scaled down first
/// so that the shift cannot overflow.
#[inline]
pub(crate) fn ratio_q16(num: i64, den: i64) -> i64 {
    let bits = 64 - den.leading_zeros() as i64;
    let s = (bits - 46).max(0);
    let den = (den >> s).max(1);
    ((num >> s) << 16) / den
}

/// `v` scaled to Q16 unit length (zero for the zero vector).
fn unit(v: [i64; 3]) -> [i64; 3] {
    let big = v.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
    let s = (64 - big.leading_zeros() as i64 - 30).max(0);
    let w = v.map(|x| x >> s);
    let len = isqrt_u64(dot(w, w) as u64) as i64;
    if len == 0 {
        return [0; 3];
    }
    w.map(|x| (x << 16) / len)
}

impl MeshInfo {
    /// No mesh.
    pub const EMPTY: MeshInfo = MeshInfo {
        vertices: 0,
        faces: 0,
        area: 0,
        bounds: [[0; 3]; 2],
    };
}

impl<'m> Mesh<'m> {
    /// Validates `vertices` (Q16) and `faces` and fills `parts` with each
    /// face's neighbours and normal.
    ///
    /// # Errors
    /// The first problem found, naming its vertex or face.
    pub fn new_checked(
        vertices: &'m [[i32; 3]],
        faces: &'m [[u32; 3]],
        parts: MeshParts<'m>,
    ) -> Result<Mesh<'m>, MeshError> {
        let n = faces.len();
        if n == 0 {
            return Err(MeshError::Empty);
        }
        if vertices.len() > MAX_VERTICES
            || n > MAX_FACES
            || parts.neighbours.len() < n
            || parts.normals.len() < n
            || !(parts.inward.is_empty() || parts.inward.len() >= n)
            || !(parts.edges.is_empty() || parts.edges.len() >= 3 * n)
        {
            return Err(MeshError::TooLarge);
        }
        let mut bounds = [[i32::MAX; 3], [i32::MIN; 3]];
        for (i, v) in vertices.iter().enumerate() {
            if v.iter().any(|c| !(-MAX_COORD..=MAX_COORD).contains(c)) {
                return Err(MeshError::Coordinate { vertex: i as u32 });
            }
            for c in 0..3 {
                bounds[0][c] = bounds[0][c].min(v[c]);
                bounds[1][c] = bounds[1][c].max(v[c]);
            }
        }
        let mut area = 0u64;
        for (f, tri) in faces.iter().enumerate() {
            let face = f as u32;
            let [a, b, c] = tri.map(|i| i as usize);
            if a.max(b).max(c) >= vertices.len() || a == b || b == c || a == c {
                return Err(MeshError::Index { face });
            }
            // Components below 2^53: scaled to 30 bits for the length.
            let w = cross(sub(vertices[b], vertices[a]), sub(vertices[c], vertices[a]));
            let big = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
            let s = (64 - big.leading_zeros() as i64 - 30).max(0);
            let double = isqrt_u64(dot(w.map(|x| x >> s), w.map(|x| x >> s)) as u64) << s;
            if double < MIN_DOUBLE_AREA {
                return Err(MeshError::Degenerate { face });
            }
            area += double >> 17; // Q32 double area → Q16 area
            let normal = unit(w);
            parts.normals[f] = normal.map(|x| x as i32);
            if let Some(inward) = parts.inward.get_mut(f) {
                *inward = inward_normals(normal, tri.map(|v| vertices[v as usize]));
            }
            if let Some(keys) = parts.edges.get_mut(3 * f..3 * f + 3) {
                for (k, key) in keys.iter_mut().enumerate() {
                    let (p, q) = (tri[k], tri[(k + 1) % 3]);
                    let edge = u64::from(p.min(q)) << 44 | u64::from(p.max(q)) << 24;
                    *key = edge | u64::from(face) << 2 | k as u64;
                }
            }
        }
        parts.neighbours[..n].fill([NO_FACE; 3]);
        if parts.edges.is_empty() {
            pair_edges_by_search(faces, &mut parts.neighbours[..n])?;
        } else {
            pair_sorted_edges(&mut parts.edges[..3 * n], &mut parts.neighbours[..n])?;
        }
        let info = MeshInfo {
            vertices: vertices.len() as u32,
            faces: n as u32,
            area,
            bounds,
        };
        Ok(Mesh {
            vertices,
            faces,
            neighbours: &parts.neighbours[..n],
            normals: &parts.normals[..n],
            inward: parts.inward.get(..n).unwrap_or(&[]),
            info,
        })
    }

    /// The mesh of `arrays` that [`Mesh::new_checked`] filled and described
    /// by `info` (empty if they are shorter than `info` says).
    #[must_use]
    pub fn view(info: &MeshInfo, arrays: MeshArrays<'m>) -> Mesh<'m> {
        let (nv, nf) = (info.vertices as usize, info.faces as usize);
        match (
            arrays.vertices.get(..nv),
            arrays.faces.get(..nf),
            arrays.neighbours.get(..nf),
            arrays.normals.get(..nf),
        ) {
            (Some(vertices), Some(faces), Some(neighbours), Some(normals)) => Mesh {
                vertices,
                faces,
                neighbours,
                normals,
                inward: arrays.inward.get(..nf).unwrap_or(&[]),
                info: *info,
            },
            _ => Mesh {
                vertices: &[],
                faces: &[],
                neighbours: &[],
                normals: &[],
                inward: &[],
                info: MeshInfo::EMPTY,
            },
        }
    }

    /// Its counts, area and bounds, to view it again ([`Mesh::view`]).
    #[must_use]
    pub fn info(&self) -> MeshInfo {
        self.info
    }

    /// The vertices (Q16).
    #[must_use]
    pub fn vertices(&self) -> &'m [[i32; 3]] {
        self.vertices
    }

    /// The faces.
    #[must_use]
    pub fn faces(&self) -> &'m [[u32; 3]] {
        self.faces
    }

    /// The unit normal of face `f` (Q16).
    #[must_use]
    pub fn normal(&self, f: u32) -> [i32; 3] {
        self.normals.get(f as usize).copied().unwrap_or([0; 3])
    }

    /// The total area as Q16 square units.
    #[must_use]
    pub fn area_q16(&self) -> u64 {
        self.info.area
    }

    /// The lowest and highest corner of the bounding box (Q16).
    #[must_use]
    pub fn bounds(&self) -> [[i32; 3]; 2] {
        self.info.bounds
    }

    /// The corners of face `f`.
    #[inline]
    fn corners(&self, f: u32) -> [[i32; 3]; 3] {
        let Some(tri) = self.faces.get(f as usize) else {
            return [[0; 3]; 3];
        };
        tri.map(|v| self.vertices.get(v as usize).copied().unwrap_or_default())
    }

    /// The centroid of face `f` (Q16).
    #[must_use]
    pub fn centroid(&self, f: u32) -> [i32; 3] {
        let [a, b, c] = self.corners(f);
        per_axis(|k| ((i64::from(a[k]) + i64::from(b[k]) + i64::from(c[k])) / 3) as i32)
    }

    /// The point of face `f` at the barycentric weights `w` (Q16, summing
    /// to 2^16) of its corners.
    #[must_use]
    pub fn at(&self, f: u32, w: [i64; 3]) -> [i32; 3] {
        at_corners(self.corners(f), w)
    }

    /// The in-plane unit vectors `(along, across)` of face `f`: along its
    /// first edge and across it, into the face; a frame for offsets on it.
    #[must_use]
    pub fn frame(&self, f: u32) -> [[i64; 3]; 2] {
        let [a, b, _] = self.corners(f);
        let along = unit(sub(b, a));
        let n = self.normal(f).map(i64::from);
        [along, cross_q16(n, along)]
    }

    /// `p` held on face `f`: projected into its plane and, if outside,
    /// onto its nearest edge (through its barycentric weights, negative
    /// ones set to zero).
    #[must_use]
    pub fn snap(&self, f: u32, p: [i32; 3]) -> [i32; 3] {
        self.snap_onto(f, self.corners(f), self.normal(f).map(i64::from), p)
    }

    /// [`Mesh::snap`] onto face `f` with its `corners` and normal `n`.
    fn snap_onto(&self, f: u32, corners: [[i32; 3]; 3], n: [i64; 3], p: [i32; 3]) -> [i32; 3] {
        let [a, b, c] = corners;
        // The weight of a corner: twice the area of (the next corner, the
        // one after, p) along n; Q16 cross (< 2^37) · Q16 normal < 2^55.
        let weight = |s: [i32; 3], t: [i32; 3]| {
            let e = cross(sub(t, s), sub(p, s));
            dot(per_axis(|k| e[k] >> 16), n).max(0)
        };
        let w = [weight(b, c), weight(c, a), weight(a, b)];
        let total = w[0] + w[1] + w[2];
        if total == 0 {
            return self.centroid(f);
        }
        at_corners(corners, per_axis(|k| ratio_q16(w[k], total)))
    }

    /// `from` moved by `d` (Q16) along the surface: `d` is projected into
    /// the face's plane; at each edge the rest of the move is unfolded
    /// about it onto the neighbouring face, or, at a boundary, loses its
    /// part across the edge. At most [`MAX_CROSSINGS`] edges are crossed.
    #[must_use]
    #[inline]
    pub fn walk(&self, from: Place, d: [i64; 3]) -> Place {
        let n = self.normal(from.face).map(i64::from);
        let d = along_plane(d, n);
        let corners = self.corners(from.face);
        match self.exit(from.face, &corners, from.p, d) {
            None => self.land(from.face, &corners, n, from.p, d),
            Some(exit) => self.unfold(from, d, exit),
        }
    }

    /// The end of the move `d` from `p` inside face `f` (up to rounding):
    /// held on the face only if rounding has taken it off its plane.
    #[inline]
    fn land(
        &self,
        f: u32,
        corners: &[[i32; 3]; 3],
        n: [i64; 3],
        p: [i32; 3],
        d: [i64; 3],
    ) -> Place {
        let to = per_axis(|c| (i64::from(p[c]) + d[c]) as i32);
        let off = dot(sub(to, corners[0]), n) >> 16;
        let to = if off.abs() <= 2 {
            to
        } else {
            self.snap_onto(f, *corners, n, to)
        };
        Place { face: f, p: to }
    }

    /// The rest of [`Mesh::walk`] once the move `d` (in the plane of
    /// `from`'s face) leaves it by `exit`: crossing by crossing.
    #[inline(never)]
    fn unfold(&self, from: Place, mut d: [i64; 3], mut exit: (usize, i64)) -> Place {
        let mut face = from.face;
        let mut p = from.p;
        let mut corners = self.corners(face);
        let mut n = self.normal(face).map(i64::from);
        for crossing in 1..=MAX_CROSSINGS {
            let (k, t) = exit;
            let part = d.map(|x| (x * t) >> 16);
            p = per_axis(|c| (i64::from(p[c]) + part[c]) as i32);
            let rest = per_axis(|c| d[c] - part[c]);
            let (s, e) = (corners[k], corners[(k + 1) % 3]);
            let along = unit(sub(e, s));
            let out = cross_q16(along, n); // out of the face, across edge k
            let next = self
                .neighbours
                .get(face as usize)
                .map_or(NO_FACE, |nb| nb[k]);
            let ahead = dot(rest, along) >> 16;
            let across = dot(rest, out) >> 16;
            if next == NO_FACE {
                // Slide along the boundary.
                d = along.map(|x| (x * ahead) >> 16);
                if ahead == 0 {
                    break;
                }
            } else {
                // Into the neighbour: along the edge, and across it inwards.
                let Some(into) = self.inward(next, s, e) else {
                    break; // not the neighbour's edge: a mesh not validated
                };
                d = per_axis(|c| (along[c] * ahead + into[c] * across) >> 16);
                face = next;
                corners = self.corners(face);
                n = self.normal(face).map(i64::from);
            }
            if crossing == MAX_CROSSINGS {
                break;
            }
            match self.exit(face, &corners, p, d) {
                None => return self.land(face, &corners, n, p, d),
                Some(next) => exit = next,
            }
        }
        Place {
            face,
            p: self.snap_onto(face, corners, n, p),
        }
    }

    /// The edge of face `f` (with `corners`) that the move `d` from `p`
    /// leaves by first, and the part of `d` made before it (Q16, below 1):
    /// h/−rate smallest, h the height of `p` over the edge and rate the
    /// move's; `None` if the move ends inside.
    #[inline(always)]
    fn exit(
        &self,
        f: u32,
        corners: &[[i32; 3]; 3],
        p: [i32; 3],
        d: [i64; 3],
    ) -> Option<(usize, i64)> {
        if f as usize >= self.faces.len() {
            return None;
        }
        let edges = match self.inward.get(f as usize) {
            Some(stored) => *stored,
            None => inward_normals(self.normal(f).map(i64::from), *corners),
        };
        let mut exit: Option<(usize, i64)> = None;
        for (k, (inward, s)) in edges.iter().zip(corners).enumerate() {
            let inward = inward.map(i64::from);
            let rate = dot(d, inward);
            if rate >= 0 {
                continue;
            }
            let h = dot(sub(p, *s), inward).max(0);
            if h >= -rate {
                continue;
            }
            let t = ratio_q16(h, -rate);
            if exit.is_none_or(|(_, best)| t < best) {
                exit = Some((k, t));
            }
        }
        exit
    }

    /// The unit vector in face `f`'s plane across its edge between the
    /// corners `s` and `e`, pointing into the face.
    fn inward(&self, f: u32, s: [i32; 3], e: [i32; 3]) -> Option<[i64; 3]> {
        let corners = self.corners(f);
        let k = (0..3).find(|&k| {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            (a == s && b == e) || (a == e && b == s)
        })?;
        let n = self.normal(f).map(i64::from);
        let edge = unit(sub(corners[(k + 1) % 3], corners[k]));
        Some(cross_q16(n, edge))
    }
}

/// Each edge of the triangle `corners` turned a quarter turn about its
/// unit `normal` (Q16), into it, as long as the edge: |n × e| ≤ |e| < 2^27.
#[inline]
fn inward_normals(normal: [i64; 3], corners: [[i32; 3]; 3]) -> [[i32; 3]; 3] {
    [0, 1, 2].map(|k| cross_q16(normal, sub(corners[(k + 1) % 3], corners[k])).map(|x| x as i32))
}

/// Fills `neighbours` from the sorted edge keys (`3·f + k` holds edge k
/// of face f: its vertex pair, face and k).
fn pair_sorted_edges(edges: &mut [u64], neighbours: &mut [[u32; 3]]) -> Result<(), MeshError> {
    edges.sort_unstable();
    let side = |e: u64| (((e >> 2) & ((1 << 22) - 1)) as usize, (e & 3) as usize);
    for shared in edges.chunk_by(|a, b| a >> 24 == b >> 24) {
        match *shared {
            [_] => {}
            [a, b] => {
                let ((f, k), (g, l)) = (side(a), side(b));
                neighbours[f][k] = g as u32;
                neighbours[g][l] = f as u32;
            }
            _ => {
                return Err(MeshError::NonManifold {
                    face: side(shared[0]).0 as u32,
                });
            }
        }
    }
    Ok(())
}

/// Fills `neighbours` by comparing each edge with every other: no scratch,
/// the same pairs as [`pair_sorted_edges`] (an edge of three or more faces
/// names the first face found on it).
fn pair_edges_by_search(faces: &[[u32; 3]], neighbours: &mut [[u32; 3]]) -> Result<(), MeshError> {
    let edge = |tri: &[u32; 3], k: usize| {
        let (p, q) = (tri[k], tri[(k + 1) % 3]);
        (p.min(q), p.max(q))
    };
    for (f, tri) in faces.iter().enumerate() {
        for k in 0..3 {
            if neighbours[f][k] != NO_FACE {
                continue;
            }
            let e = edge(tri, k);
            let mut other = None;
            for (g, t) in faces.iter().enumerate().skip(f + 1) {
                for l in 0..3 {
                    if edge(t, l) == e {
                        if other.is_some() {
                            return Err(MeshError::NonManifold { face: f as u32 });
                        }
                        other = Some((g, l));
                    }
                }
            }
            if let Some((g, l)) = other {
                neighbours[f][k] = g as u32;
                neighbours[g][l] = f as u32;
            }
        }
    }
    Ok(())
}

/// The point of the triangle `[a, b, c]` at the barycentric weights `w`
/// (Q16) of its corners.
#[inline]
fn at_corners([a, b, c]: [[i32; 3]; 3], w: [i64; 3]) -> [i32; 3] {
    let total = (w[0] + w[1] + w[2]).max(1);
    per_axis(|k| {
        let s =
            w[1] * (i64::from(b[k]) - i64::from(a[k])) + w[2] * (i64::from(c[k]) - i64::from(a[k]));
        (i64::from(a[k]) + (s + total / 2).div_euclid(total)) as i32
    })
}

/// `d` less its part along the unit normal `n` (Q16).
#[inline]
#[must_use]
pub fn along_plane(d: [i64; 3], n: [i64; 3]) -> [i64; 3] {
    let dn = dot(d, n) >> 16;
    per_axis(|c| d[c] - ((dn * n[c]) >> 16))
}

#[cfg(test)]
mod tests;
