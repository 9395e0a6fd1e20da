//! Instruction counts of the models' hot paths under Valgrind (gungraun):
//! the speed figures that a noisy machine cannot time. Needs valgrind and
//! `cargo install gungraun-runner --version 0.20.0`; run by
//! `scripts/bench.sh`, or `cargo bench -p morphogen-benches --bench
//! model_instructions`. Setup (parsing, the initial relaxations) is not
//! counted.
//!
//! - `relaxation_step`: one relaxation step of 2 000 croton cells (a
//!   croton-like periodic square after its initial relaxations) as the
//!   host runs it on one thread, each pair of neighbours once: divide by
//!   [`CELLS`] for instructions per cell-relaxation step;
//!   `relaxation_step_per_cell` the same step as the MCU runs it, each
//!   cell summing its own pushes;
//! - `surface_relaxation_step`: the same on a mesh, 2 000 cells on
//!   `watermelon-fruit`'s ellipsoid (3 072 triangles) at croton's w_r = 1
//!   (as many neighbours), each pair once as on the host: divide by
//!   [`CELLS`] and compare with the plane's; `…_per_cell` as on an MCU;
//! - `shrub`: ABOP Fig. 1.25's shrub at n = 7, derived and drawn by the
//!   turtle into a sink that drops the records.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;

use gungraun::{library_benchmark, library_benchmark_group, main};
use morphogen::lsys::LSystem;
use morphogen::mosaic::kernels::mesh as surface_relaxation;
use morphogen::mosaic::kernels::plane::{self as relaxation, Grid};
use morphogen::mosaic::{
    CellStore, Forces, MAX_TYPES, Mesh, MeshBuffers, MeshParts, Mosaic, OnMesh, Params, Surface,
    SurfaceForces, SurfaceMesh, SurfaceMosaic, build_mesh,
};
use morphogen::preset::Model;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};
use morphogen_scenario::run::MeshVecs;
use morphogen_scenario::store::VecStore;

/// Cells of the relaxation bench.
const CELLS: u32 = 2_000;

struct Null;

impl Sink for Null {
    fn record(&mut self, _: &Record) -> Result<(), SinkError> {
        Ok(())
    }
}

/// A relaxation ready to run: the cells after their initial relaxations,
/// the grid and the forces.
struct Relaxation {
    mosaic: Mosaic<'static, VecStore>,
    forces: Forces<'static>,
    /// The host's sums of pair pushes ([`relaxation::relax_pairs`]).
    sums: Vec<[i64; 2]>,
}

fn croton_cells() -> Relaxation {
    let scenario = Box::leak(Box::new(
        morphogen_scenario::builtin("croton").expect("a built-in scenario"),
    ));
    let croton: Params<'static> = scenario.with_preset(|p| {
        let Model::Mosaic(params) = p.model else {
            unreachable!("croton is a mosaic")
        };
        Params {
            types: params.types.to_vec().leak(),
            mask: None,
            anisotropy: None,
            frames: morphogen::mosaic::Frames::EveryDay,
            surface: None,
            ..*params
        }
    });
    let side = f64::from(CELLS).sqrt().round() as i32;
    let params: &'static Params<'static> = Box::leak(Box::new(Params {
        initial_cells: CELLS,
        days: 0,
        initial_relaxations: 5,
        domain: morphogen::mosaic::Domain::periodic(
            morphogen::fx::Fx::from_int(side),
            morphogen::fx::Fx::from_int((CELLS as i32 + side / 2) / side),
        ),
        ..croton
    }));
    let mut mosaic = Mosaic::new(VecStore::new(CELLS as usize));
    mosaic.start(params, 1).expect("valid");
    while !mosaic.step(&mut Null).expect("runs").finished() {}
    let radius = mosaic.radius().to_bits();
    let bins = mosaic.store_mut().slices().bins.len() - 1;
    let grid: &'static Grid = Box::leak(Box::new(Grid::plan(&params.domain, radius, bins)));
    Relaxation {
        forces: Forces {
            domain: &params.domain,
            grid,
            radius,
            repel: [[1 << 16; MAX_TYPES]; MAX_TYPES],
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: 0,
            field: None,
            momentum: 0,
        },
        mosaic,
        sums: vec![[0; 2]; CELLS as usize],
    }
}

#[library_benchmark]
#[bench::croton_2000(setup = croton_cells)]
fn relaxation_step(mut r: Relaxation) -> Relaxation {
    let len = r.mosaic.len();
    relaxation::relax_pairs(
        &mut r.mosaic.store_mut().slices(),
        black_box(len),
        &r.forces,
        &mut r.sums,
    );
    r
}

