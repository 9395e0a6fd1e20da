//! Unit tests of the surface mosaic: cells stay on the mesh and spread
//! evenly; a run without a surface, or with momentum on a store without
//! velocities, is refused naming why.

#![allow(clippy::float_arithmetic)] // f64 measures the fixed-point results

use super::meshes::ArrayMeshStore;
use super::*;
use crate::mosaic::mesh::MeshArrays;
use crate::mosaic::params::{CellType, Frames, NO_MUTATION, pair_table};
use crate::mosaic::shapes::{Shape, Tessellation};
use crate::mosaic::{ArrayStore, OnMesh};
use crate::mosaic::{Domain, VELOCITY_LIMIT};
use crate::sim::{Simulation, Start};
use crate::stream::Encoder;
use crate::stream::SinkError;

static TYPES: [CellType; 2] = [
    CellType {
        colour: [150, 196, 96],
        division_days: 10,
        initial_probability: Fx::from_ratio(1, 2),
    },
    CellType {
        colour: [28, 78, 34],
        division_days: 5,
        initial_probability: Fx::from_ratio(1, 2),
    },
];

const SPHERE: Surface<'static> = Surface {
    mesh: SurfaceMesh::Shape(Tessellation {
        shape: Shape::Ellipsoid {
            radii: [Fx::from_int(5), Fx::from_int(5), Fx::from_int(6)],
            square: Fx::ZERO,
        },
        rings: 12,
        segments: 16,
    }),
    control: ControlMap::Cylinder,
};

fn params(days: u16) -> Params<'static> {
    Params {
        domain: Domain::cylinder(Fx::from_int(31), Fx::from_int(12)),
        initial_cells: 400,
        types: &TYPES,
        adhesion: pair_table(
            [
                Fx::from_ratio(8, 10),
                Fx::from_ratio(5, 10),
                Fx::ZERO,
                Fx::ZERO,
            ],
            Fx::ZERO,
        ),
        mutation: NO_MUTATION,
        radius_weight: Fx::from_ratio(3, 2),
        push_weight: Fx::from_ratio(1, 10),
        initial_relaxations: 40,
        daily_relaxations: 8,
        momentum: Fx::ZERO,
        days,
        mask: None,
        anisotropy: None,
        frames: Frames::EveryDay,
        surface: Some(SPHERE),
    }
}

/// A mesh store with every part (the host's layout: inward normals
/// stored, edges sorted).
struct MeshVecs {
    v: [[i32; 3]; 256],
    f: [[u32; 3]; 512],
    nb: [[u32; 3]; 512],
    normals: [[i32; 3]; 512],
    inward: [[[i32; 3]; 3]; 512],
    edges: [u64; 1536],
}

impl MeshVecs {
    fn new() -> MeshVecs {
        MeshVecs {
            v: [[0; 3]; 256],
            f: [[0; 3]; 512],
            nb: [[0; 3]; 512],
            normals: [[0; 3]; 512],
            inward: [[[0; 3]; 3]; 512],
            edges: [0; 1536],
        }
    }

    fn arrays(&self) -> MeshArrays<'_> {
        MeshArrays {
            vertices: &self.v,
            faces: &self.f,
            neighbours: &self.nb,
            normals: &self.normals,
            inward: &self.inward,
        }
    }
}

impl MeshStore for MeshVecs {
    fn buffers(
        &mut self,
        _vertices: usize,
        _faces: usize,
    ) -> Result<(MeshBuffers<'_>, &mut [[i32; 3]]), Error> {
        let buffers = MeshBuffers {
            vertices: &mut self.v,
            faces: &mut self.f,
            parts: MeshParts {
                neighbours: &mut self.nb,
                normals: &mut self.normals,
                inward: &mut self.inward,
                edges: &mut self.edges,
            },
        };
        Ok((buffers, &mut []))
    }

    fn arrays(&self) -> (MeshArrays<'_>, &[[i32; 3]]) {
        (MeshVecs::arrays(self), &[])
    }

    fn arrays_mut(&mut self) -> (MeshArrays<'_>, &mut [[i32; 3]]) {
        (MeshVecs::arrays(self), &mut [])
    }
}

/// Collects the surface cells of the last frame.
#[derive(Default)]
struct Last(Vec<(u8, [Fx; 3])>, usize);

impl Sink for Last {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        match r {
            Record::FrameStart { .. } => self.0.clear(),
            Record::SurfaceCell { kind, p, .. } => self.0.push((*kind, *p)),
            Record::Triangle { .. } => self.1 += 1,
            _ => {}
        }
        Ok(())
    }
}

type Store = ArrayStore<2048, 1025, OnMesh>;

