//! The host's relaxation on one and on two threads: the whole
//! `croton-ageing` run (10 000 cells growing for 30 days, 280 relaxation
//! steps of 50 000 cells on average) as the host runs it, on a pool of one
//! thread and one of two, in turn, with the time spent relaxing counted
//! apart from the run's. Prints the medians and, pair by pair, the ratios'
//! median. Run with `cargo bench -p morphogen-benches --bench threads`.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::time::{Duration, Instant};

use morphogen::mosaic::{CellSlices, CellStore, Forces, Mosaic, Plane, Relax, host_capacity};
use morphogen::preset::Model;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};
use morphogen_scenario::store::VecStore;

/// Pairs of runs (one thread, two threads).
const PAIRS: usize = 7;

struct Null;

impl Sink for Null {
    fn record(&mut self, _: &Record) -> Result<(), SinkError> {
        Ok(())
    }
}

/// The host's store, with the time its relaxation steps took.
struct Timed {
    store: VecStore,
    relaxing: Duration,
}

impl CellStore for Timed {
    fn capacity(&self) -> usize {
        self.store.capacity()
    }
    fn slices(&mut self) -> CellSlices<'_, Plane> {
        self.store.slices()
    }
    fn positions(&self) -> &[[i32; 2]] {
        self.store.positions()
    }
    fn kinds(&self) -> &[u8] {
        self.store.kinds()
    }
}

impl Relax for Timed {
    fn relax(&mut self, n: usize, forces: &Forces<'_>, times: u16) {
        let t = Instant::now();
        self.store.relax(n, forces, times);
        self.relaxing += t.elapsed();
    }
}

/// One run on `threads` threads: (whole run, relaxation) in seconds.
fn run(threads: usize) -> (f64, f64) {
    let scenario = morphogen_scenario::builtin("croton-ageing").expect("a built-in scenario");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("threads");
    scenario.with_preset(|preset| {
        let Model::Mosaic(params) = preset.model else {
            unreachable!("croton-ageing is a mosaic")
        };
        pool.install(|| {
            let t = Instant::now();
            let store = Timed {
                store: VecStore::new(host_capacity(params)),
                relaxing: Duration::ZERO,
            };
            let mut m = Mosaic::new(store);
            m.start(params, preset.default_seed).expect("valid");
            while !m.step(&mut Null).expect("runs").finished() {}
            (
                t.elapsed().as_secs_f64(),
                m.store_mut().relaxing.as_secs_f64(),
            )
        })
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One figure of every pair: the medians on one and on two threads, and
/// of their ratios pair by pair.
fn line(what: &str, runs: &[[f64; 2]]) {
    let on = |k: usize| median(runs.iter().map(|r| r[k]).collect());
    let ratio = median(runs.iter().map(|r| r[0] / r[1]).collect());
    println!(
        "croton-ageing {what}: 1 thread {:.3} s, 2 threads {:.3} s: {ratio:.2}x (median of {PAIRS} pairs)",
        on(0),
        on(1)
    );
}

fn main() {
    run(2); // warm-up
    let pairs: Vec<[(f64, f64); 2]> = (0..PAIRS).map(|_| [run(1), run(2)]).collect();
    line(
        "relaxation",
        &pairs.iter().map(|[a, b]| [a.1, b.1]).collect::<Vec<_>>(),
    );
    line(
        "whole run ",
        &pairs.iter().map(|[a, b]| [a.0, b.0]).collect::<Vec<_>>(),
    );
}
