//! Clonal mosaics on a triangle mesh (thesis Secs. 3.2 and 4.1: MClone
//! grows its cells on the object itself). The same day as on the plane —
//! division, radius r = w_r·√(area/N), ρ_s relaxations — with cells that
//! are [`Place`]s on a [`Mesh`]: neighbours within r found by 3D distance
//! through a grid of cubes ([`relaxation`]), the push taken into the cell's
//! tangent plane and walked along the surface across edges
//! ([`Mesh::walk`]). The mask is read through the control cylinder's (or
//! plane's) (u, v) (Sec. 3.2.2, [`ControlMap`]).
//!
//! A run streams the mesh once (in its first frame: [`Record::MeshVertex`]
//! and [`Record::Triangle`]), then each streamed day's cells as
//! [`Record::SurfaceCell`]s.

pub mod meshes;
pub mod relaxation;
pub mod spec;

use super::control::{Anisotropy, Field};
use super::day::{self, Day, Run};
use super::division::{self, Purpose, stream_id};
use super::mesh::{Mesh, MeshError, MeshInfo, MeshParts, Place, along_plane};
use super::params::{MAX_TYPES, Params};
use super::store::{ArrayStore, Relax};
use super::{CELL_LIMIT, MosaicError, repulsion, validate};
use crate::Error;
use crate::fx::{Fx, Real};
use crate::rng::KeyedRng;
use crate::sim::{Progress, Simulation, Start};
use crate::stream::{Record, Sink};
use meshes::MeshStore;
use relaxation::{OnMesh, SurfaceForces};
pub use spec::{ControlMap, Surface, SurfaceMesh};

/// The name of the limit in [`Error::Capacity`] when the buffer for the
/// anisotropy field has fewer entries than the mesh has faces.
pub const FIELD_LIMIT: &str = "surface anisotropy field (one vector per face of the mesh)";

/// The MCU's surface cell store: 1 024 cells and 256 grid buckets
/// (36 868 B).
pub type McuSurfaceStore = ArrayStore<1024, 257, OnMesh>;
/// The MCU's mesh store: up to 132 vertices and 256 faces (10 800 B; an
/// ellipsoid of 10 rings × 14 segments has 128 and 252). With the cells,
/// a surface mosaic on the MCU holds 47 768 B.
pub type McuMeshStore = meshes::ArrayMeshStore<132, 256>;

/// The buffers a surface's mesh is built in ([`Surface::counts`] entries
/// each; three edge keys per face).
#[derive(Debug)]
pub struct MeshBuffers<'m> {
    /// Vertices (Q16).
    pub vertices: &'m mut [[i32; 3]],
    /// Faces.
    pub faces: &'m mut [[u32; 3]],
    /// Adjacency, normals and scratch.
    pub parts: MeshParts<'m>,
}

/// Builds and validates the mesh of `surface` in `buffers`.
///
/// # Errors
/// An unusable shape ([`MosaicError::Param`]) or mesh ([`MosaicError::Mesh`]).
pub fn build_mesh<'m>(surface: &Surface<'_>, buffers: MeshBuffers<'m>) -> Result<Mesh<'m>, Error> {
    let (nv, nf) = surface.counts();
    if buffers.vertices.len() < nv || buffers.faces.len() < nf {
        return Err(MosaicError::Mesh(MeshError::TooLarge).into());
    }
    match surface.mesh {
        SurfaceMesh::Shape(t) => {
            if !t.is_valid() {
                return Err(MosaicError::Param("surface shape (sizes, rings, segments)").into());
            }
            t.build(buffers.vertices, buffers.faces);
        }
        SurfaceMesh::Triangles { vertices, faces } => {
            for (to, v) in buffers.vertices.iter_mut().zip(vertices) {
                *to = v.map(Fx::to_bits);
            }
            buffers.faces[..nf].copy_from_slice(faces);
        }
    }
    let vertices: &'m [[i32; 3]] = buffers.vertices;
    let faces: &'m [[u32; 3]] = buffers.faces;
    Mesh::new_checked(&vertices[..nv], &faces[..nf], buffers.parts)
        .map_err(|e| MosaicError::Mesh(e).into())
}

/// A running mosaic over the cell store `S`, on a mesh built at each
/// start in the mesh store `M`.
#[derive(Debug)]
pub struct SurfaceMosaic<'a, S: Relax<OnMesh>, M: MeshStore> {
    store: S,
    meshes: M,
    /// The counts, area and bounds of the mesh in `meshes`.
    mesh: MeshInfo,
    run: Run<'a>,
}

