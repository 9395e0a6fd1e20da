//! Bones (bones paper, Secs. 2–6): an L-system skeleton of points and
//! segments, wrapped by [`crate::shrinkwrap`] in a closed triangle mesh on
//! the iso-surface V(r) = V0 of V(r) = Σ ρ_i / |r − R_i|, with the paper's
//! normalised ρ_i over the skeleton's vertices (eqs. (1)–(2)) or each
//! element's own constant ρ ([`crate::shrinkwrap::Weights`]).
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

use crate::fx::Fx;
use crate::rng::KeyedRng;
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

/// The RNG streams of a frame's wrap draws ([`BonesParams::frame_wrap`]):
/// the top byte 0, which no derivation step's stream has
/// ([`crate::lsys::stream_id`] puts steps from 1 there), so the draws do
/// not depend on how many numbers the skeleton's derivation drew.
const WRAP_STREAM: u64 = 0x0000_7772_6170_0000; // "wrap"
/// The draw of V0 within [`WRAP_STREAM`].
const TARGET_DRAW: u64 = 0;
/// The draw of ΔV within [`WRAP_STREAM`].
const STEP_DRAW: u64 = 1;

impl BonesParams<'_> {
    /// The seed frame `frame` of a run from `seed` derives its skeleton
    /// with: s + frame for [`Frames::Seeds`] (Fig. 3), else s.
    #[must_use]
    pub const fn frame_seed(&self, seed: u64, frame: u32) -> u64 {
        match self.frames {
            Frames::Seeds(_) => seed.wrapping_add(frame as u64),
            Frames::Final | Frames::EveryStep { .. } => seed,
        }
    }

    /// The wrap of the frame whose skeleton grew `steps` derivation steps
    /// from `seed`: V0 and ΔV each drawn uniformly in its range
    /// ([`WrapParams::target_max`], [`WrapParams::step_max`]; bones paper,
    /// Summary and Fig. 3) at 16.16 resolution, each from its own stream of
    /// `seed` keyed by `steps`, so the same skeleton always gets the same
    /// wrap. Without ranges, [`BonesParams::wrap`] as it is.
    ///
    /// ```
    /// use morphogen::bones::{BonesParams, Frames};
    /// use morphogen::fx::Fx;
    /// use morphogen::shrinkwrap::{SPLIT_TOLERANCE, Weights, WrapParams};
    /// let wrap = WrapParams {
    ///     meridians: 8,
    ///     parallels: 5,
    ///     target: Fx::from_int(3),
    ///     step: Fx::from_ratio(1, 4),
    ///     max_iterations: 40,
    ///     split_tolerance: SPLIT_TOLERANCE,
    ///     weights: Weights::Constant,
    ///     target_max: Some(Fx::from_int(4)),
    ///     step_max: None,
    /// };
    /// let bone = BonesParams { grammar: "n = 0\naxiom: O(1)\n", wrap, frames: Frames::Seeds(2) };
    /// let drawn = bone.frame_wrap(7, 0);
    /// assert!(Fx::from_int(3) <= drawn.target && drawn.target <= Fx::from_int(4));
    /// assert_eq!((drawn.step, drawn.target_max), (wrap.step, None));
    /// assert_eq!(bone.frame_wrap(7, 0), drawn);
    /// ```
    #[must_use]
    pub fn frame_wrap(&self, seed: u64, steps: u8) -> WrapParams {
        let draw = |lo: Fx, hi: Option<Fx>, which: u64| match hi {
            None => lo,
            Some(hi) => {
                let stream = WRAP_STREAM | (u64::from(steps) << 8) | which;
                Fx::from_bits(KeyedRng::new(seed, stream).between(lo.to_bits(), hi.to_bits()))
            }
        };
        WrapParams {
            target: draw(self.wrap.target, self.wrap.target_max, TARGET_DRAW),
            step: draw(self.wrap.step, self.wrap.step_max, STEP_DRAW),
            target_max: None,
            step_max: None,
            ..self.wrap
        }
    }
}
