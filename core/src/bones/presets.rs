//! The built-in bones (seed `003_…`). Their grammars are the files in
//! `grammars/`, compiled in. V falls off as 1/r, so the whole skeleton
//! lifts the level along the shaft: V0 = 3.4 gives the final bone a shaft
//! of radius 0.34 in the middle and ends of radius 0.9 (length 8.6).

use crate::fx::Fx;
use crate::shrinkwrap::WrapParams;

use super::{BonesParams, Frames};

/// A long bone's skeleton rules (deterministic).
pub const LONG_BONE_GRAMMAR: &str = include_str!("../../../grammars/long-bone.lsys");
/// The same rules with chance in them.
pub const LONG_BONE_RANDOM_GRAMMAR: &str = include_str!("../../../grammars/long-bone-random.lsys");

/// Mesh vertices of the presets: sized to the firmware's RAM.
pub const MCU_VERTICES: usize = 1200;
/// Mesh triangles: 2·V − 4, a closed genus-0 mesh's count.
pub const MCU_TRIANGLES: usize = 2 * MCU_VERTICES - 4;

/// The shrinkwrap of every preset: a sphere of 16 × 7 + 2 vertices,
/// V0 = 3.4 reached in steps of 0.15.
pub const WRAP: WrapParams = WrapParams {
    meridians: 24,
    parallels: 11,
    target: Fx::from_ratio(17, 5),
    step: Fx::from_ratio(3, 20),
    max_iterations: 64,
};

/// `long-bone`: the bone after 12 steps.
pub static LONG_BONE: BonesParams = BonesParams {
    grammar: LONG_BONE_GRAMMAR,
    wrap: WRAP,
    frames: Frames::Final,
};

/// `long-bone-random`: three stochastic bones (Fig. 3).
pub static LONG_BONE_RANDOM: BonesParams = BonesParams {
    grammar: LONG_BONE_RANDOM_GRAMMAR,
    wrap: WRAP,
    frames: Frames::Seeds(3),
};

/// `bone-growth`: the bone after each of its 12 steps (Fig. 2).
pub static BONE_GROWTH: BonesParams = BonesParams {
    grammar: LONG_BONE_GRAMMAR,
    wrap: WRAP,
    frames: Frames::EveryStep { first: 1 },
};

/// Every bone preset with its name.
pub static ALL: [(&str, &BonesParams); 3] = [
    ("long-bone", &LONG_BONE),
    ("long-bone-random", &LONG_BONE_RANDOM),
    ("bone-growth", &BONE_GROWTH),
];

/// The bone preset called `name`.
#[must_use]
pub fn find(name: &str) -> Option<&'static BonesParams> {
    ALL.iter().find(|(n, _)| *n == name).map(|(_, p)| *p)
}