/// The mesh in `meshes`, as `info` describes it.
fn mesh_of<'m>(meshes: &'m impl MeshStore, info: &MeshInfo) -> Mesh<'m> {
    Mesh::view(info, meshes.arrays().0)
}

/// The (u, v) in the domain of `p` on a mesh with `bounds`, through the
/// control map (thesis Sec. 3.2.2).
fn control_uv(params: &Params, [lo, hi]: [[i32; 3]; 2], p: [i32; 3]) -> [i32; 2] {
    let size = params.domain.size.map(|s| i64::from(s.to_bits()));
    let along = |x: i32, c: usize, s: i64| {
        let span = (i64::from(hi[c]) - i64::from(lo[c])).max(1);
        ((i64::from(x) - i64::from(lo[c])) * s / span).clamp(0, s - 1) as i32
    };
    let map = params.surface.map_or(ControlMap::Plane, |s| s.control);
    match map {
        ControlMap::Cylinder => {
            let turn = <Fx as Real>::atan2(Fx::from_bits(p[1]), Fx::from_bits(p[0]));
            let u = (u64::from(turn.0) * size[0] as u64) >> 32;
            [u as i32, along(p[2], 2, size[1])]
        }
        ControlMap::Plane => [along(p[0], 0, size[0]), along(p[1], 1, size[1])],
    }
}

impl<'a, S: Relax<OnMesh>, M: MeshStore> SurfaceMosaic<'a, S, M> {
    /// A mosaic over `store`, its mesh (and the anisotropy field's vector
    /// at each face, in its plane, Q14) built in `meshes` at each start;
    /// not yet started.
    pub const fn new(store: S, meshes: M) -> SurfaceMosaic<'a, S, M> {
        SurfaceMosaic {
            store,
            meshes,
            mesh: MeshInfo::EMPTY,
            run: Run::new(),
        }
    }

    /// The mesh (empty before a start).
    #[must_use]
    pub fn mesh(&self) -> Mesh<'_> {
        mesh_of(&self.meshes, &self.mesh)
    }

    /// Number of cells.
    #[must_use]
    pub fn len(&self) -> usize {
        self.run.cells as usize
    }

    /// Whether there are no cells (before day 0).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.run.cells == 0
    }

    /// The cell store (for benches and tools that drive the kernels
    /// directly; the first [`SurfaceMosaic::len`] cells are live).
    pub fn store_mut(&mut self) -> &mut S {
        &mut self.store
    }

    /// The current repulsion radius (Q16 bits).
    #[must_use]
    pub fn radius(&self) -> Fx {
        Fx::from_bits(self.run.radius)
    }

    /// Where the cells are, by id.
    #[must_use]
    pub fn places(&self) -> &[Place] {
        &self.store.positions()[..self.len()]
    }

    /// The (u, v) of `p` in the domain, through the control map.
    fn control_uv(&self, params: &Params, p: [i32; 3]) -> [i32; 2] {
        control_uv(params, self.mesh().bounds(), p)
    }

    /// The anisotropy field `a` (defined over the domain's (u, v)) at each
    /// face's centroid, turned into the face's plane: u runs around z on
    /// a cylinder (x on a plane), v along z (y).
    fn tabulate(&mut self, params: &Params, a: &Anisotropy) -> Result<(), Error> {
        let (arrays, out) = self.meshes.arrays_mut();
        let mesh = Mesh::view(&self.mesh, arrays);
        let faces = mesh.faces().len();
        if out.len() < faces {
            return Err(Error::Capacity {
                limit: FIELD_LIMIT,
                capacity: out.len() as u32,
            });
        }
        let field = Field::interpolate(&params.domain, a).map_err(MosaicError::Control)?;
        let map = params.surface.map_or(ControlMap::Plane, |s| s.control);
        for f in 0..faces as u32 {
            let c = mesh.centroid(f);
            let v = field
                .at(&params.domain, control_uv(params, mesh.bounds(), c))
                .map(i64::from);
            let (u_axis, v_axis) = match map {
                ControlMap::Cylinder => {
                    let around = <Fx as Real>::atan2(Fx::from_bits(c[1]), Fx::from_bits(c[0]));
                    let (sin, cos) = (
                        i64::from(<Fx as Real>::sin(around).to_bits()),
                        i64::from(<Fx as Real>::cos(around).to_bits()),
                    );
                    ([-sin, cos, 0], [0, 0, 1 << 16])
                }
                ControlMap::Plane => ([1 << 16, 0, 0], [0, 1 << 16, 0]),
            };
            let d = [0, 1, 2].map(|k| (u_axis[k] * v[0] + v_axis[k] * v[1]) >> 16); // Q14
            let n = mesh.normal(f).map(i64::from);
            out[f as usize] = along_plane(d, n).map(|x| x as i32);
        }
        Ok(())
    }

    /// A point uniformly at random on the surface: a face by its area
    /// (rejection against the `largest` double area, found once for all
    /// cells), a point by its barycentric weights.
    fn random_place(&self, rng: &mut KeyedRng, largest: u64) -> Place {
        let faces = self.mesh().faces().len() as u32;
        for _ in 0..64 {
            let f = rng.below(faces);
            let accept = u64::from(rng.next_u32());
            if (u128::from(self.double_area(f)) << 32) < u128::from(accept) * u128::from(largest) {
                continue;
            }
            return self.point_in(f, rng);
        }
        let f = rng.below(faces);
        self.point_in(f, rng)
    }

    fn point_in(&self, f: u32, rng: &mut KeyedRng) -> Place {
        let (mut a, mut b) = (i64::from(rng.below(1 << 16)), i64::from(rng.below(1 << 16)));
        if a + b > 1 << 16 {
            (a, b) = ((1 << 16) - a, (1 << 16) - b);
        }
        Place {
            face: f,
            p: self.mesh().at(f, [(1 << 16) - a - b, a, b]),
        }
    }

    fn double_area(&self, f: u32) -> u64 {
        let mesh = self.mesh();
        let n = mesh.normal(f).map(i64::from);
        let [a, b, c] = mesh.faces()[f as usize].map(|v| mesh.vertices()[v as usize]);
        let e = |p: [i32; 3], q: [i32; 3]| [0, 1, 2].map(|k| i64::from(p[k]) - i64::from(q[k]));
        let (u, v) = (e(b, a), e(c, a));
        let w = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        // |w| = w·n for the face's own normal (Q32 · Q16 >> 16 = Q32).
        ((w[0] >> 16) * n[0] + (w[1] >> 16) * n[1] + (w[2] >> 16) * n[2]).unsigned_abs()
    }

    fn largest_double_area(&self) -> u64 {
        (0..self.mesh().faces().len() as u32)
            .map(|f| self.double_area(f))
            .max()
            .unwrap_or(1)
            .max(1)
    }
}

