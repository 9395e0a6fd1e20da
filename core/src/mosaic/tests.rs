//! Unit tests of the mosaic stepper (cross-crate ones, and those of the
//! built-in scenarios, are in `tests/tests/mosaic.rs`).

use super::*;
use grid::Grid;
use terrain::repulsion;

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
        momentum: Fx::ZERO,
        days: 0,
        mask: None,
        anisotropy: None,
        frames: Frames::EveryDay,
        surface: None,
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
    for _ in 0..5 {
        let n = a.len();
        let mut s = a.store.slices();
        let grid = Grid::plan(&params.domain, a.run.radius, s.bins.len() - 1);
        let f = Forces {
            domain: &params.domain,
            grid: &grid,
            radius: a.run.radius,
            repel: [[40_000; MAX_TYPES]; MAX_TYPES],
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: 0,
            field: None,
            momentum: 0,
        };
        relaxation::relax(&mut s, n, &f);
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
            let radius = Fx::from_ratio(9, 2).to_bits();
            let grid = Grid::plan(&params.domain, radius, max_bins);
            let f = Forces {
                domain: &params.domain,
                grid: &grid,
                radius,
                repel: [[40_000; MAX_TYPES]; MAX_TYPES],
                push_weight: params.push_weight.to_bits(),
                anisotropy_weight: 0,
                field: None,
                momentum: 0,
            };
            let n = a.len();
            for _ in 0..3 {
                relaxation::relax(&mut a.store.slices(), n, &f);
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

/// A store that keeps each cell's last move, as the host's does (the MCU's
/// [`ArrayStore`] has no room for them).
struct Moving {
    cells: [[i32; 2]; 512],
    kind: [u8; 512],
    next_division: [u16; 512],
    order: [u32; 512],
    push: [[i32; 2]; 512],
    bins: [u32; 129],
    velocity: [[i32; 2]; 512],
}

impl Moving {
    fn new() -> Box<Moving> {
        Box::new(Moving {
            cells: [[0; 2]; 512],
            kind: [0; 512],
            next_division: [0; 512],
            order: [0; 512],
            push: [[0; 2]; 512],
            bins: [0; 129],
            velocity: [[0; 2]; 512],
        })
    }
}

impl CellStore for Box<Moving> {
    fn capacity(&self) -> usize {
        512
    }
    fn slices(&mut self) -> CellSlices<'_, Plane> {
        CellSlices {
            pos: &mut self.cells,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.push,
            bins: &mut self.bins,
            velocity: &mut self.velocity,
        }
    }
    fn positions(&self) -> &[[i32; 2]] {
        &self.cells
    }
    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}

impl Relax for Box<Moving> {}

#[test]
fn momentum_needs_a_store_that_keeps_velocities() {
    let params = &Params {
        momentum: Fx::from_ratio(9, 10),
        ..croton_mcu_day_0(100)
    };
    let mut m = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
    assert_eq!(
        m.start(params, 1),
        Err(Error::Capacity {
            limit: VELOCITY_LIMIT,
            capacity: 0
        })
    );
    assert!(Mosaic::new(Moving::new()).start(params, 1).is_ok());
    let too_much = &Params {
        momentum: Fx::ONE,
        ..*params
    };
    assert!(Mosaic::new(Moving::new()).start(too_much, 1).is_err());
}

#[test]
fn a_heavy_ball_step_adds_beta_times_the_last_move_to_the_plain_step() {
    let params = &croton_mcu_day_0(300);
    let beta = Fx::from_ratio(9, 10).to_bits();
    let mut m = Mosaic::new(Moving::new());
    m.start(params, 3).unwrap();
    m.place(params).unwrap();
    m.update_radius(params);
    let grid = Grid::plan(&params.domain, m.run.radius, 128);
    let forces = |momentum| Forces {
        domain: &params.domain,
        grid: &grid,
        radius: m.run.radius,
        repel: [[40_000; MAX_TYPES]; MAX_TYPES],
        push_weight: params.push_weight.to_bits(),
        anisotropy_weight: 0,
        field: None,
        momentum,
    };
    let (heavy, plain) = (forces(beta), forces(0));
    let n = m.len();
    let mut store = m.store;
    for step in 0..4 {
        let before = store.cells;
        let last = store.velocity;
        // The plain step from the same positions, on a copy.
        let mut copy = Moving::new();
        copy.cells = before;
        copy.kind = store.kind;
        relaxation::relax(&mut copy.slices(), n, &plain);
        relaxation::relax(&mut store.slices(), n, &heavy);
        for i in 0..n {
            for c in 0..2 {
                let d = i64::from(params.domain.delta(c, copy.cells[i][c], before[i][c]));
                let carry = (i64::from(beta) * i64::from(last[i][c]) + (1 << 15)) >> 16;
                let r = i64::from(m.run.radius);
                let s = (d + carry).clamp(-r, r);
                let want = params.domain.confine(c, i64::from(before[i][c]) + s);
                assert_eq!(store.cells[i][c], want, "step {step} cell {i}");
                assert_eq!(
                    store.velocity[i][c],
                    params.domain.delta(c, want, before[i][c])
                );
            }
        }
        if step == 0 {
            // No last move yet: the first step is the plain one.
            assert_eq!(store.cells[..n], copy.cells[..n]);
        }
    }
    assert!(store.velocity[..n].iter().any(|v| *v != [0, 0]));
}

#[test]
fn a_pair_repels_with_one_minus_its_adhesion() {
    let alpha = pair_table(
        [
            Fx::from_ratio(8, 10),
            Fx::from_ratio(5, 10),
            Fx::ZERO,
            Fx::from_ratio(95, 100),
        ],
        Fx::from_ratio(1, 10),
    );
    let r = repulsion(&alpha, true);
    for (p, row) in r.iter().enumerate() {
        for (q, x) in row.iter().enumerate() {
            assert_eq!(*x, (Fx::ONE - alpha[p][q]).to_bits(), "{p},{q}");
        }
    }
    // The croton's B (α .8) is softer than its F (α .5).
    assert!(r[0][0] < r[1][1]);
}

#[test]
fn pairs_found_once_move_cells_as_the_per_cell_step_does() {
    // relax_pairs computes each pair's pushes once, from its lower grid
    // slot, with the floors of both sides taken from one product; relax
    // sums every cell's pushes itself. On periodic and walled domains,
    // coarse grids (displacements without shifts) and fine ones, radii
    // whose squares need 64 bits, a repulsion that is not symmetric (so a
    // swapped pair would show), coincident cells and momentum, the
    // positions and last moves are the same bits.
    let base = &croton_mcu_day_0(200);
    let mut repel = [[40_000; MAX_TYPES]; MAX_TYPES];
    repel[0][1] = 25_000;
    repel[1][0] = 90_000;
    let mut compared = 0;
    for domain in [
        base.domain,
        Domain::walled(Fx::from_int(15), Fx::from_int(12)),
    ] {
        let params = &Params { domain, ..*base };
        for (radius, max_bins) in [
            (Fx::from_ratio(9, 2), 1),
            (Fx::from_ratio(9, 2), 6),
            (Fx::ONE, 128),
            (Fx::from_ratio(3, 2), 40),
        ] {
            for momentum in [0, Fx::from_ratio(7, 10).to_bits()] {
                let mut a = Mosaic::new(Moving::new());
                a.start(params, 7).unwrap();
                a.place(params).unwrap();
                let n = a.len();
                // A child on its parent.
                a.store.cells[n - 1] = a.store.cells[0];
                let mut b = Mosaic::new(Moving::new());
                b.start(params, 7).unwrap();
                b.place(params).unwrap();
                b.store.cells[n - 1] = b.store.cells[0];
                let grid = Grid::plan(&params.domain, radius.to_bits(), max_bins);
                let f = Forces {
                    domain: &params.domain,
                    grid: &grid,
                    radius: radius.to_bits(),
                    repel,
                    push_weight: params.push_weight.to_bits(),
                    anisotropy_weight: 0,
                    field: None,
                    momentum,
                };
                let mut sums = [[0i64; 2]; 512];
                for step in 0..3 {
                    let before = a.store.cells;
                    relaxation::relax(&mut a.store.slices(), n, &f);
                    relaxation::relax_pairs(&mut b.store.slices(), n, &f, &mut sums);
                    assert_eq!(
                        a.store.cells[..n],
                        b.store.cells[..n],
                        "{:?} r {radius} {}×{} β {momentum} step {step}",
                        params.domain.periodic,
                        grid.cols,
                        grid.rows
                    );
                    assert_eq!(a.store.velocity[..n], b.store.velocity[..n]);
                    assert_ne!(a.store.cells[..n], before[..n], "the cells move");
                    compared += 1;
                }
            }
        }
    }
    assert_eq!(compared, 2 * 4 * 2 * 3);
}

#[test]
fn shares_of_the_slots_and_their_spills_give_the_sums_of_one_pass() {
    // A computer's threads each take a share of the grid slots with its
    // part of the sums; pushes on slots past a share's end come back
    // through `beyond`. Added up, any split gives the sums of one pass,
    // on fine and coarse grids (where a share's rows reach across the
    // wrap).
    let params = &croton_mcu_day_0(300);
    for max_bins in [4, 128] {
        let mut m = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
        m.start(params, 9).unwrap();
        m.place(params).unwrap();
        m.update_radius(params);
        let grid = Grid::plan(&params.domain, m.run.radius, max_bins);
        let f = Forces {
            domain: &params.domain,
            grid: &grid,
            radius: m.run.radius,
            repel: [[40_000; MAX_TYPES]; MAX_TYPES],
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: 0,
            field: None,
            momentum: 0,
        };
        let n = m.len();
        let mut cells = m.store.slices();
        let (snapshot, _) = relaxation::snapshot(&mut cells, n, &f);
        let mut whole = vec![[0i64; 2]; n];
        snapshot.pair_sums(0..n, &mut whole, &mut |slot, _| {
            panic!("slot {slot} is in the sums")
        });
        assert!(whole.iter().filter(|s| **s != [0, 0]).count() > n / 2);
        for shares in [2, 3, 7, n] {
            let share = n.div_ceil(shares);
            let mut sums = vec![[0i64; 2]; n];
            let mut spilt = Vec::new();
            for (k, part) in sums.chunks_mut(share).enumerate() {
                let first = k * share;
                snapshot.pair_sums(first..first + part.len(), part, &mut |slot, push| {
                    assert!(slot >= first + share, "slot {slot} spilt from share {k}");
                    spilt.push((slot, push));
                });
            }
            assert!(!spilt.is_empty(), "pairs across shares");
            for (slot, push) in spilt {
                sums[slot] = [sums[slot][0] + push[0], sums[slot][1] + push[1]];
            }
            assert_eq!(sums, whole, "{shares} shares, {max_bins} bins");
        }
    }
}
