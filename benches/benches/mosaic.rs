//! Clonal mosaic costs. Run with
//! `cargo bench -p morphogen-benches --bench mosaic`. The big mosaics run on the
//! host (the core has no heap): this bench runs them as the host does, on
//! the scenario crate's `Vec`-backed store
//! ([`morphogen_scenario::store::VecStore`]).
//!
//! 1. `sansevieria` end to end on one core (the thesis's 25–30 minute run):
//!    median of 5 wall-clock runs, with cell-relaxation steps per second.
//! 2. One relaxation step, uniform grid vs naive O(N²), at 2 000 and 15 000
//!    cells (criterion).
//! 3. Bytes of RAM per cell.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use morphogen::embedded_io::{ErrorType, Write};
use morphogen::mosaic::kernels::plane::{self as relaxation, Grid};
use morphogen::mosaic::{CellStore, Forces, MAX_TYPES, McuStore, Mosaic, Params, host_capacity};
use morphogen::preset::{Model, Preset};
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Encoder, Record, Sink, SinkError};
use morphogen_scenario::store::VecStore;

/// Calls `f` with the built-in mosaic scenario `name` and its parameters.
fn with_mosaic<R>(name: &str, f: impl FnOnce(&Preset<'_>, &Params<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::Mosaic(params) = p.model else {
            unreachable!("{name} is a mosaic")
        };
        f(p, params)
    })
}

/// Counts bytes like a file would.
struct Bytes(u64);

impl ErrorType for Bytes {
    type Error = core::convert::Infallible;
}

impl Write for Bytes {
    fn write(&mut self, bytes: &[u8]) -> Result<usize, Self::Error> {
        self.0 += bytes.len() as u64;
        Ok(bytes.len())
    }

    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

struct Null;

impl Sink for Null {
    fn record(&mut self, _: &Record) -> Result<(), SinkError> {
        Ok(())
    }
}

/// Cell-relaxation steps of one sansevieria run: Σ over relaxations of N.
fn relaxation_steps(params: &Params<'_>) -> u64 {
    let mut m = Mosaic::new(VecStore::new(host_capacity(params)));
    m.start(params, 1).ok();
    let mut steps = 0u64;
    loop {
        let Ok(p) = m.step(&mut Null) else { return 0 };
        let rho = if p.done == 1 {
            params.initial_relaxations
        } else {
            params.daily_relaxations
        };
        steps += m.len() as u64 * u64::from(rho);
        if p.finished() {
            return steps;
        }
    }
}

fn end_to_end() {
    with_mosaic("sansevieria", |preset, params| {
        let seed = preset.default_seed;
        let mut times = Vec::new();
        let mut bytes = 0;
        for _ in 0..5 {
            let mut encoder = Encoder::new(Bytes(0));
            let t = Instant::now();
            // As the host runs it: header, then every step.
            morphogen_scenario::run::run(preset, seed, &mut encoder, &mut |_| {}).expect("runs");
            times.push(t.elapsed().as_secs_f64());
            bytes = encoder.into_writer().0;
        }
        times.sort_by(f64::total_cmp);
        let median = times[2];
        let steps = relaxation_steps(params);
        println!(
            "sansevieria end to end (1 core): median of 5 = {:.3} s (runs {:?}), {bytes} stream bytes; \
             {steps} cell-relaxation steps = {:.1} M steps/s",
            median,
            times
                .iter()
                .map(|t| (t * 1000.0).round() / 1000.0)
                .collect::<Vec<_>>(),
            steps as f64 / median / 1e6
        );
    });
    println!(
        "RAM per cell: {} B in the arrays + 4 B per grid bin; MCU store ArrayStore<2048, 513> = {} B = {:.3} B/cell",
        relaxation::CELL_BYTES,
        core::mem::size_of::<McuStore>(),
        core::mem::size_of::<McuStore>() as f64 / 2048.0
    );
}

/// A croton-like configuration of `n` cells: `croton` on a periodic
/// square of area about `n`, no days, 5 initial relaxations.
fn configuration<'a>(croton: &Params<'a>, n: u32) -> Params<'a> {
    let side = f64::from(n).sqrt();
    Params {
        initial_cells: n,
        days: 0,
        initial_relaxations: 5,
        domain: morphogen::mosaic::Domain::periodic(
            morphogen::fx::Fx::from_int(side.round() as i32),
            morphogen::fx::Fx::from_int((f64::from(n) / side.round()).round() as i32),
        ),
        ..*croton
    }
}

/// `params`' cells after its initial relaxations.
fn relaxed<'a>(params: &'a Params<'a>) -> Mosaic<'a, VecStore> {
    let n = params.initial_cells as usize;
    let mut m = Mosaic::new(VecStore::new(n));
    m.start(params, 1).expect("valid");
    while !m.step(&mut Null).expect("runs").finished() {}
    m
}

fn grid_vs_naive(c: &mut Criterion) {
    end_to_end();
    let mut g = c.benchmark_group("mosaic relaxation step");
    g.sample_size(10);
    with_mosaic("croton", |_, croton| {
        for n in [2_000u32, 15_000] {
            let params = configuration(croton, n);
            let mut m = relaxed(&params);
            let radius = m.radius().to_bits();
            let len = m.len();
            let store = m.store_mut();
            let bins = store.slices().bins.len() - 1;
            let grid = Grid::plan(&params.domain, radius, bins);
            let forces = Forces {
                domain: &params.domain,
                grid: &grid,
                radius,
                repel: [[1 << 16; MAX_TYPES]; MAX_TYPES],
                push_weight: params.push_weight.to_bits(),
                anisotropy_weight: 0,
                field: None,
                momentum: 0,
            };
            g.bench_function(format!("grid {n}"), |b| {
                b.iter(|| relaxation::relax(&mut store.slices(), black_box(len), &forces));
            });
            g.bench_function(format!("naive {n}"), |b| {
                b.iter(|| relaxation::relax_naive(&mut store.slices(), black_box(len), &forces));
            });
        }
    });
    g.finish();
}

criterion_group!(benches, grid_vs_naive);
criterion_main!(benches);
