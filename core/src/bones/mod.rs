//! Bones (seed `003_…`, Slovak): an L-system skeleton of points and
//! segments, wrapped by [`crate::shrinkwrap`] in a closed triangle mesh on
//! the iso-surface V(r) = V0 of V(r) = Σ ρ_i / |r − R_i|.
//!
//! - [`Grower`] derives a bone grammar and draws its skeleton: `F` is a
//!   segment of weight = the turtle's width, `O(ρ)` a point of weight ρ,
//!   `{ … }` a convex polygon (Sec. 6); streaming, or buffered for a
//!   context-sensitive grammar (Sec. 3) on a host.
//! - [`Bones`] is the simulation: one wrapped frame per skeleton, for the
//!   final step, every step (the paper's Fig. 2) or several seeds (Fig. 3).
//! - The built-in bones are the scenarios `long-bone`, `long-bone-random`,
//!   `bone-growth`, `bone-plate` (a polygon) and `bone-ossification` (a
//!   context-sensitive grammar, host only) (`scenarios/`).

mod sim;
mod skeleton;

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests;

use serde::{Deserialize, Serialize};

use crate::shrinkwrap::WrapParams;

pub use sim::Bones;

/// Mesh vertices of a bone run on the MCU (the [`Runner`](crate::preset::Runner)'s
/// capacity): sized to the firmware's RAM.
pub const MCU_VERTICES: usize = 1200;
/// Mesh triangles: 2·V − 4, a closed genus-0 mesh's count.
pub const MCU_TRIANGLES: usize = 2 * MCU_VERTICES - 4;
/// Vertices at which a host's bone run keeps the field between moves
/// (`Bones<MCU_VERTICES, MCU_TRIANGLES, HOST_FIELD_CACHE>`): all of them,
/// 16 B each, which an MCU's RAM cannot spare. The same results, a
/// third fewer field evaluations.
pub const HOST_FIELD_CACHE: usize = MCU_VERTICES;
pub use skeleton::{Grower, MAX_ELEMENTS, MAX_SKELETON_MODULES, MAX_SKELETON_VISITS, Skeleton};

/// Which skeletons a run wraps, one frame each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Frames {
    /// The skeleton after the grammar's `n` steps.
    Final,
    /// The skeleton after every step from `first` to `n` (Fig. 2).
    EveryStep {
        /// The first step shown.
        first: u8,
    },
    /// The skeleton after `n` steps from seeds s, s + 1, … (Fig. 3).
    Seeds(u8),
}

/// A bone run whose frames do not fit its grammar.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum BonesError {
    /// [`Frames::EveryStep`] starts after the grammar's last step `n`.
    FirstStepPastEnd {
        /// The first step asked for.
        first: u8,
        /// The grammar's `n`.
        steps: u8,
    },
}

impl core::fmt::Display for BonesError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BonesError::FirstStepPastEnd { first, steps } => write!(
                f,
                "frames from step {first}, past the grammar's last step n = {steps}"
            ),
        }
    }
}

impl core::error::Error for BonesError {}

impl From<BonesError> for crate::Error {
    fn from(e: BonesError) -> crate::Error {
        crate::Error::Bones(e)
    }
}

/// A bone run's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct BonesParams<'a> {
    /// The skeleton's grammar (`docs/lsystems.md`, with `O(ρ)`).
    pub grammar: &'a str,
    /// The shrinkwrap parameters.
    pub wrap: WrapParams,
    /// Which skeletons are wrapped.
    pub frames: Frames,
}
