//! Wall-clock cost of each numeric kernel, per operation (criterion).
//! Each bench runs a batch of 1024 inputs; divide the reported time by
//! 1024, or read criterion's throughput line (elements/s).

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use morphogen::fx::{Angle, Fx, Real};
use morphogen::geom::Rigid;
use morphogen::rng::KeyedRng;
use morphogen::stream::{Encoder, MAX_FRAME, Record};
use nalgebra::Vector3;

const BATCH: usize = 1024;

fn angles() -> Vec<Angle> {
    (0..BATCH as u32)
        .map(|i| Angle(i.wrapping_mul(0x9E37_79B9)))
        .collect()
}

fn values(lo: i32, hi: i32) -> Vec<Fx> {
    let span = (hi as i64 - lo as i64) as u64;
    (0..BATCH as u64)
        .map(|i| Fx::from_bits((lo as i64 + (i * 2_654_435_761 % span) as i64) as i32))
        .collect()
}

fn numbers(c: &mut Criterion) {
    let mut g = c.benchmark_group("fx");
    g.throughput(Throughput::Elements(BATCH as u64));
    let a = angles();
    g.bench_function("sin", |b| {
        b.iter(|| {
            a.iter()
                .map(|&x| Fx::sin(black_box(x)))
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    g.bench_function("cos", |b| {
        b.iter(|| {
            a.iter()
                .map(|&x| Fx::cos(black_box(x)))
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    let positive = values(1, i32::MAX);
    g.bench_function("sqrt", |b| {
        b.iter(|| {
            positive
                .iter()
                .map(|&x| black_box(x).sqrt())
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    g.bench_function("recip", |b| {
        b.iter(|| {
            positive
                .iter()
                .map(|&x| black_box(x).recip())
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    let wide = values(-20 << 16, 20 << 16);
    g.bench_function("sigmoid", |b| {
        b.iter(|| {
            wide.iter()
                .map(|&x| black_box(x).sigmoid())
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    let exps = values(-11 << 16, 10 << 16);
    g.bench_function("exp", |b| {
        b.iter(|| {
            exps.iter()
                .map(|&x| Real::exp(black_box(x)))
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    g.bench_function("ln", |b| {
        b.iter(|| {
            positive
                .iter()
                .map(|&x| Real::ln(black_box(x)))
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    let pairs: Vec<(Fx, Fx)> = wide
        .iter()
        .zip(exps.iter())
        .map(|(&x, &y)| (x, y))
        .collect();
    g.bench_function("atan2", |b| {
        b.iter(|| {
            pairs
                .iter()
                .map(|&(y, x)| Fx::atan2(black_box(y), black_box(x)).0)
                .fold(0u32, u32::wrapping_add)
        })
    });
    g.finish();
}

fn transforms(c: &mut Criterion) {
    let mut g = c.benchmark_group("geom");
    g.throughput(Throughput::Elements(BATCH as u64));
    let motions: Vec<Rigid> = angles()
        .iter()
        .map(|&a| {
            Rigid::positioner(
                Vector3::new(Fx::ONE, Fx::HALF, Fx::from_int(3)),
                a,
                a + a,
                -a,
            )
        })
        .collect();
    g.bench_function("rigid_compose_fx", |b| {
        b.iter(|| {
            motions
                .iter()
                .fold(Rigid::identity(), |acc, m| black_box(acc.compose(m)))
        })
    });
    let motions64: Vec<Rigid<f64>> = angles()
        .iter()
        .map(|&a| Rigid::positioner(Vector3::new(1.0, 0.5, 3.0), a, a + a, -a))
        .collect();
    g.bench_function("rigid_compose_f64", |b| {
        b.iter(|| {
            motions64
                .iter()
                .fold(Rigid::identity(), |acc, m| black_box(acc.compose(m)))
        })
    });
    let p = Vector3::new(Fx::from_int(3), Fx::from_int(-2), Fx::ONE);
    g.bench_function("rigid_apply_point", |b| {
        b.iter(|| {
            motions
                .iter()
                .map(|m| m.apply_point(black_box(&p)))
                .fold(Vector3::zeros(), |s, v| s + v)
        })
    });
    g.finish();
}

fn randomness(c: &mut Criterion) {
    let mut g = c.benchmark_group("rng");
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function("keyed_stream_new", |b| {
        b.iter(|| {
            (0..BATCH as u64)
                .map(|i| KeyedRng::new(7, black_box(i)).next_u32())
                .fold(0u32, u32::wrapping_add)
        })
    });
    let mut rng = KeyedRng::new(1, 2);
    g.bench_function("below_6", |b| {
        b.iter(|| (0..BATCH).map(|_| rng.below(6)).sum::<u32>())
    });
    g.bench_function("exponential", |b| {
        b.iter(|| {
            (0..BATCH)
                .map(|_| rng.exponential(Fx::from_int(10)))
                .fold(Fx::ZERO, |s, v| s + v)
        })
    });
    g.bench_function("poisson_mean_1", |b| {
        b.iter(|| {
            (0..BATCH)
                .map(|_| rng.poisson(Fx::ONE).unwrap_or(0))
                .sum::<u32>()
        })
    });
    g.finish();
}

fn framing(c: &mut Criterion) {
    let mut g = c.benchmark_group("stream");
    g.throughput(Throughput::Elements(BATCH as u64));
    let segment = Record::Segment {
        a: [Fx::ONE; 3],
        b: [Fx::from_ratio(-7, 3); 3],
        width: Fx::HALF,
        colour: 3,
    };
    g.bench_function("encode_segment_frame", |b| {
        let mut frame = [0u8; MAX_FRAME];
        b.iter(|| {
            (0..BATCH)
                .map(|_| {
                    Encoder::<Vec<u8>>::encode_frame(black_box(&segment), &mut frame).unwrap_or(0)
                })
                .sum::<usize>()
        })
    });
    g.finish();
}

criterion_group!(benches, numbers, transforms, randomness, framing);
criterion_main!(benches);