impl<'a, S: Relax<OnMesh>, M: MeshStore> Day<'a> for SurfaceMosaic<'a, S, M> {
    fn run(&mut self) -> &mut Run<'a> {
        &mut self.run
    }

    fn prepare(&mut self, params: &'a Params<'a>) -> Result<(), Error> {
        validate(params)?;
        let Some(surface) = &params.surface else {
            return Err(MosaicError::Param("surface (a surface mosaic needs one)").into());
        };
        self.mesh = MeshInfo::EMPTY;
        let (nv, nf) = surface.counts();
        let (buffers, _) = self.meshes.buffers(nv, nf)?;
        self.mesh = build_mesh(surface, buffers)?.info();
        let velocities = self.store.slices().velocity.len();
        day::check_store(params, self.store.capacity(), velocities)?;
        if let Some(a) = &params.anisotropy {
            self.tabulate(params, a)?;
        }
        Ok(())
    }

    /// r = w_r·√(area/N) for the mesh's area.
    fn update_radius(&mut self, params: &Params) {
        let n = u64::from(self.run.cells.max(1));
        let area = self.mesh().area_q16();
        // area/N as Q32: shifted first while it fits (2^47 square units
        // and more only on meshes of millions of large triangles).
        let per_cell = match area.checked_mul(1 << 16) {
            Some(q32) => q32 / n,
            None => (area / n).saturating_mul(1 << 16),
        };
        let spacing = per_cell.isqrt(); // Q16
        let r = (spacing * u64::from(params.radius_weight.to_bits().unsigned_abs())) >> 16;
        self.run.radius = r.clamp(1, 1 << 28) as i32;
    }

    fn place(&mut self, params: &Params) -> Result<(), Error> {
        let largest = self.largest_double_area();
        for id in 0..params.initial_cells {
            let mut rng = KeyedRng::new(self.run.seed, stream_id(Purpose::Place, 0, id));
            let at = self.random_place(&mut rng, largest);
            let mut kind = division::initial_type(&mut rng, params.types);
            let uv = self.control_uv(params, at.p);
            if kind != 0 && params.mask.is_some_and(|m| !m.allows(&params.domain, uv)) {
                kind = 0;
            }
            let next = division::interval(&mut rng, &params.types[kind as usize])?;
            let cells = self.store.slices();
            cells.pos[id as usize] = at;
            cells.kind[id as usize] = kind;
            cells.next_division[id as usize] = next;
            if let Some(v) = cells.velocity.get_mut(id as usize) {
                *v = [0; 3];
            }
        }
        self.run.cells = params.initial_cells;
        Ok(())
    }

    fn divide(&mut self, params: &Params) -> Result<(), Error> {
        let (seed, day) = (self.run.seed, self.run.day);
        let capacity = self.store.capacity();
        let disc = self.run.radius / 200;
        let mesh = mesh_of(&self.meshes, &self.mesh);
        let cells = self.store.slices();
        let existing = self.run.cells as usize;
        let mut n = existing;
        for id in 0..existing {
            if cells.next_division[id] > day {
                continue;
            }
            if n >= capacity {
                return Err(Error::Capacity {
                    limit: CELL_LIMIT,
                    capacity: capacity as u32,
                });
            }
            let split = division::split(seed, day, id as u32, cells.kind[id], params, disc)?;
            let off = split.offset.map(i64::from);
            let at = cells.pos[id];
            let [along, across] = mesh.frame(at.face);
            let d = [0, 1, 2].map(|c| (along[c] * off[0] + across[c] * off[1]) >> 16);
            cells.pos[n] = mesh.walk(at, d);
            cells.kind[n] = split.child;
            if let Some(v) = cells.velocity.get_mut(n) {
                *v = [0; 3];
            }
            cells.next_division[n] = split.child_next;
            cells.next_division[id] = split.parent_next;
            n += 1;
        }
        self.run.cells = n as u32;
        Ok(())
    }

    fn relax(&mut self, params: &Params, times: u16, adhesion: bool) {
        let repel = if adhesion {
            repulsion(&params.adhesion)
        } else {
            [[1 << 16; MAX_TYPES]; MAX_TYPES]
        };
        let (arrays, field) = self.meshes.arrays();
        let mesh = Mesh::view(&self.mesh, arrays);
        let forces = SurfaceForces {
            mesh: &mesh,
            radius: self.run.radius,
            repel,
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: params
                .anisotropy
                .map_or(0, |a| a.weight.clamp(Fx::ZERO, Fx::ONE).to_bits()),
            field: params.anisotropy.as_ref().map(|_| field),
            momentum: params.momentum.to_bits(),
        };
        let n = self.run.cells as usize;
        self.store.relax(n, &forces, times);
    }

    fn records(&mut self, sink: &mut dyn Sink) -> Result<(), Error> {
        if self.run.frame == 0 {
            let mesh = self.mesh();
            for (id, v) in mesh.vertices().iter().enumerate() {
                sink.record(&Record::MeshVertex {
                    id: id as u32,
                    p: v.map(Fx::from_bits),
                })?;
            }
            for f in mesh.faces() {
                sink.record(&Record::Triangle { v: *f })?;
            }
        }
        let n = self.len();
        let (places, kinds) = (self.store.positions(), self.store.kinds());
        for (id, (at, k)) in places[..n].iter().zip(&kinds[..n]).enumerate() {
            sink.record(&Record::SurfaceCell {
                id: id as u32,
                kind: *k,
                p: at.p.map(Fx::from_bits),
            })?;
        }
        Ok(())
    }
}

impl<'a, S: Relax<OnMesh>, M: MeshStore> Start<'a> for SurfaceMosaic<'a, S, M> {
    type Params = Params<'a>;

    /// (Re)starts a run of `params` with `seed`, in place.
    ///
    /// # Errors
    /// Invalid parameters, a run without a surface, or more initial cells
    /// than the store holds; also returned by the next step.
    fn start(&mut self, params: &'a Params<'a>, seed: u64) -> Result<(), Error> {
        self.start_run(params, seed)
    }
}

impl<S: Relax<OnMesh>, M: MeshStore> Simulation for SurfaceMosaic<'_, S, M> {
    /// Step 0 places and relaxes the initial cells; step d ≥ 1 simulates
    /// day d, as on the plane.
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.step_day(sink)
    }
}

#[cfg(test)]
mod tests;
