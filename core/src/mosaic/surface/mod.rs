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
use super::mesh::{Mesh, MeshError, MeshInfo, MeshParts, Place, along_plane};
use super::params::Params;
use super::store::{ArrayStore, Relax};
use super::terrain::{Push, Terrain};
use super::{Mosaic, MosaicError};
use crate::Error;
use crate::fx::{Fx, Real};
use crate::rng::KeyedRng;
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

/// A running mosaic on a mesh: over the cell store `S`, on a mesh built
/// at each start in the mesh store `M`.
pub type SurfaceMosaic<'a, S, M> = Mosaic<'a, S, MeshTerrain<M>>;

impl<'a, S: Relax<OnMesh>, M: MeshStore> SurfaceMosaic<'a, S, M> {
    /// A mosaic over `store`, its mesh (and the anisotropy field's vector
    /// at each face, in its plane, Q14) built in `meshes` at each start;
    /// not yet started.
    pub const fn on_mesh(store: S, meshes: M) -> SurfaceMosaic<'a, S, M> {
        Mosaic::on(
            store,
            MeshTerrain {
                meshes,
                mesh: MeshInfo::EMPTY,
            },
        )
    }

    /// The mesh (empty before a start).
    #[must_use]
    pub fn mesh(&self) -> Mesh<'_> {
        self.terrain().mesh()
    }
}

/// A triangle mesh built at each start in the mesh store `M`, with the
/// anisotropy field at each face.
#[derive(Debug)]
pub struct MeshTerrain<M: MeshStore> {
    meshes: M,
    /// The counts, area and bounds of the mesh in `meshes`.
    mesh: MeshInfo,
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

impl<M: MeshStore> MeshTerrain<M> {
    /// The mesh (empty before a start).
    #[must_use]
    pub fn mesh(&self) -> Mesh<'_> {
        Mesh::view(&self.mesh, self.meshes.arrays().0)
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

impl<M: MeshStore> Terrain for MeshTerrain<M> {
    type Ground = OnMesh;

    fn prepare(&mut self, params: &Params) -> Result<(), Error> {
        let Some(surface) = &params.surface else {
            return Err(MosaicError::Param("surface (a surface mosaic needs one)").into());
        };
        self.mesh = MeshInfo::EMPTY;
        let (nv, nf) = surface.counts();
        let (buffers, _) = self.meshes.buffers(nv, nf)?;
        self.mesh = build_mesh(surface, buffers)?.info();
        if let Some(a) = &params.anisotropy {
            self.tabulate(params, a)?;
        }
        Ok(())
    }

    /// For the mesh's area.
    fn radius(&self, params: &Params, cells: u32) -> i32 {
        let n = u64::from(cells.max(1));
        let area = self.mesh().area_q16();
        // area/N as Q32: shifted first while it fits (2^47 square units
        // and more only on meshes of millions of large triangles).
        let per_cell = match area.checked_mul(1 << 16) {
            Some(q32) => q32 / n,
            None => (area / n).saturating_mul(1 << 16),
        };
        let spacing = per_cell.isqrt(); // Q16
        let r = (spacing * u64::from(params.radius_weight.to_bits().unsigned_abs())) >> 16;
        r.clamp(1, 1 << 28) as i32
    }

    fn scatter(&self, _: &Params) -> impl FnMut(&mut KeyedRng) -> Place {
        let largest = self.largest_double_area();
        move |rng| self.random_place(rng, largest)
    }

    /// The offset in the plane of the mother's face, walked along the
    /// surface.
    fn offspring(&self, _: &Params) -> impl Fn(Place, [i32; 2]) -> Place {
        let mesh = self.mesh();
        move |at, off| {
            let off = off.map(i64::from);
            let [along, across] = mesh.frame(at.face);
            let d = [0, 1, 2].map(|c| (along[c] * off[0] + across[c] * off[1]) >> 16);
            mesh.walk(at, d)
        }
    }

    fn control_uv(&self, params: &Params, at: &Place) -> [i32; 2] {
        control_uv(params, self.mesh().bounds(), at.p)
    }

    fn relax<S: Relax<OnMesh>>(
        &self,
        store: &mut S,
        n: usize,
        push: Push,
        params: &Params,
        times: u16,
    ) {
        let (arrays, field) = self.meshes.arrays();
        let mesh = Mesh::view(&self.mesh, arrays);
        let forces = SurfaceForces {
            mesh: &mesh,
            radius: push.radius,
            repel: push.repel,
            push_weight: push.push_weight,
            anisotropy_weight: push.anisotropy_weight,
            field: params.anisotropy.as_ref().map(|_| field),
            momentum: push.momentum,
        };
        store.relax(n, &forces, times);
    }

    /// The mesh, in the first frame.
    fn records(&self, frame: u32, sink: &mut dyn Sink) -> Result<(), Error> {
        if frame == 0 {
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
        Ok(())
    }

    fn cell(id: u32, kind: u8, at: &Place) -> Record {
        Record::SurfaceCell {
            id,
            kind,
            p: at.p.map(Fx::from_bits),
        }
    }
}

#[cfg(test)]
mod tests;
