//! The `growth-curve` preset: the horn paper's seasonal sigmoid f(t) over
//! one year, sampled daily (Sec. 2 and Fig. 7c).
//!
//! One frame; per day `d = 0..=365` two samples: series 0 is `f(d)`,
//! series 1 the day's increment `f(d + 1) − f(d)` (0 after the last day).

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::fx::Fx;
use crate::growth::Sigmoid;
use crate::sim::{Progress, Simulation, Start};
use crate::stream::{Record, Sink};

/// Series index of the cumulative growth f(t).
pub const SERIES_GROWTH: u16 = 0;
/// Series index of the daily increment.
pub const SERIES_DAILY: u16 = 1;

/// Parameters of the growth-curve run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Params {
    /// The growth function.
    pub growth: Sigmoid,
    /// Number of days sampled after day 0.
    pub days: u16,
}

/// The daily sampler.
#[derive(Clone, Debug)]
pub struct GrowthCurve {
    params: Params,
    day: u32,
}

impl GrowthCurve {
    /// A run over `params`, ready at day 0 (through [`Start`]).
    const fn new(params: Params) -> GrowthCurve {
        GrowthCurve { params, day: 0 }
    }

    /// Nothing to sample until started (`const`, for a `static`).
    pub const IDLE: GrowthCurve = GrowthCurve::new(Params {
        growth: Sigmoid {
            centre: Fx::ZERO,
            width: Fx::ONE,
            span: Fx::ONE,
        },
        days: 0,
    });

    fn total(&self) -> u32 {
        self.params.days as u32 + 1
    }
}

impl Start<'_> for GrowthCurve {
    type Params = Params;

    /// The curve has no randomness: `seed` is not used.
    fn start(&mut self, params: &Params, _seed: u64) -> Result<(), Error> {
        *self = GrowthCurve::new(*params);
        Ok(())
    }
}

impl Simulation for GrowthCurve {
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        let total = self.total();
        if self.day >= total {
            return Ok(Progress { done: total, total });
        }
        if self.day == 0 {
            sink.record(&Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            })?;
        }
        let f = |d: u32| self.params.growth.fraction(Fx::from_int(d as i32));
        let today = f(self.day);
        let increment = if self.day + 1 < total {
            f(self.day + 1) - today
        } else {
            Fx::ZERO
        };
        let x = Fx::from_int(self.day as i32);
        sink.record(&Record::Sample {
            series: SERIES_GROWTH,
            x,
            y: today,
        })?;
        sink.record(&Record::Sample {
            series: SERIES_DAILY,
            x,
            y: increment,
        })?;
        self.day += 1;
        if self.day == total {
            sink.record(&Record::FrameEnd { frame: 0 })?;
        }
        Ok(Progress {
            done: self.day,
            total,
        })
    }
}
