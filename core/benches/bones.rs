//! Shrinkwrap speed: each bone preset run to the end (skeleton growth,
//! wrap, streaming into a counting sink), in triangles of the final meshes
//! per second; and one `long-bone` wrap in fixed point against `f64`.
//! The state's size (the peak memory, which is all static) is printed.
//!
//! `CARGO_TARGET_DIR=… cargo bench -p morphogen --bench bones`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::bones::presets::{self, MCU_TRIANGLES, MCU_VERTICES};
use morphogen::bones::{Bones, Grower, Skeleton};
use morphogen::fx::{Fx, Real};
use morphogen::shrinkwrap::{Element, Shrinkwrap};
use morphogen::sim::Simulation;
use morphogen::stream::{Record, Sink, SinkError};

type McuBones = Bones<MCU_VERTICES, MCU_TRIANGLES>;

/// Counts triangles, keeps nothing.
struct Count(u64);
impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.0 += u64::from(matches!(r, Record::Triangle { .. }));
        Ok(())
    }
}

fn run(name: &str) -> u64 {
    let params = presets::find(name).expect("a bone preset");
    let mut bones = Box::new(McuBones::new());
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
    for (name, _) in presets::ALL {
        group.throughput(Throughput::Elements(run(name)));
        group.bench_function(format!("{name} run (triangles/s)"), |b| {
            b.iter(|| run(name))
        });
    }
    group.finish();
}

fn wrap(c: &mut Criterion) {
    let mut grower = Grower::new();
    grower.load(presets::LONG_BONE_GRAMMAR).expect("parses");
    let mut skeleton = Skeleton::new();
    grower.grow(12, 0, &mut skeleton).expect("grows");
    let skeleton_f64: Vec<Element<f64>> =
        skeleton.iter().map(|e| e.convert(f64::from_fx)).collect();
    let mut group = c.benchmark_group("shrinkwrap long-bone");
    group.bench_function("fixed point", |b| {
        let mut w = Box::new(Shrinkwrap::<Fx, MCU_VERTICES, MCU_TRIANGLES>::new(Fx::ZERO));
        b.iter(|| w.run(&skeleton, &presets::WRAP).expect("wraps"));
    });
    group.bench_function("f64", |b| {
        let mut w = Box::new(Shrinkwrap::<f64, MCU_VERTICES, MCU_TRIANGLES>::new(0.0));
        b.iter(|| w.run(&skeleton_f64, &presets::WRAP).expect("wraps"));
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = presets_run, wrap
}
criterion_main!(benches);
