//! The crate-wide error: one variant per module that can fail.

use crate::body::BodyError;
use crate::bones::BonesError;
use crate::horn::HornError;
use crate::lsys::LsysError;
use crate::mosaic::MosaicError;
use crate::rng::RngError;
use crate::shrinkwrap::ShrinkwrapError;
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
    /// A horn's parameters are inconsistent.
    Horn(HornError),
    /// A mosaic's parameters or control inputs are unusable.
    Mosaic(MosaicError),
    /// An L-system's grammar, derivation or turtle failed.
    Lsys(LsysError),
    /// A body model, its growth table or its mesh is unusable.
    Body(BodyError),
    /// A shrinkwrap run cannot start.
    Shrinkwrap(ShrinkwrapError),
    /// A bone run's frames do not fit its grammar.
    Bones(BonesError),
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
            Error::Horn(e) => write!(f, "horn: {e}"),
            Error::Mosaic(e) => write!(f, "mosaic: {e}"),
            Error::Lsys(e) => write!(f, "L-system: {e}"),
            Error::Body(e) => write!(f, "body: {e}"),
            Error::Shrinkwrap(e) => write!(f, "shrinkwrap: {e}"),
            Error::Bones(e) => write!(f, "bones: {e}"),
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

impl From<HornError> for Error {
    fn from(e: HornError) -> Error {
        Error::Horn(e)
    }
}

impl From<LsysError> for Error {
    fn from(e: LsysError) -> Error {
        Error::Lsys(e)
    }
}

impl From<BodyError> for Error {
    fn from(e: BodyError) -> Error {
        Error::Body(e)
    }
}