/// The distance (units, f64) from a cell to its face's triangle.
fn off_triangle(mesh: &Mesh<'_>, at: Place) -> f64 {
    let units = |p: [i32; 3]| p.map(|x| f64::from(x) / 65536.0);
    let [a, b, c] = mesh.faces()[at.face as usize].map(|v| units(mesh.vertices()[v as usize]));
    let p = units(at.p);
    let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
    let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let (u, v, w) = (sub(b, a), sub(c, a), sub(p, a));
    // Barycentric (s, t) of p's projection; the part of w off the plane.
    let (uu, uv, vv, wu, wv) = (dot(u, u), dot(u, v), dot(v, v), dot(w, u), dot(w, v));
    let det = uu * vv - uv * uv;
    let s = (vv * wu - uv * wv) / det;
    let t = (uu * wv - uv * wu) / det;
    let slack = 1e-4;
    if s < -slack || t < -slack || s + t > 1.0 + slack {
        return f64::INFINITY;
    }
    let q = [0, 1, 2].map(|k| a[k] + s * u[k] + t * v[k]);
    dot(sub(p, q), sub(p, q)).sqrt()
}

#[test]
fn cells_stay_on_the_mesh_and_spread_evenly() {
    let p = params(6);
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, MeshVecs::new());
    m.start(&p, 3).unwrap();
    let mut sink = Last::default();
    while !m.step(&mut sink).unwrap().finished() {}
    let mesh = m.mesh();
    assert_eq!(sink.1, mesh.faces().len(), "the mesh is streamed once");
    assert!(m.len() > 600, "{}", m.len());
    for at in m.positions() {
        // On its face, within 10⁻³ of the mesh's size (12 units).
        let d = off_triangle(&mesh, *at);
        assert!(d < 12e-3 / 10.0, "{at:?} is {d} off its face");
    }
    // Clark–Evans by 3D distance after the initial relaxation: mean
    // nearest-neighbour distance over 0.5/√density (1 for random points).
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, MeshVecs::new());
    let p0 = params(0);
    m.start(&p0, 3).unwrap();
    m.step(&mut Last::default()).unwrap();
    let pts: Vec<[f64; 3]> = m
        .positions()
        .iter()
        .map(|at| at.p.map(|x| f64::from(x) / 65536.0))
        .collect();
    let nearest: f64 = pts
        .iter()
        .enumerate()
        .map(|(i, a)| {
            pts.iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
                .fold(f64::MAX, f64::min)
        })
        .sum::<f64>()
        / pts.len() as f64;
    let area = m.mesh().area_q16() as f64 / 65536.0;
    let clark_evans = nearest / (0.5 * (area / pts.len() as f64).sqrt());
    assert!(clark_evans >= 1.4, "Clark–Evans index {clark_evans}");
}

#[test]
fn a_surface_run_needs_a_surface_and_names_its_limits() {
    let mut plain = params(1);
    plain.surface = None;
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, MeshVecs::new());
    assert!(matches!(
        m.start(&plain, 1),
        Err(Error::Mosaic(MosaicError::Param(_)))
    ));
    let mut heavy = params(1);
    heavy.momentum = Fx::from_ratio(1, 2);
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, MeshVecs::new());
    assert!(matches!(
        m.start(&heavy, 1),
        Err(Error::Capacity {
            limit: VELOCITY_LIMIT,
            ..
        })
    ));
}

/// The digest of the stream of a run of `p` with seed 3 on `meshes`.
fn digest(p: &Params<'_>, meshes: impl MeshStore) -> u64 {
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, meshes);
    m.start(p, 3).unwrap();
    let mut sink = Encoder::new(Vec::new());
    while !m.step(&mut sink).unwrap().finished() {}
    sink.digest()
}

#[test]
fn the_mcu_mesh_store_gives_the_same_run_without_inward_normals_or_edge_scratch() {
    // 12 rings × 16 segments: 178 vertices, 352 faces.
    type Mcu = ArrayMeshStore<178, 352>;
    let p = params(3);
    assert_eq!(digest(&p, MeshVecs::new()), digest(&p, Mcu::EMPTY));
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, ArrayMeshStore::<177, 352>::EMPTY);
    assert!(matches!(
        m.start(&p, 3),
        Err(Error::Capacity {
            limit: meshes::MESH_VERTEX_LIMIT,
            capacity: 177
        })
    ));
    let mut m = SurfaceMosaic::on_mesh(Store::EMPTY, ArrayMeshStore::<178, 351>::EMPTY);
    assert!(matches!(
        m.start(&p, 3),
        Err(Error::Capacity {
            limit: meshes::MESH_FACE_LIMIT,
            capacity: 351
        })
    ));
}

#[test]
fn the_mcu_surface_mosaic_holds_at_most_48_kib_within_the_planar_mcu_mosaic() {
    type Mcu = SurfaceMosaic<'static, McuSurfaceStore, McuMeshStore>;
    let size = core::mem::size_of::<Mcu>();
    assert!(size <= 48 * 1024, "{size} B");
    assert!(
        size <= core::mem::size_of::<crate::mosaic::Mosaic<'static, crate::mosaic::McuStore>>()
    );
    const { assert!(McuSurfaceStore::CAPACITY >= 1000) };
}
