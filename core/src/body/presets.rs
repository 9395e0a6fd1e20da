//! The body presets: the built-in quadrupeds grown through their tables
//! (growth paper, Sec. 8, Figs. 5, 6 and 8).

use super::gait::TROT;
use super::quadruped::{COW, HORSE};
use super::sim::BodyParams;
use super::table::{HOLSTEIN, QUARTER_HORSE};
use crate::fx::Fx;

/// `horse-growth`: the quarter horse from birth to 60 months, every 6
/// months (11 frames; every table age is a frame).
pub static HORSE_GROWTH: BodyParams<'static> = BodyParams {
    model: &HORSE,
    table: &QUARTER_HORSE,
    frames: 11,
    first_age: Fx::from_int(0),
    last_age: Fx::from_int(60),
    gait: None,
    frames_per_stride: 1,
};

/// `cow-growth`: the Holstein from birth to 36 months, every 3 months
/// (13 frames; every table age is a frame).
pub static COW_GROWTH: BodyParams<'static> = BodyParams {
    model: &COW,
    table: &HOLSTEIN,
    frames: 13,
    first_age: Fx::from_int(0),
    last_age: Fx::from_int(36),
    gait: None,
    frames_per_stride: 1,
};

/// `horse-trot`: the horse trotting while it grows from 6 to 60 months —
/// 3 strides of 12 frames (36 frames, 1.54 months apart).
pub static HORSE_TROT: BodyParams<'static> = BodyParams {
    model: &HORSE,
    table: &QUARTER_HORSE,
    frames: 36,
    first_age: Fx::from_int(6),
    last_age: Fx::from_int(60),
    gait: Some(&TROT),
    frames_per_stride: 12,
};

/// The body preset called `name` (as in `morphogen list`).
#[must_use]
pub fn find(name: &str) -> Option<&'static BodyParams<'static>> {
    match name {
        "horse-growth" => Some(&HORSE_GROWTH),
        "cow-growth" => Some(&COW_GROWTH),
        "horse-trot" => Some(&HORSE_TROT),
        _ => None,
    }
}
