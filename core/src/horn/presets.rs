//! The ram horn of the horn paper (Sec. 6, Table 1) and its two runs.

use super::{HornParams, Module, ROUNDED_TRIANGLE};
use crate::fx::{Angle, Fx};
use crate::growth::{Sigmoid, YEAR_DAYS};

/// The path radius of every module, 20 cm (horn paper, Sec. 6).
pub const PATH_RADIUS_CM: Fx = Fx::from_int(20);

/// One row of Table 1: scales in %, angles in degrees.
const fn row(positioner: i32, base: i32, bend: i32, twist: i32) -> Module {
    Module {
        positioner_scale: Fx::from_ratio(positioner, 100),
        base_scale: Fx::from_ratio(base, 100),
        bend: Angle::from_degrees(bend),
        twist: Angle::from_degrees(twist),
        path_radius: PATH_RADIUS_CM,
    }
}

/// Table 1 of the horn paper: modules E_1 (the tip) … E_8 of the ram horn.
pub static TABLE_1: [Module; 8] = [
    row(30, 100, 75, 30),
    row(100, 137, 83, 33),
    row(137, 150, 59, 24),
    row(150, 155, 35, 14),
    row(155, 156, 22, 9),
    row(156, 153, 17, 8),
    row(153, 150, 14, 6),
    row(150, 148, 12, 3),
];

/// `ram-horn`: the 8 modules of Table 1, T = one year of seasonal growth,
/// a frame at every mid-year and year end (16 frames). J = 24 cross-sections
/// per module (two a month: the dense winter ones form the annual rings),
/// 24 points each (8 per side of the rounded triangle). About 0.8 MB.
pub static RAM_HORN: HornParams = HornParams {
    modules: &TABLE_1,
    outline: &ROUNDED_TRIANGLE,
    ring_points: 24,
    rings_per_module: 24,
    delay_days: YEAR_DAYS as u16,
    growth: Sigmoid::SEASONAL_YEAR,
    frames_per_year: 2,
    years: 8,
};

/// `ram-horn-animation`: the same horn at the end of every month for
/// 8 years (96 frames), one cross-section a month (J = 12: the paper's
/// monthly stripes, Fig. 7d) of 16 points, to keep the stream under 2 MB.
pub static RAM_HORN_ANIMATION: HornParams = HornParams {
    modules: &TABLE_1,
    outline: &ROUNDED_TRIANGLE,
    ring_points: 16,
    rings_per_module: 12,
    delay_days: YEAR_DAYS as u16,
    growth: Sigmoid::SEASONAL_YEAR,
    frames_per_year: 12,
    years: 8,
};
