//! Shrinkwrap speed: each bone preset run to the end (skeleton growth,
//! wrap, streaming into a counting sink), in triangles of the final meshes
//! per second, as the MCU runs it and as a host does (with the field cache,
//! `HOST_FIELD_CACHE`); and one `long-bone` wrap in fixed point against
//! `f64`.
//! The state's size (the peak memory, which is all static) is printed.
//!
//! `CARGO_TARGET_DIR=… cargo bench -p morphogen-benches --bench bones`

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::bones::{
    Bones, BonesParams, Grower, HOST_FIELD_CACHE, MCU_TRIANGLES, MCU_VERTICES, Skeleton,
};
use morphogen::fx::{Fx, Real};
use morphogen::preset::Model;
use morphogen::shrinkwrap::{Element, Shrinkwrap};
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};

type McuBones<'a> = Bones<'a, MCU_VERTICES, MCU_TRIANGLES>;

/// The built-in bone scenarios.
const PRESETS: [&str; 3] = ["long-bone", "long-bone-random", "bone-growth"];

/// Calls `f` with the parameters of the built-in bone scenario `name`.
fn with_bones<R>(name: &str, f: impl FnOnce(&BonesParams<'_>) -> R) -> R {
    let scenario = morphogen_scenario::builtin(name).expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::Bones(params) = p.model else {
            unreachable!("{name} is a bone")
        };
        f(params)
    })
}

/// Counts triangles, keeps nothing.
struct Count(u64);
impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.0 += u64::from(matches!(r, Record::Triangle { .. }));
        Ok(())
    }
}

/// Runs `params` to the end with a field cache of `C` vertices; returns
/// the triangles streamed.
fn run<const C: usize>(params: &BonesParams<'_>) -> u64 {
    let mut bones = Box::new(Bones::<'_, MCU_VERTICES, MCU_TRIANGLES, C>::new());
    bones.start(params, 1).expect("the preset's grammar parses");
    let mut sink = Count(0);
    while !bones.step(&mut sink).expect("the preset runs").finished() {}
    sink.0
}

fn presets_run(c: &mut Criterion) {
    println!(
        "state: Bones<{MCU_VERTICES}, {MCU_TRIANGLES}> = {} bytes",
        size_of::<McuBones>()
    );
    let mut group = c.benchmark_group("bones");
    for name in PRESETS {
        with_bones(name, |params| {
            group.throughput(Throughput::Elements(run::<0>(params)));
            group.bench_function(format!("{name} run (triangles/s)"), |b| {
                b.iter(|| run::<0>(params))
            });
            group.bench_function(format!("{name} run on a host (triangles/s)"), |b| {
                b.iter(|| run::<HOST_FIELD_CACHE>(params))
            });
        });
    }
    group.finish();
}

fn wrap(c: &mut Criterion) {
    let (skeleton, wrap) = with_bones("long-bone", |params| {
        let mut grower = Grower::new();
        grower.load(params.grammar).expect("parses");
        let mut skeleton = Skeleton::new();
        grower.grow(12, 0, &mut skeleton).expect("grows");
        (skeleton, params.wrap)
    });
    let skeleton_f64: Vec<Element<f64>> =
        skeleton.iter().map(|e| e.convert(f64::from_fx)).collect();
    let mut group = c.benchmark_group("shrinkwrap long-bone");
    group.bench_function("fixed point", |b| {
        let mut w = Box::new(Shrinkwrap::<Fx, MCU_VERTICES, MCU_TRIANGLES>::new(Fx::ZERO));
        b.iter(|| w.run(&skeleton, &wrap).expect("wraps"));
    });
    group.bench_function("f64", |b| {
        let mut w = Box::new(Shrinkwrap::<f64, MCU_VERTICES, MCU_TRIANGLES>::new(0.0));
        b.iter(|| w.run(&skeleton_f64, &wrap).expect("wraps"));
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = presets_run, wrap
}
criterion_main!(benches);
