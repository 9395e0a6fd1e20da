//! The parameters of a horn and of its modules (horn paper, Sec. 6 and
//! Table 1).

use serde::{Deserialize, Serialize};

use super::{HornError, MAX_MODULES, MAX_RING_POINTS};
use crate::Error;
use crate::fx::{Angle, Fx};
use crate::growth::Sigmoid;

/// One module E_i: its positioner and the cross-sections it sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Module {
    /// Scale of the upper base L_i(0) (the positioner's shape) relative to
    /// L_1(T), as a ratio (Table 1's % / 100).
    pub positioner_scale: Fx,
    /// Scale of the lower base L_i(T) relative to L_1(T), as a ratio.
    pub base_scale: Fx,
    /// Bend angle α(T): the arc the path turns through by τ = T (R_z).
    pub bend: Angle,
    /// Twist angle β(T): the positioner's roll about the path by τ = T (R_x).
    pub twist: Angle,
    /// Radius of the path's arc, cm (20 cm in the paper, Sec. 6).
    pub path_radius: Fx,
}

/// Everything that defines a horn run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HornParams<'a> {
    /// Modules E_1 … E_k, oldest (the tip) first.
    pub modules: &'a [Module],
    /// The cross-section at scale 1 (= L_1(T)): a closed polyline (the last
    /// vertex joins the first) of (y, z) in cm, counter-clockwise seen from
    /// +x; resampled to `ring_points` points of equal spacing.
    pub outline: &'a [[Fx; 2]],
    /// Points per cross-section (per ring).
    pub ring_points: u16,
    /// J: cross-sections per module, at θ_j = j·T/J, j = 0 … J.
    pub rings_per_module: u16,
    /// The delay T between modules, days.
    pub delay_days: u16,
    /// The growth f(τ) over a module's life (span = T).
    pub growth: Sigmoid,
    /// Frames per year: frame m (from 1) shows t = m·T / `frames_per_year`.
    pub frames_per_year: u16,
    /// Years shown; at most k.
    pub years: u16,
}

impl HornParams<'_> {
    /// Number of frames of the run.
    #[must_use]
    pub const fn frames(&self) -> u32 {
        self.frames_per_year as u32 * self.years as u32
    }

    /// Checks every limit and the paper's continuity condition.
    ///
    /// # Errors
    /// [`Error::Capacity`] naming `MAX_MODULES` or `MAX_RING_POINTS`, or
    /// [`Error::Horn`] naming the inconsistent parameter.
    pub fn validate(&self) -> Result<(), Error> {
        if self.modules.is_empty() {
            return Err(HornError::NoModules.into());
        }
        if self.modules.len() > MAX_MODULES {
            return Err(Error::Capacity {
                limit: "horn::MAX_MODULES",
                capacity: MAX_MODULES as u32,
            });
        }
        if self.ring_points as usize > MAX_RING_POINTS {
            return Err(Error::Capacity {
                limit: "horn::MAX_RING_POINTS",
                capacity: MAX_RING_POINTS as u32,
            });
        }
        if self.ring_points == 0
            || self.rings_per_module == 0
            || self.frames_per_year == 0
            || self.delay_days == 0
        {
            return Err(HornError::ZeroCount.into());
        }
        // T must be a whole number of days inside Fx's range.
        if self.delay_days > i16::MAX as u16
            || self.growth.span != Fx::from_int(self.delay_days as i32)
        {
            return Err(HornError::SpanMismatch.into());
        }
        if self.years as usize > self.modules.len() {
            return Err(HornError::PastLastModule.into());
        }
        for (i, pair) in self.modules.windows(2).enumerate() {
            if pair[1].positioner_scale != pair[0].base_scale {
                return Err(HornError::ScaleMismatch {
                    module: (i + 2) as u16,
                }
                .into());
            }
        }
        Ok(())
    }
}
