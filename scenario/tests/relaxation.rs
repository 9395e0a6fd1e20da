//! The host's cell store ([`VecStore`] on the plane and on a mesh) relax a day's steps with the cells kept in grid order between
//! them, each pair of neighbours once and in shares of the grid on several
//! threads; the core's per-cell step (the MCU's) is the reference, bit for
//! bit.

use morphogen::fx::Fx;
use morphogen::mosaic::kernels::plane::{self as relaxation, Grid};
use morphogen::mosaic::{CellSlices, CellStore, Domain, Forces, MAX_TYPES, OnMesh, Plane, Relax};
use morphogen_scenario::store::VecStore;

/// Cells: enough for the store's grid-order path and several chunks.
const CELLS: usize = 3_000;

/// Steps in a row, as a day's ρ_s.
const STEPS: u16 = 5;

/// The cells' positions, types and last moves, spread by a fixed LCG over
/// `domain`, with a child on its parent (coincident cells).
fn cells(domain: &Domain) -> (Vec<[i32; 2]>, Vec<u8>, Vec<[i32; 2]>) {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |below: u32| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 33) % u64::from(below)) as u32
    };
    let size = domain.size.map(|s| s.to_bits() as u32);
    let mut pos: Vec<[i32; 2]> = (0..CELLS)
        .map(|_| [next(size[0]) as i32, next(size[1]) as i32])
        .collect();
    pos[CELLS - 1] = pos[7];
    let kind = (0..CELLS).map(|_| next(2) as u8).collect();
    let velocity = (0..CELLS)
        .map(|_| [next(8_000) as i32 - 4_000, next(8_000) as i32 - 4_000])
        .collect();
    (pos, kind, velocity)
}

#[test]
fn a_days_steps_in_grid_order_move_cells_as_the_per_cell_step_does() {
    let mut repel = [[40_000; MAX_TYPES]; MAX_TYPES];
    repel[0][1] = 25_000;
    repel[1][0] = 90_000;
    let mut compared = 0;
    for domain in [
        Domain {
            size: [Fx::from_int(40), Fx::from_int(30)],
            periodic: [true, true],
        },
        Domain::walled(Fx::from_int(40), Fx::from_int(30)),
    ] {
        // A fine grid (the shifted scan) and a coarse one (3 × 3 bins on
        // the torus: displacements wrap per pair).
        for max_bins in [CELLS / 2, 9] {
            for momentum in [0, Fx::from_ratio(7, 10).to_bits()] {
                let grid = Grid::plan(&domain, Fx::ONE.to_bits(), max_bins);
                let forces = Forces {
                    domain: &domain,
                    grid: &grid,
                    radius: Fx::ONE.to_bits(),
                    repel,
                    push_weight: Fx::ONE.to_bits(),
                    anisotropy_weight: 0,
                    field: None,
                    momentum,
                };
                let (pos, kind, velocity) = cells(&domain);

                // The reference: the per-cell step, STEPS times.
                let (mut want, mut want_kind, mut want_velocity) =
                    (pos.clone(), kind.clone(), velocity.clone());
                let (mut order, mut push) = (vec![0; CELLS], vec![[0; 2]; CELLS]);
                let (mut next_division, mut bins) = (vec![0; CELLS], vec![0; max_bins + 1]);
                for _ in 0..STEPS {
                    let mut slices = CellSlices {
                        pos: &mut want,
                        kind: &mut want_kind,
                        next_division: &mut next_division,
                        order: &mut order,
                        sorted: &mut push,
                        bins: &mut bins,
                        velocity: &mut want_velocity,
                    };
                    relaxation::relax(&mut slices, CELLS, &forces);
                }
                assert_ne!(want, pos, "the cells move");

                for threads in [1, 2, 3] {
                    let mut store = VecStore::<Plane>::new(CELLS + 100);
                    let slices = store.slices();
                    slices.pos[..CELLS].copy_from_slice(&pos);
                    slices.kind[..CELLS].copy_from_slice(&kind);
                    slices.velocity[..CELLS].copy_from_slice(&velocity);
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap()
                        .install(|| store.relax(CELLS, &forces, STEPS));
                    let case = format!(
                        "{:?}, {}×{} bins, β {momentum}, {threads} threads",
                        domain.periodic, grid.cols, grid.rows
                    );
                    assert!(store.positions()[..CELLS] == want[..], "positions: {case}");
                    let moved = &store.slices().velocity[..CELLS];
                    assert!(moved == &want_velocity[..], "last moves: {case}");
                    compared += 1;
                }
            }
        }
    }
    assert_eq!(compared, 2 * 2 * 2 * 3);
}

