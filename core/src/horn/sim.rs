//! The horn as a [`Simulation`]: one frame per step, each the compound
//! solid Z(t) of the horn paper, Sec. 7, at its global time t.
//!
//! Frame m (from 0) shows global time t = (m + 1)·T / `frames_per_year`;
//! its `FrameStart` carries t in years. Then, module by module from the tip,
//! each ring as a `Ring` record and its `Point`s, then `FrameEnd`.

use super::{Emit, HornKernel, HornParams, Moment};
use crate::Error;
use crate::fx::Fx;
use crate::sim::{Deferred, Progress, Simulation, Start};
use crate::stream::{Record, Sink};

/// A running horn: the fixed-point kernel and the frame counter. A few
/// hundred bytes plus the outline (see [`super::MAX_RING_POINTS`]).
#[derive(Clone, Debug)]
pub struct Horn<'a> {
    /// The kernel, once started with valid parameters (its `None` is the
    /// null of the parameters' reference: an idle horn is all zero bytes,
    /// written into a runner slot by a memset).
    kernel: Option<HornKernel<'a, Fx>>,
    /// Why the parameters were refused (reported by every `step`).
    refused: Deferred,
    frame: u32,
}

impl<'a> Start<'a> for Horn<'a> {
    type Params = HornParams<'a>;

    /// A horn grows deterministically: `seed` is not used.
    fn start(&mut self, params: &'a HornParams<'a>, _seed: u64) -> Result<(), Error> {
        self.frame = 0;
        self.kernel = None;
        let result = HornKernel::new(params).map(|kernel| self.kernel = Some(kernel));
        self.refused.keep(result)
    }
}

impl Horn<'_> {
    /// Nothing to draw until started (`const`, for a `static`).
    pub const IDLE: Horn<'static> = Horn {
        kernel: None,
        refused: Deferred::new(),
        frame: 0,
    };

    /// Why the parameters were refused, if they were.
    ///
    /// # Errors
    /// The first [`Simulation::step`]'s error for invalid parameters.
    pub fn check(&self) -> Result<(), Error> {
        self.refused.check()
    }
}

impl Simulation for Horn<'_> {
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.refused.check()?;
        let kernel = self.kernel.as_mut().ok_or(Error::NotStarted)?;
        let params = kernel.params();
        let total = params.frames();
        if self.frame >= total {
            return Ok(Progress { done: total, total });
        }
        let per_year = u32::from(params.frames_per_year);
        let at = Moment::new(self.frame + 1, per_year);
        kernel.place(at)?;
        // Years = frame / frames_per_year; both ≤ u16::MAX, so the ratio is
        // a small Fx.
        let years = Fx::from_ratio((self.frame + 1) as i32, per_year as i32);
        sink.record(&Record::FrameStart {
            frame: self.frame,
            time: years,
        })?;
        kernel.emit(&mut |e| {
            let record = match e {
                Emit::Ring {
                    module,
                    ring,
                    points,
                } => Record::Ring {
                    module,
                    ring,
                    points,
                },
                Emit::Point(p) => Record::Point { p: [p.x, p.y, p.z] },
            };
            sink.record(&record).map_err(Error::from)
        })?;
        sink.record(&Record::FrameEnd { frame: self.frame })?;
        self.frame += 1;
        Ok(Progress {
            done: self.frame,
            total,
        })
    }
}
