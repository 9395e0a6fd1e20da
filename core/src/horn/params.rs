//! The parameters of a horn and of its modules (horn paper, Sec. 6 and
//! Table 1), written in Rust with the same bits a scenario file gives.

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

/// A scale as Table 1 of the horn paper and the scenario files write it:
/// a whole percentage of L_1(T) (`Percent(137)` is 1.37·L_1(T)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Percent(pub u16);

impl Percent {
    /// The ratio a [`Module`] holds: `p / 100` rounded to nearest, the
    /// value a scenario file's reader gives the percentage `p`.
    ///
    /// ```
    /// use morphogen::fx::Fx;
    /// use morphogen::horn::Percent;
    /// assert_eq!(Percent(150).ratio(), Fx::from_ratio(3, 2));
    /// assert_eq!(Percent(137).ratio().to_bits(), 89_784); // 1.37 · 2¹⁶ = 89,784.32
    /// ```
    #[must_use]
    pub const fn ratio(self) -> Fx {
        Fx::from_ratio(self.0 as i32, 100)
    }
}

impl Module {
    /// A row of Table 1 as the paper and the scenario files write it:
    /// scales in percent of L_1(T) (held as ratios), the bend α(T) and the
    /// twist β(T) as angles (whole degrees: [`Angle::from_degrees`]), the
    /// path's radius in cm (`const`, for a `static` table).
    #[must_use]
    pub const fn new(
        positioner_scale: Percent,
        base_scale: Percent,
        bend: Angle,
        twist: Angle,
        path_radius: Fx,
    ) -> Module {
        Module {
            positioner_scale: positioner_scale.ratio(),
            base_scale: base_scale.ratio(),
            bend,
            twist,
            path_radius,
        }
    }
}

/// Everything that defines a horn run.
///
/// Three things a scenario file's reader does that hand-written parameters
/// must do too, or their stream header's parameter digest (and, for the
/// first two, the horn) differs from the scenario's:
/// - a module grows over its life T: the growth sigmoid's `span` is
///   `delay_days` ([`Sigmoid::over_life`]; any other span is refused with
///   [`HornError::SpanMismatch`], naming T);
/// - Table 1 and the scenario files give scales in percent of L_1(T), the
///   parameters hold ratios: [`Module::new`] takes [`Percent`]s;
/// - decimals become 16.16 rounded to nearest: [`Fx::from_ratio`] of the
///   decimal's digits (`1.299` is `Fx::from_ratio(1299, 1000)`) is the
///   value the reader gives (see there).
///
/// A horn of two modules (Table 1's first two rows) with a square
/// cross-section, written by hand:
///
/// ```
/// use morphogen::fx::{Angle, Fx};
/// use morphogen::growth::Sigmoid;
/// use morphogen::horn::{Horn, HornError, HornParams, Module, Percent};
/// use morphogen::sim::{Simulation, Start};
/// use morphogen::stream::Encoder;
/// use morphogen::Error;
///
/// static MODULES: [Module; 2] = [
///     Module::new(Percent(30), Percent(100), Angle::from_degrees(75), Angle::from_degrees(30), Fx::from_int(20)),
///     Module::new(Percent(100), Percent(137), Angle::from_degrees(83), Angle::from_degrees(33), Fx::from_int(20)),
/// ];
/// // L_1(T): a square of side 5 cm, (y, z) counter-clockwise seen from +x.
/// const P: Fx = Fx::from_ratio(5, 2);
/// const M: Fx = Fx::from_ratio(-5, 2);
/// static SQUARE: [[Fx; 2]; 4] = [[P, P], [M, P], [M, M], [P, M]];
/// static PARAMS: HornParams<'static> = HornParams {
///     modules: &MODULES,
///     outline: &SQUARE,
///     ring_points: 8,
///     rings_per_module: 4,
///     delay_days: 365,
///     growth: Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), 365),
///     frames_per_year: 1,
///     years: 2,
/// };
/// assert_eq!(PARAMS.validate(), Ok(()));
/// assert_eq!(MODULES[1].base_scale, Fx::from_ratio(137, 100));
///
/// let mut horn = Horn::IDLE;
/// horn.start(&PARAMS, 0).unwrap();
/// // Any `embedded_io::Write`: a UART on a device, a `Vec<u8>` here.
/// let mut encoder = Encoder::new(Vec::new());
/// while !horn.step(&mut encoder).unwrap().finished() {}
/// // Two frames (start and end records each): at t = T the first module's
/// // J + 1 = 5 rings (a ring record and its 8 points each), at 2T both modules'.
/// assert_eq!(encoder.frames(), 2 * 2 + (1 + 2) * 5 * (1 + 8));
///
/// // A sigmoid over another span is refused, naming T.
/// let wrong = HornParams { growth: Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), 360), ..PARAMS };
/// assert_eq!(wrong.validate(), Err(Error::Horn(HornError::SpanMismatch { delay_days: 365 })));
/// ```
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
    /// The growth f(τ) over a module's life: its span must be T
    /// ([`Sigmoid::over_life`] of `delay_days`).
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
            return Err(HornError::SpanMismatch {
                delay_days: self.delay_days,
            }
            .into());
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
