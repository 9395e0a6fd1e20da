//! The ram horn of the horn paper (Stępień & Prolejko, Table 1 and Sec. 6),
//! its parameters written in Rust with the core alone: the same bits as the
//! built-in scenario `scenarios/ram-horn.toml`, so the same stream.
//! `tests/tests/embedding.rs` proves it (parameter digest and stream digest
//! against `fixtures/ram-horn/summary.toml`, and field by field against the
//! scenario reader's parameters); the firmware examples `horn_direct`,
//! `horn_runner` and `horn_draw` include this file.

use morphogen::fx::{Angle, Fx};
use morphogen::growth::Sigmoid;
use morphogen::horn::{HornParams, Module, Percent};

/// The delay T between modules: a new module every year (days).
const T: u16 = 365;

/// A module of Table 1: scales in percent of L_1(T), angles in whole
/// degrees, a path of radius 20 cm (Sec. 6).
const fn row(positioner: u16, base: u16, bend: i32, twist: i32) -> Module {
    Module::new(
        Percent(positioner),
        Percent(base),
        Angle::from_degrees(bend),
        Angle::from_degrees(twist),
        Fx::from_int(20),
    )
}

/// Table 1 of the horn paper, the tip (E_1) first.
pub static MODULES: [Module; 8] = [
    row(30, 100, 75, 30),
    row(100, 137, 83, 33),
    row(137, 150, 59, 24),
    row(150, 155, 35, 14),
    row(155, 156, 22, 9),
    row(156, 153, 17, 8),
    row(153, 150, 14, 6),
    row(150, 148, 12, 3),
];

/// A length in cm given in ten-thousandths (`cm(12_990)` is 1.299 cm):
/// the decimal's digits over its power of ten, rounded as the scenario
/// reader rounds `1.299`.
const fn cm(ten_thousandths: i32) -> Fx {
    Fx::from_ratio(ten_thousandths, 10_000)
}

/// L_1(T): the rounded triangle (corners arcs of radius 1.5 cm around an
/// equilateral triangle of circumradius 2 cm, a corner up), (y, z) in cm,
/// counter-clockwise seen from +x (Sec. 6, Fig. 7b).
pub static OUTLINE: [[Fx; 2]; 21] = [
    [cm(12_990), cm(27_500)],
    [cm(9_642), cm(31_491)],
    [cm(5_130), cm(34_095)],
    [cm(0), cm(35_000)],
    [cm(-5_130), cm(34_095)],
    [cm(-9_642), cm(31_491)],
    [cm(-12_990), cm(27_500)],
    [cm(-30_311), cm(-2_500)],
    [cm(-32_093), cm(-7_395)],
    [cm(-32_093), cm(-12_605)],
    [cm(-30_311), cm(-17_500)],
    [cm(-26_962), cm(-21_491)],
    [cm(-22_451), cm(-24_095)],
    [cm(-17_321), cm(-25_000)],
    [cm(17_321), cm(-25_000)],
    [cm(22_451), cm(-24_095)],
    [cm(26_962), cm(-21_491)],
    [cm(30_311), cm(-17_500)],
    [cm(32_093), cm(-12_605)],
    [cm(32_093), cm(-7_395)],
    [cm(30_311), cm(-2_500)],
];

/// The ram horn, every half year for 8 years; growth fastest on day 151.5,
/// 22 days wide, over each module's life of T (Sec. 2).
pub static PARAMS: HornParams<'static> = HornParams {
    modules: &MODULES,
    outline: &OUTLINE,
    ring_points: 24,
    rings_per_module: 24,
    delay_days: T,
    growth: Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), T),
    frames_per_year: 2,
    years: 8,
};

/// The stream header's name.
pub const NAME: &str = "ram-horn";

/// The parameter digest of [`PARAMS`] (`Model::Horn(&PARAMS).params_digest()`),
/// written here so that a device needs no serializer for it: the
/// `params_digest` of `fixtures/ram-horn/summary.toml`.
pub const PARAMS_DIGEST: u64 = 0xa49a_3cbf_111e_3af3;

/// The digest of the whole stream with seed 0: the fixture's
/// `stream_digest`.
pub const STREAM_DIGEST: u64 = 0xae87_fcd6_dc16_bc07;
