//! The presets drawn on the OLED by the core's rig renderer
//! ([`morphogen::rig`]): one palette for a monochrome panel, the one place
//! a [`Rig`] is built, and a sink that streams each record and draws it.

use morphogen::embedded_io::Write;
use morphogen::rig::embedded_graphics::geometry::Size;
use morphogen::rig::embedded_graphics::pixelcolor::BinaryColor;
use morphogen::rig::{Bounds, Rig, View, plane_bytes};
use morphogen::stream::{Encoder, Record, Sink, SinkError};

use crate::board::Oled;

/// The rig's palette on a monochrome panel: the background (what a frame
/// start clears to) is dark; inks alternate lit and dark (ink `n` is
/// `PALETTE[1 + n mod 2]`), so that everything drawn in ink 0 — lines,
/// points, the first mosaic type — is lit, and two mosaic types stay apart.
pub const PALETTE: [BinaryColor; 3] = [BinaryColor::Off, BinaryColor::On, BinaryColor::Off];

/// The cell plane a 128×64 panel needs (4 KiB).
pub const PLANE_BYTES: usize = plane_bytes(Size::new(128, 64));

/// The rig that draws a preset through `view`, with the cell `plane` of
/// [`PLANE_BYTES`].
pub fn rig(view: View, plane: &mut [u8]) -> Rig<'_, BinaryColor> {
    Rig::new(view, &PALETTE, plane)
}

/// A [`Sink`] that writes each record to `stream` (the framed UART
/// stream, first, so the receiver's bytes never wait on the display), then
/// draws it on the OLED's buffer, and sends the buffer to the panel at
/// each frame's end. After the header it sends the run's `extent` (a link
/// record, outside the stream's digest), which a receiver fits its view to.
pub struct Shown<'a, 'p, W> {
    stream: &'a mut Encoder<W>,
    extent: &'a Bounds,
    rig: &'a mut Rig<'p, BinaryColor>,
    oled: &'a mut Oled,
}

impl<'a, 'p, W: Write> Shown<'a, 'p, W> {
    /// Streams into `stream`, with `extent` after the header, and draws
    /// with `rig` on `oled`.
    pub fn new(
        stream: &'a mut Encoder<W>,
        extent: &'a Bounds,
        rig: &'a mut Rig<'p, BinaryColor>,
        oled: &'a mut Oled,
    ) -> Shown<'a, 'p, W> {
        Shown {
            stream,
            extent,
            rig,
            oled,
        }
    }
}

impl<W: Write> Sink for Shown<'_, '_, W> {
    /// A display that fails (a loose wire: the I²C write is not
    /// acknowledged) is [`SinkError::Write`], as a failed UART is.
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.stream.record(record)?;
        if let Record::Header(_) = record {
            self.stream.link(&self.extent.to_record())?;
        }
        self.rig
            .draw(record, self.oled)
            .map_err(|_| SinkError::Write)?;
        if matches!(record, Record::FrameEnd { .. }) {
            self.oled.flush().map_err(|_| SinkError::Write)?;
        }
        Ok(())
    }
}
