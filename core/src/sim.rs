//! The face every simulation shows to host, firmware and tests: a stepper
//! that pushes records into a [`Sink`] and reports its progress.
//!
//! Every model starts through [`Start`] with its parameters and a seed, in
//! place, then steps; each step pushes its records into any [`Sink`] — an
//! encoder, a display, or one of your own:
//!
//! ```
//! use morphogen::fx::Fx;
//! use morphogen::growth::Sigmoid;
//! use morphogen::growth_curve::{GrowthCurve, Params};
//! use morphogen::sim::{Simulation, Start};
//! use morphogen::stream::{Record, Sink, SinkError};
//!
//! /// Keeps the last sample of the growth f(t) (series 0).
//! struct Last(Fx);
//! impl Sink for Last {
//!     fn record(&mut self, record: &Record) -> Result<(), SinkError> {
//!         if let Record::Sample { series: 0, y, .. } = record {
//!             self.0 = *y;
//!         }
//!         Ok(())
//!     }
//! }
//!
//! // The horn paper's seasonal growth over a year (Sec. 2), sampled daily.
//! static PARAMS: Params = Params {
//!     growth: Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), 365),
//!     days: 365,
//! };
//! let mut curve = GrowthCurve::IDLE; // a `static` on a device
//! curve.start(&PARAMS, 0).unwrap();
//! let mut last = Last(Fx::ZERO);
//! loop {
//!     let progress = curve.step(&mut last).unwrap();
//!     if progress.finished() {
//!         break;
//!     }
//! }
//! assert_eq!(last.0, Fx::ONE); // f(T) = 1: the year's growth is complete
//! ```

use heapless::Vec;

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

/// A model's deferred error: the refusal of its parameters, or the error
/// that stopped its run, kept so that every later [`Simulation::step`]
/// returns it too.
///
/// Empty, it is all zero bytes (a `heapless::Vec` of capacity one, where
/// the `None` of an `Option<Error>` would be a non-zero niche): an idle
/// model is then all zeros, and the [`Runner`](crate::preset::Runner)
/// writes one into its slot with a memset instead of copying a template of
/// the whole model out of flash.
#[derive(Clone, Debug, Default)]
pub(crate) struct Deferred(Vec<Error, 1>);

impl Deferred {
    /// No error (`const`, for a `static`).
    pub(crate) const fn new() -> Deferred {
        Deferred(Vec::new())
    }

    /// Keeps `result`'s error, or forgets the kept one if `result` is
    /// `Ok`; returns `result`.
    pub(crate) fn keep(&mut self, result: Result<(), Error>) -> Result<(), Error> {
        self.0.clear();
        if let Err(e) = result {
            let _ = self.0.push(e); // capacity 1, just cleared
        }
        result
    }

    /// The kept error, if any.
    pub(crate) fn check(&self) -> Result<(), Error> {
        match self.0.first() {
            Some(&e) => Err(e),
            None => Ok(()),
        }
    }
}
