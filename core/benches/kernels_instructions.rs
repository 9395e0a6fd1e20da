//! Instruction counts of the numeric kernels under Valgrind (gungraun):
//! stable on noisy machines. Needs valgrind and the matching runner:
//! `cargo install gungraun-runner --version 0.20.0`, then
//! `cargo bench -p morphogen --bench kernels_instructions`.
//! Each bench evaluates 1024 inputs.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    missing_docs,
    reason = "a benchmark stops on a setup that is not as it expects; its harness macros generate undocumented items"
)]

use std::hint::black_box;

use gungraun::{library_benchmark, library_benchmark_group, main};
use morphogen::fx::{Angle, Fx, Real};
use morphogen::geom::Rigid;
use nalgebra::Vector3;

const BATCH: u32 = 1024;

#[library_benchmark]
fn sin_1024() -> Fx {
    (0..BATCH)
        .map(|i| Fx::sin(black_box(Angle(i.wrapping_mul(0x9E37_79B9)))))
        .fold(Fx::ZERO, |s, v| s + v)
}

#[library_benchmark]
fn sqrt_1024() -> Fx {
    (0..BATCH)
        .map(|i| black_box(Fx::from_bits((i * 2_097_143) as i32)).sqrt())
        .fold(Fx::ZERO, |s, v| s + v)
}

#[library_benchmark]
fn sigmoid_1024() -> Fx {
    (0..BATCH)
        .map(|i| black_box(Fx::from_bits((i as i32 - 512) * 2_560)).sigmoid())
        .fold(Fx::ZERO, |s, v| s + v)
}

#[library_benchmark]
fn rigid_compose_1024() -> Rigid {
    let t = Vector3::new(Fx::ONE, Fx::HALF, Fx::from_int(3));
    (0..BATCH)
        .map(|i| Angle(i.wrapping_mul(0x9E37_79B9)))
        .fold(Rigid::identity(), |acc, a| {
            black_box(acc.compose(&Rigid::positioner(t, a, a, a)))
        })
}

library_benchmark_group!(
    name = kernels,
    benchmarks = [sin_1024, sqrt_1024, sigmoid_1024, rigid_compose_1024]
);
main!(library_benchmark_groups = kernels);
