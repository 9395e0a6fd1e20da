//! The day of a clonal mosaic (thesis Sec. 3.2; docs/mosaics.md), the
//! same on the plane and on a mesh ([`Mosaic`] on any [`Terrain`]): day 0 spreads the initial cells and
//! relaxes them ρ_i times without adhesion; each following day divides the
//! cells whose division day has come, works out the repulsion radius again
//! and relaxes ρ_s times with adhesion. A day that [`Params::frames`]
//! selects is streamed as a frame.

use super::params::Params;
use super::store::Relax;
use super::{CELL_LIMIT, VELOCITY_LIMIT};
use super::{Mosaic, Terrain};
use crate::Error;
use crate::fx::Fx;
use crate::sim::{Deferred, Progress};
use crate::stream::{Record, Sink};

/// Where a mosaic's run is: its parameters and seed, and its counters.
#[derive(Debug)]
pub(crate) struct Run<'a> {
    /// The parameters (none before a start, or after a refused one).
    params: Option<&'a Params<'a>>,
    /// The seed.
    pub(crate) seed: u64,
    /// The live cells.
    pub(crate) cells: u32,
    /// The day last simulated (0 after the initial relaxation).
    pub(crate) day: u16,
    /// Steps done: 0 before day 0, then days done + 1.
    done: u32,
    /// Frames streamed.
    pub(crate) frame: u32,
    /// The repulsion radius r (Q16 bits).
    pub(crate) radius: i32,
    /// A refused start, reported by the next step.
    pending: Deferred,
}

impl<'a> Run<'a> {
    /// Not started (all zero bytes: an idle mosaic is written with a
    /// memset, [`crate::sim::Deferred`]).
    pub(crate) const fn new() -> Run<'a> {
        Run {
            params: None,
            seed: 0,
            cells: 0,
            day: 0,
            done: 0,
            frame: 0,
            radius: 0,
            pending: Deferred::new(),
        }
    }

    /// The parameters of the run.
    pub(crate) fn params(&self) -> Result<&'a Params<'a>, Error> {
        self.params.ok_or(Error::NotStarted)
    }

    /// Ready for day 0 of `params` with `seed`.
    pub(crate) fn begin(&mut self, params: &'a Params<'a>, seed: u64) {
        *self = Run {
            params: Some(params),
            seed,
            ..Run::new()
        };
    }
}

/// Whether a cell store of `capacity` cells, `velocities` of them with a
/// velocity, holds the start of a run of `params`: its initial cells,
/// and a velocity for each cell if the run has momentum.
///
/// # Errors
/// [`Error::Capacity`] naming [`CELL_LIMIT`] or [`VELOCITY_LIMIT`].
pub(crate) fn check_store(
    params: &Params,
    capacity: usize,
    velocities: usize,
) -> Result<(), Error> {
    if params.initial_cells as usize > capacity {
        return Err(Error::Capacity {
            limit: CELL_LIMIT,
            capacity: capacity as u32,
        });
    }
    if params.momentum != Fx::ZERO && velocities < capacity {
        return Err(Error::Capacity {
            limit: VELOCITY_LIMIT,
            capacity: velocities as u32,
        });
    }
    Ok(())
}

/// The day itself, the same on every terrain.
impl<'a, S: Relax<T::Ground>, T: Terrain> Mosaic<'a, S, T> {
    /// (Re)starts a run of `params` with `seed`, in place; a refusal is
    /// also kept for the next [`Mosaic::step_day`].
    ///
    /// # Errors
    /// An invalid run (`Mosaic::prepare`).
    pub(crate) fn start_run(&mut self, params: &'a Params<'a>, seed: u64) -> Result<(), Error> {
        self.run.params = None;
        let result = self.prepare(params);
        if result.is_ok() {
            self.run.begin(params, seed);
        }
        self.run.pending.keep(result)
    }

    /// Step 0 places and relaxes the initial cells; step d ≥ 1 simulates
    /// day d. A step streams its day if [`Params::frames`] selects it.
    ///
    /// # Errors
    /// A refused start, a full store or the sink's error.
    pub(crate) fn step_day(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        let run = &mut self.run;
        run.pending.check()?;
        let params = run.params()?;
        let total = u32::from(params.days) + 1;
        if run.done >= total {
            return Ok(Progress { done: total, total });
        }
        // Day 0 relaxes ρ_i times ignoring adhesion, later days ρ_s times.
        let (times, adhesion) = if run.done == 0 {
            self.place(params)?;
            (params.initial_relaxations, false)
        } else {
            self.run.day += 1;
            self.divide(params)?;
            (params.daily_relaxations, true)
        };
        self.update_radius(params);
        self.relax(params, times, adhesion);
        let run = &mut self.run;
        if params.frames.includes(run.day) {
            sink.record(&Record::FrameStart {
                frame: run.frame,
                time: Fx::from_int(i32::from(run.day)),
            })?;
            self.records(sink)?;
            let run = &mut self.run;
            sink.record(&Record::FrameEnd { frame: run.frame })?;
            run.frame += 1;
        }
        let run = &mut self.run;
        run.done += 1;
        Ok(Progress {
            done: run.done,
            total,
        })
    }
}
