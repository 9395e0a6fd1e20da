//! L-system throughput on the host: derived modules per second (streaming
//! and buffered) and turtle segments per second (the whole simulation into
//! a counting sink), on ABOP Fig. 1.25's shrub (77 399 modules, 3 891
//! segments, 1 284 polygons at n = 7).
//!
//! `CARGO_TARGET_DIR=… cargo bench -p morphogen-benches --bench lsys`

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::lsys::{
    Buffered, Derivation, Grammar, LSystem, Module, Neighbours, Next, Streaming,
};
use morphogen::preset::Model;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};

struct Count(u64);

impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        if matches!(r, Record::Segment { .. }) {
            self.0 += 1;
        }
        Ok(())
    }
}

/// The grammar text of the built-in L-system scenario `name`.
fn grammar_text(name: &str) -> String {
    let scenario = morphogen_scenario::builtin(name).expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::LSystem(text) = p.model else {
            unreachable!("{name} is an L-system")
        };
        text.to_owned()
    })
}

fn shrub() -> Grammar {
    let mut g = Grammar::new();
    g.parse(&grammar_text("abop-shrub"))
        .expect("the shrub parses");
    g
}

/// Derives the shrub's 7 steps with `d`, reading every module.
fn derive_all(d: &mut impl Derivation, g: &Grammar) -> u32 {
    d.restart(g, 7, 0).expect("restart");
    let mut n = 0u32;
    loop {
        match d.next_module(g).expect("module") {
            Next::Module(m) => n += u32::from(black_box(m).symbol),
            Next::Pending => {}
            Next::End => return n,
        }
    }
}

fn derive(c: &mut Criterion) {
    let g = shrub();
    let mut group = c.benchmark_group("shrub_derivation");
    group.throughput(Throughput::Elements(77_399));
    group.bench_function("streaming_modules", |b| {
        let mut d = Streaming::new();
        b.iter(|| derive_all(&mut d, &g));
    });
    let mut a = vec![Module::default(); 80_000];
    let mut bb = vec![Module::default(); 80_000];
    let mut links = vec![Neighbours::default(); 80_000];
    group.bench_function("buffered_modules", |b| {
        let mut d = Buffered::new(&mut a, &mut bb, &mut links);
        b.iter(|| derive_all(&mut d, &g));
    });
    group.finish();
}

fn draw(c: &mut Criterion) {
    let mut group = c.benchmark_group("shrub_turtle");
    group.throughput(Throughput::Elements(3_891));
    let shrub = grammar_text("abop-shrub");
    group.bench_function("segments_streaming", |b| {
        let mut sim = Box::new(LSystem::new());
        b.iter(|| {
            sim.start(&shrub, 0).expect("load");
            let mut sink = Count(0);
            while !sim.step(&mut sink).expect("step").finished() {}
            sink.0
        });
    });
    group.finish();
}

fn parse(c: &mut Criterion) {
    let monopodial = grammar_text("abop-monopodial");
    c.bench_function("parse_monopodial", |b| {
        let mut g = Grammar::new();
        b.iter(|| g.parse(black_box(&monopodial)).expect("parse"));
    });
}

criterion_group!(benches, derive, draw, parse);
criterion_main!(benches);
