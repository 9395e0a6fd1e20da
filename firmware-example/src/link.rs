//! The stream a sender writes on UART0 ([`Linked`]): every record of a run,
//! and after its header the run's extent.

use morphogen::embedded_io::Write;
use morphogen::rig::Bounds;
use morphogen::stream::{Encoder, Record, Sink, SinkError};

/// A sink that sends each record to the UART encoder and, after the header,
/// the run's extent as a link record (outside the stream's digest), so that
/// a receiver can fit its view before frame 0 (`docs/stream-format.md`,
/// "The extent").
pub struct Linked<'a, W: Write> {
    /// Where the stream goes.
    pub encoder: &'a mut Encoder<W>,
    /// What the run draws, measured by a first run.
    pub extent: &'a Bounds,
}

impl<W: Write> core::fmt::Debug for Linked<'_, W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Linked")
            .field("extent", self.extent)
            .finish_non_exhaustive()
    }
}

impl<W: Write> Sink for Linked<'_, W> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.encoder.record(record)?;
        if let Record::Header(_) = record {
            self.encoder.link(&self.extent.to_record())?;
        }
        Ok(())
    }
}
