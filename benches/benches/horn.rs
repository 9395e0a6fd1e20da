//! Rings per second for a full `ram-horn` frame (t = 8 years: 8 complete
//! modules, 200 rings of 24 points), in fixed point and in the f64
//! reference. Run: `cargo bench -p morphogen-benches --bench horn`.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::Error;
use morphogen::fx::{Fx, Real};
use morphogen::horn::{Emit, HornKernel, HornParams, Moment};
use morphogen::preset::Model;

/// Places and emits one frame, folding every point into a checksum.
fn frame<R: Real>(kernel: &mut HornKernel<'_, R>, t: Moment) -> Result<u64, Error> {
    kernel.place(t)?;
    let mut sum = 0u64;
    kernel.emit(&mut |e| {
        if let Emit::Point(p) = e {
            sum = sum.wrapping_add(p.x.to_f64().to_bits() ^ p.z.to_f64().to_bits());
        }
        Ok(())
    })?;
    Ok(sum)
}

fn full_frame(c: &mut Criterion) {
    let scenario = morphogen_scenario::builtin("ram-horn").expect("a built-in scenario");
    scenario.with_preset(|p| {
        let Model::Horn(ram_horn) = p.model else {
            unreachable!("ram-horn is a horn")
        };
        bench_full_frame(c, ram_horn);
    });
}

fn bench_full_frame(c: &mut Criterion, ram_horn: &HornParams<'_>) {
    let last = Moment::new(ram_horn.frames(), u32::from(ram_horn.frames_per_year));
    let mut fixed = HornKernel::<Fx>::new(ram_horn).expect("valid preset");
    fixed.place(last).expect("in range");
    let rings = u64::from(fixed.ring_count());
    let mut group = c.benchmark_group("ram-horn full frame");
    group.throughput(Throughput::Elements(rings));
    group.bench_function("fx rings", |b| {
        b.iter(|| frame(&mut fixed, black_box(last)).expect("frame"))
    });
    let mut reference = HornKernel::<f64>::new(ram_horn).expect("valid preset");
    group.bench_function("f64 rings", |b| {
        b.iter(|| frame(&mut reference, black_box(last)).expect("frame"))
    });
    group.finish();
}

criterion_group!(benches, full_frame);
criterion_main!(benches);
