//! Dense sweeps of every elementary function against `libm` f64, asserting
//! the error budgets README.md gives ("How it is built", Numbers).

#![allow(clippy::float_arithmetic)]

use super::{Angle, Fx, Real};

const LSB: f64 = 1.0 / 65_536.0;

/// The largest error in LSB of `f` against `reference` over `inputs`.
fn worst(
    inputs: impl Iterator<Item = Fx>,
    f: impl Fn(Fx) -> Fx,
    reference: impl Fn(f64) -> f64,
) -> (f64, Fx) {
    let mut worst = (0.0, Fx::ZERO);
    for x in inputs {
        let err = libm::fabs(f(x).to_f64() - reference(x.to_f64())) / LSB;
        if err > worst.0 {
            worst = (err, x);
        }
    }
    worst
}

/// Every `step`-th Fx bit pattern in `[lo, hi]`, both ends included.
fn sweep(lo: i32, hi: i32, step: usize) -> impl Iterator<Item = Fx> {
    (lo..=hi)
        .step_by(step)
        .chain(core::iter::once(hi))
        .map(Fx::from_bits)
}

#[test]
fn sin_and_cos_within_two_lsb_over_the_whole_turn() {
    let mut worst = 0.0f64;
    for units in (0..=u32::MAX).step_by(4_099) {
        let a = Angle(units);
        for (fx, reference) in [
            (Fx::sin(a), <f64 as Real>::sin(a)),
            (Fx::cos(a), <f64 as Real>::cos(a)),
        ] {
            worst = worst.max(libm::fabs(fx.to_f64() - reference) / LSB);
        }
    }
    assert!(worst <= 2.0, "sin/cos error {worst} LSB");
    assert!(worst > 0.0);
}

#[test]
fn sqrt_within_one_lsb_over_the_whole_range() {
    let (err, at) = worst(sweep(0, i32::MAX, 1_009), Real::sqrt, libm::sqrt);
    assert!(err <= 1.0, "sqrt error {err} LSB at {at}");
    // Exactly rounded means at most half an LSB.
    assert!(
        err <= 0.5 + 1e-9,
        "sqrt not exactly rounded: {err} LSB at {at}"
    );
}

#[test]
fn sigmoid_within_four_lsb_over_the_whole_range() {
    let (err, at) = worst(sweep(i32::MIN, i32::MAX, 3_001), Real::sigmoid, |x| {
        1.0 / (1.0 + libm::exp(-x))
    });
    assert!(err <= 4.0, "sigmoid error {err} LSB at {at}");
    let (near, at) = worst(sweep(-20 << 16, 20 << 16, 7), Real::sigmoid, |x| {
        1.0 / (1.0 + libm::exp(-x))
    });
    assert!(near <= 2.0, "sigmoid error {near} LSB at {at}");
}

#[test]
fn exp_within_relative_budget() {
    let mut worst = 0.0f64;
    for x in sweep(-12 << 16, (10 << 16) + 26_000, 97) {
        let exact = libm::exp(x.to_f64());
        let err = libm::fabs(Real::exp(x).to_f64() - exact);
        let budget = (exact * LSB).max(2.0 * LSB);
        worst = worst.max(err / budget);
    }
    assert!(worst <= 1.0, "exp error {worst} of budget");
}

#[test]
fn ln_within_budget() {
    let (err, at) = worst(sweep(1, i32::MAX, 1_013), Real::ln, libm::log);
    assert!(err <= 2.0, "ln error {err} LSB at {at}");
}

#[test]
fn atan2_within_budget_all_around() {
    let mut worst = 0u32;
    for deg_tenths in 0..3600 {
        let a = Angle::from_turn_ratio(deg_tenths, 3600);
        for radius in [Fx::from_ratio(1, 100), Fx::ONE, Fx::from_int(1000)] {
            let (x, y) = (Fx::cos(a) * radius, Fx::sin(a) * radius);
            let got = Fx::atan2(y, x);
            let exact = <f64 as Real>::atan2(y.to_f64(), x.to_f64());
            worst = worst.max((got - exact).signed().unsigned_abs());
        }
    }
    assert!(
        worst <= 1 << 14,
        "atan2 error {worst} units (2^-18 turn = 16384)"
    );
}

#[test]
fn division_and_reciprocal_are_exactly_rounded() {
    for (n, d) in [(1, 3), (-7, 9), (1000, -700_000), (5, 65_536 * 3)] {
        let (a, b) = (Fx::from_bits(n << 8), Fx::from_bits(d));
        let exact = a.to_f64() / b.to_f64();
        assert!(libm::fabs((a / b).to_f64() - exact) <= 0.5 * LSB, "{a}/{b}");
    }
    let (err, at) = worst(sweep(1 << 8, i32::MAX, 10_007), Fx::recip, |x| 1.0 / x);
    assert!(err <= 0.5 + 1e-9, "recip error {err} LSB at {at}");
}
