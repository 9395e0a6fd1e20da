//! The face every simulation shows to host, firmware and tests: a stepper
//! that pushes records into a [`Sink`] and reports its progress.

use crate::Error;
use crate::stream::Sink;

/// How far a run is: `done` of `total` steps (a step is usually a frame or
/// a sample); the run is over when `done == total`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Progress {
    /// Steps done.
    pub done: u32,
    /// Steps in the whole run.
    pub total: u32,
}

impl Progress {
    /// Whether the run is over.
    #[must_use]
    pub const fn finished(&self) -> bool {
        self.done >= self.total
    }
}

/// A simulation: bounded state, advanced one step at a time.
pub trait Simulation {
    /// Runs one step, pushing its records into `sink`.
    ///
    /// # Errors
    /// A full sink, or a model limit (each names the limit); `NotStarted`
    /// before a successful [`Start::start`].
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error>;
}

/// How every model starts: from its checked parameters and a seed, in
/// place (so that a model's state, tens of KB on an MCU, is never a
/// temporary), ready to step or refused with the reason.
pub trait Start<'a>: Simulation {
    /// The parameters it starts from.
    type Params: ?Sized;

    /// (Re)starts from `params` and `seed`.
    ///
    /// # Errors
    /// The parameter or limit that refuses the run; stepping then returns
    /// the same error.
    fn start(&mut self, params: &'a Self::Params, seed: u64) -> Result<(), Error>;
}
