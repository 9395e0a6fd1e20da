//! Unit tests of the mosaic stepper (cross-crate ones, and those of the
//! built-in scenarios, are in `core/tests/mosaic.rs`).

use super::*;
use params::{NO_MUTATION, ORIGINAL_PUSH_WEIGHT, pair_table};
use store::{ArrayStore, CellStore};

/// The two cell types of the croton (thesis Fig. 4.1): green background,
/// yellow foreground, both dividing every 10 days.
static CROTON_TYPES: [CellType; 2] = [
    CellType {
        colour: [40, 105, 45],
        division_days: 10,
        initial_probability: Fx::from_ratio(7, 10),
    },
    CellType {
        colour: [236, 200, 48],
        division_days: 10,
        initial_probability: Fx::from_ratio(3, 10),
    },
];

/// The `croton-mcu` scenario's parameters with `initial_cells` cells and
/// no days (a periodic 15 × 12, α_BB .8, α_FF .5, α_FB 0, w_r 1).
fn croton_mcu_day_0(initial_cells: u32) -> Params<'static> {
    Params {
        domain: Domain::periodic(Fx::from_int(15), Fx::from_int(12)),
        initial_cells,
        types: &CROTON_TYPES,
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
        radius_weight: Fx::ONE,
        push_weight: ORIGINAL_PUSH_WEIGHT,
        initial_relaxations: 40,
        daily_relaxations: 8,
        days: 0,
        mask: None,
        anisotropy: None,
        frames: Frames::EveryDay,
    }
}

#[test]
fn grid_and_naive_relaxation_agree_bit_for_bit() {
    let mut a = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
    let params = &croton_mcu_day_0(300);
    a.start(params, 3).unwrap();
    a.place(params).unwrap();
    a.update_radius(params);
    let mut b = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
    b.start(params, 3).unwrap();
    b.place(params).unwrap();
    b.update_radius(params);
    let forces = |r| Forces {
        domain: &params.domain,
        radius: r,
        repel: [[40_000; MAX_TYPES]; MAX_TYPES],
        push_weight: params.push_weight.to_bits(),
        anisotropy_weight: 0,
        field: None,
    };
    for _ in 0..5 {
        let f = forces(a.radius);
        let n = a.len();
        let mut s = a.store.slices();
        let grid = Grid::plan(&params.domain, a.radius, s.bins.len() - 1);
        relaxation::relax(&mut s, n, &grid, &f);
        relaxation::relax_naive(&mut b.store.slices(), n, &f);
    }
    assert_eq!(a.positions(), b.positions());
    assert_ne!(a.positions()[0], {
        let mut c = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
        c.start(params, 3).unwrap();
        c.place(params).unwrap();
        c.positions()[0]
    });
}

#[test]
fn coarse_grids_find_every_neighbour_on_both_sides_of_the_wrap() {
    // With one or two bins along a periodic axis, one bin holds neighbours
    // on both sides of a cell; with three or more, each bin's shift gives
    // the shortest displacement. Either way the grid agrees with the naive
    // step, on periodic and walled domains.
    let params = &croton_mcu_day_0(120);
    for domain in [
        params.domain,
        Domain::walled(Fx::from_int(15), Fx::from_int(12)),
    ] {
        let params = &Params { domain, ..*params };
        for max_bins in [1, 2, 4, 6, 9, 16, 128] {
            let mut a = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
            a.start(params, 5).unwrap();
            a.place(params).unwrap();
            let mut b = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
            b.start(params, 5).unwrap();
            b.place(params).unwrap();
            // A radius of 4.5 in a 15 × 12 domain: up to 3 bins per axis.
            let f = Forces {
                domain: &params.domain,
                radius: Fx::from_ratio(9, 2).to_bits(),
                repel: [[40_000; MAX_TYPES]; MAX_TYPES],
                push_weight: params.push_weight.to_bits(),
                anisotropy_weight: 0,
                field: None,
            };
            let grid = Grid::plan(&params.domain, f.radius, max_bins);
            let n = a.len();
            for _ in 0..3 {
                relaxation::relax(&mut a.store.slices(), n, &grid, &f);
                relaxation::relax_naive(&mut b.store.slices(), n, &f);
            }
            assert_eq!(
                a.positions(),
                b.positions(),
                "{:?} grid {}×{}",
                params.domain.periodic,
                grid.cols,
                grid.rows
            );
        }
    }
}
