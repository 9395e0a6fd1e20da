//! The crate-wide error: one variant per module that can fail.

use crate::rng::RngError;
use crate::stream::SinkError;

/// Anything a simulation run can fail with. Every limit names itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// The output sink refused a record.
    Sink(SinkError),
    /// A variate generator was given an out-of-range parameter.
    Rng(RngError),
    /// A fixed capacity was exceeded.
    Capacity {
        /// The limit's name, as written in the code (e.g. `MAX_CELLS`).
        limit: &'static str,
        /// Its value.
        capacity: u32,
    },
    /// `step` was called on a runner that holds no simulation.
    NotStarted,
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Sink(e) => write!(f, "output: {e}"),
            Error::Rng(e) => write!(f, "random variate: {e}"),
            Error::Capacity { limit, capacity } => {
                write!(f, "capacity {limit} = {capacity} exceeded")
            }
            Error::NotStarted => f.write_str("no simulation has been started"),
        }
    }
}

impl core::error::Error for Error {}

impl From<SinkError> for Error {
    fn from(e: SinkError) -> Error {
        Error::Sink(e)
    }
}

impl From<RngError> for Error {
    fn from(e: RngError) -> Error {
        Error::Rng(e)
    }
}
