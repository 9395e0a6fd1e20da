//! The one output vocabulary and its wire format (specified for
//! receivers in `docs/stream-format.md`).
//!
//! A simulation pushes [`Record`]s into a [`Sink`]. The [`Encoder`] sink
//! turns each record into a frame — postcard bytes, a CRC-32, COBS, a zero
//! delimiter — and keeps a CRC-64 digest of every byte it wrote. The
//! [`Reader`] takes frames back one byte at a time, reports corrupt ones
//! as typed errors and resynchronises at the next zero byte; the
//! [`Decoder`] reads a whole byte string with it.

mod decode;
mod digest;
mod encode;
mod read;
mod record;

pub use decode::{Decoded, Decoder};
pub use digest::{ParamDigest, StreamDigest, params_digest};
pub(crate) use encode::frame_payload;
pub use encode::{Encoder, MAX_FRAME, MAX_RECORD};
pub use read::{Deframer, FrameError, Reader};
pub use record::{FORMAT_VERSION, Header, PresetName, Record};

/// Where records go.
pub trait Sink {
    /// Takes one record.
    ///
    /// # Errors
    /// When the record cannot be stored or written.
    fn record(&mut self, record: &Record) -> Result<(), SinkError>;
}

/// A sink that could not take a record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SinkError {
    /// The record does not fit `MAX_RECORD` bytes once encoded.
    RecordTooLarge,
    /// A bounded sink is full (its capacity).
    Full {
        /// The capacity that was exceeded.
        capacity: u32,
    },
    /// The writer (an `embedded_io::Write`) or the display failed.
    Write,
}

impl core::fmt::Display for SinkError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SinkError::RecordTooLarge => {
                write!(f, "a record exceeds MAX_RECORD = {MAX_RECORD} bytes")
            }
            SinkError::Full { capacity } => {
                write!(f, "the output buffer is full ({capacity} bytes)")
            }
            SinkError::Write => write!(f, "the output could not be written"),
        }
    }
}

impl core::error::Error for SinkError {}