#[library_benchmark]
#[bench::croton_2000(setup = croton_cells)]
fn relaxation_step_per_cell(mut r: Relaxation) -> Relaxation {
    let len = r.mosaic.len();
    relaxation::relax(
        &mut r.mosaic.store_mut().slices(),
        black_box(len),
        &r.forces,
    );
    r
}

/// A surface relaxation ready to run.
struct SurfaceRelaxation {
    mosaic: SurfaceMosaic<'static, VecStore<OnMesh>, MeshVecs>,
    forces: SurfaceForces<'static>,
    /// The host's sums of pair pushes ([`surface_relaxation::relax_pairs`]).
    sums: Vec<[i64; 3]>,
}

fn fruit_cells() -> SurfaceRelaxation {
    let scenario = Box::leak(Box::new(
        morphogen_scenario::builtin("watermelon-fruit").expect("a built-in scenario"),
    ));
    let fruit: Params<'static> = scenario.with_preset(|p| {
        let Model::Mosaic(params) = p.model else {
            unreachable!("watermelon-fruit is a mosaic")
        };
        Params {
            types: params.types.to_vec().leak(),
            mask: None,
            anisotropy: None,
            frames: morphogen::mosaic::Frames::EveryDay,
            initial_cells: CELLS,
            days: 0,
            initial_relaxations: 5,
            momentum: morphogen::fx::Fx::ZERO,
            radius_weight: morphogen::fx::Fx::ONE, // croton's: as many neighbours
            surface: params.surface.map(|s| match s.mesh {
                SurfaceMesh::Shape(t) => Surface {
                    mesh: SurfaceMesh::Shape(t),
                    control: s.control,
                },
                SurfaceMesh::Triangles { .. } => unreachable!("a built-in shape"),
            }),
            ..*params
        }
    });
    let params: &'static Params<'static> = Box::leak(Box::new(fruit));
    let surface = params.surface.as_ref().expect("a surface");
    let (nv, nf) = surface.counts();
    let leak = |n: usize| -> &'static mut [[i32; 3]] { vec![[0; 3]; n].leak() };
    let buffers = MeshBuffers {
        vertices: leak(nv),
        faces: vec![[0; 3]; nf].leak(),
        parts: MeshParts {
            neighbours: vec![[0; 3]; nf].leak(),
            normals: leak(nf),
            inward: vec![[[0; 3]; 3]; nf].leak(),
            edges: vec![0; 3 * nf].leak(),
        },
    };
    let mesh: &'static Mesh<'static> =
        Box::leak(Box::new(build_mesh(surface, buffers).expect("a mesh")));
    let mut mosaic = SurfaceMosaic::on_mesh(VecStore::new(CELLS as usize), MeshVecs::default());
    mosaic.start(params, 1).expect("valid");
    while !mosaic.step(&mut Null).expect("runs").finished() {}
    let radius = mosaic.radius().to_bits();
    SurfaceRelaxation {
        forces: SurfaceForces {
            mesh,
            radius,
            repel: [[1 << 16; MAX_TYPES]; MAX_TYPES],
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: 0,
            field: None,
            momentum: 0,
        },
        mosaic,
        sums: vec![[0; 3]; CELLS as usize],
    }
}

#[library_benchmark]
#[bench::fruit_2000(setup = fruit_cells)]
fn surface_relaxation_step(mut r: SurfaceRelaxation) -> SurfaceRelaxation {
    let len = r.mosaic.len();
    surface_relaxation::relax_pairs(
        &mut r.mosaic.store_mut().slices(),
        black_box(len),
        &r.forces,
        &mut r.sums,
    );
    r
}

#[library_benchmark]
#[bench::fruit_2000(setup = fruit_cells)]
fn surface_relaxation_step_per_cell(mut r: SurfaceRelaxation) -> SurfaceRelaxation {
    let len = r.mosaic.len();
    surface_relaxation::relax(
        &mut r.mosaic.store_mut().slices(),
        black_box(len),
        &r.forces,
    );
    r
}

fn shrub_grammar() -> String {
    let scenario = morphogen_scenario::builtin("abop-shrub").expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::LSystem(text) = p.model else {
            unreachable!("abop-shrub is an L-system")
        };
        text.to_owned()
    })
}

#[library_benchmark]
#[bench::n7(setup = shrub_grammar)]
fn shrub(text: String) -> u32 {
    let mut sim = Box::new(LSystem::new());
    sim.start(&text, 0).expect("the shrub loads");
    let mut steps = 0;
    while !sim.step(&mut Null).expect("runs").finished() {
        steps += 1;
    }
    black_box(steps)
}

library_benchmark_group!(
    name = models,
    benchmarks = [
        relaxation_step,
        relaxation_step_per_cell,
        surface_relaxation_step,
        surface_relaxation_step_per_cell,
        shrub
    ]
);
main!(library_benchmark_groups = models);