#[test]
fn a_days_steps_in_bucket_order_move_cells_on_a_mesh_as_the_per_cell_step_does() {
    use morphogen::mosaic::kernels::mesh as surface;
    use morphogen::mosaic::{
        Frames, MeshBuffers, MeshParts, Params, SurfaceForces, SurfaceMosaic, build_mesh,
    };
    use morphogen::preset::Model;
    use morphogen::sim::{Simulation, Start};
    use morphogen::stream::{Record, Sink, SinkError};
    use morphogen_scenario::run::MeshVecs;
    use morphogen_scenario::store::VecStore;

    /// The store on a mesh.
    type VecSurfaceStore = VecStore<OnMesh>;

    struct Null;
    impl Sink for Null {
        fn record(&mut self, _: &Record) -> Result<(), SinkError> {
            Ok(())
        }
    }

    // 2 000 cells spread and relaxed on watermelon-fruit's ellipsoid.
    let scenario = morphogen_scenario::builtin("watermelon-fruit").unwrap();
    scenario.with_preset(|p| {
        let Model::Mosaic(fruit) = p.model else {
            unreachable!("a mosaic")
        };
        let params = Params {
            mask: None,
            anisotropy: None,
            frames: Frames::EveryDay,
            initial_cells: 2_000,
            days: 0,
            initial_relaxations: 3,
            ..*fruit
        };
        let mut spread = SurfaceMosaic::on_mesh(VecSurfaceStore::new(2_000), MeshVecs::default());
        spread.start(&params, 1).unwrap();
        while !spread.step(&mut Null).unwrap().finished() {}
        let n = spread.len();
        let (places, kinds) = {
            let store = spread.store_mut();
            (store.positions()[..n].to_vec(), store.kinds()[..n].to_vec())
        };
        // A child on its parent, and last moves to carry.
        let mut places = places;
        places[n - 1] = places[3];
        let velocity: Vec<[i32; 3]> = (0..n as i32)
            .map(|i| [(i * 37) % 900 - 450, (i * 53) % 900 - 450, 0])
            .collect();

        let surface_spec = params.surface.as_ref().unwrap();
        let (nv, nf) = surface_spec.counts();
        let (mut vertices, mut faces) = (vec![[0; 3]; nv], vec![[0; 3]; nf]);
        let (mut neighbours, mut normals) = (vec![[0; 3]; nf], vec![[0; 3]; nf]);
        let (mut inward, mut edges) = (vec![[[0; 3]; 3]; nf], vec![0; 3 * nf]);
        let buffers = MeshBuffers {
            vertices: &mut vertices,
            faces: &mut faces,
            parts: MeshParts {
                neighbours: &mut neighbours,
                normals: &mut normals,
                inward: &mut inward,
                edges: &mut edges,
            },
        };
        let mesh = build_mesh(surface_spec, buffers).unwrap();
        let mut repel = [[40_000; MAX_TYPES]; MAX_TYPES];
        repel[0][1] = 25_000;
        repel[1][0] = 90_000;
        let mut compared = 0;
        for momentum in [0, Fx::from_ratio(7, 10).to_bits()] {
            let forces = SurfaceForces {
                mesh: &mesh,
                radius: spread.radius().to_bits(),
                repel,
                push_weight: params.push_weight.to_bits(),
                anisotropy_weight: 0,
                field: None,
                momentum,
            };
            let fill = |store: &mut VecSurfaceStore| {
                let cells = store.slices();
                cells.pos[..n].copy_from_slice(&places);
                cells.kind[..n].copy_from_slice(&kinds);
                cells.velocity[..n].copy_from_slice(&velocity);
            };
            let mut want = VecSurfaceStore::new(n);
            fill(&mut want);
            for _ in 0..STEPS {
                surface::relax(&mut want.slices(), n, &forces);
            }
            assert_ne!(want.positions()[..n], places[..], "the cells move");
            for threads in [1, 2, 3] {
                let mut store = VecSurfaceStore::new(n);
                fill(&mut store);
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| store.relax(n, &forces, STEPS));
                let case = format!("β {momentum}, {threads} threads");
                assert!(
                    store.positions()[..n] == want.positions()[..n],
                    "places: {case}"
                );
                assert!(
                    store.slices().velocity[..n] == want.slices().velocity[..n],
                    "last moves: {case}"
                );
                compared += 1;
            }
        }
        assert_eq!(compared, 2 * 3);
    });
}
