//! Unit tests of the mosaic stepper (cross-crate ones are in
//! `core/tests/mosaic.rs`).

use super::*;
use crate::stream::SinkError;
use store::ArrayStore;

/// Counts records.
#[derive(Default)]
struct Count {
    cells: u32,
    frames: u32,
}

impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        match r {
            Record::Cell { .. } => self.cells += 1,
            Record::FrameEnd { .. } => self.frames += 1,
            _ => {}
        }
        Ok(())
    }
}

#[test]
fn grid_and_naive_relaxation_agree_bit_for_bit() {
    let mut a = Mosaic::new(ArrayStore::<512, 129>::EMPTY);
    let params: &'static Params = Box::leak(Box::new(Params {
        initial_cells: 300,
        days: 0,
        ..presets::CROTON_MCU
    }));
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
fn croton_mcu_runs_and_streams_every_day() {
    let mut m = Mosaic::new(presets::McuStore::EMPTY);
    m.start(&presets::CROTON_MCU, 1).unwrap();
    let mut sink = Count::default();
    while !m.step(&mut sink).unwrap().finished() {}
    assert_eq!(sink.frames, 36);
    assert!((1_200..2_048).contains(&m.len()), "{}", m.len());
    // Every division is recorded; no mutation in croton.
    let d = m.divisions();
    assert_eq!(d[0][0] + d[1][1] + 180, m.len() as u32);
    assert_eq!(d[0][1] + d[1][0], 0);
}

#[test]
fn a_full_store_is_an_error_naming_the_limit() {
    let mut m = Mosaic::new(ArrayStore::<200, 51>::EMPTY);
    m.start(&presets::CROTON_MCU, 1).unwrap();
    let mut sink = Count::default();
    let e = loop {
        match m.step(&mut sink) {
            Ok(p) => assert!(!p.finished(), "should have overflowed"),
            Err(e) => break e,
        }
    };
    assert_eq!(
        e,
        Error::Capacity {
            limit: CELL_LIMIT,
            capacity: 200
        }
    );
    let mut small = Mosaic::new(ArrayStore::<100, 26>::EMPTY);
    assert!(small.start(&presets::CROTON_MCU, 1).is_err());
    assert!(small.step(&mut sink).is_err());
}
