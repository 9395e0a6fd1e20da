//! Body deformation speed: one frame of each body preset (every vertex
//! bound and blended), and a whole run into a counting sink.
//!
//! `CARGO_TARGET_DIR=… cargo bench -p morphogen-benches --bench body`

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::body::Body;
use morphogen::preset::Model;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};

/// Counts records, keeps nothing.
struct Count(u64);
impl Sink for Count {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.0 += u64::from(matches!(r, Record::MeshVertex { .. }));
        Ok(())
    }
}

fn frames(c: &mut Criterion) {
    let mut group = c.benchmark_group("body");
    for name in ["horse-growth", "cow-growth", "horse-trot"] {
        let scenario = morphogen_scenario::builtin(name).expect("a built-in scenario");
        scenario.with_preset(|p| {
            let Model::Body(params) = p.model else {
                unreachable!("{name} is a body")
            };
            let vertices = u64::from(params.model.mesh.vertex_count()) * u64::from(params.frames);
            group.throughput(Throughput::Elements(vertices));
            group.bench_function(format!("{name} run (vertices/s)"), |b| {
                b.iter(|| {
                    let mut body: Body = Body::new();
                    body.start(params, 0).expect("the preset is valid");
                    let mut sink = Count(0);
                    while !body.step(&mut sink).map(|p| p.finished()).unwrap_or(true) {}
                    sink.0
                });
            });
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = frames
}
criterion_main!(benches);
