//! The presets drawn on the OLED by the core's rig renderer
//! ([`morphogen::rig`]): one palette for a monochrome panel, the one place
//! a [`Rig`] is built, and a sink that streams each record and draws it.

use morphogen::rig::embedded_graphics::pixelcolor::BinaryColor;
use morphogen::rig::{CellSlot, Rig, View};
use morphogen::stream::{Record, Sink, SinkError};

use crate::board::Oled;

/// The rig's palette on a monochrome panel: index 0 (the background, and
/// what a frame start clears to) is dark, index 1 lit; colours are taken
/// modulo the length, so odd indices are lit and even ones dark. Mosaic
/// cell types 1 and 2 (index = type) are thus lit and dark: two types
/// stay apart. Rings (module + 1), curves (series + 1) and mesh vertices
/// (1) start lit.
pub const PALETTE: [BinaryColor; 2] = [BinaryColor::Off, BinaryColor::On];

/// The rig that draws a preset through `view`, keeping a frame's cells in
/// `cells`. The only place a [`Rig`] is built: when the rig's storage
/// changes, this is what changes.
pub fn rig(view: View, cells: &mut [CellSlot]) -> Rig<'_, BinaryColor> {
    Rig::new(view, &PALETTE, cells)
}

/// A [`Sink`] that writes each record to `stream` (the framed UART
/// stream, first, so the receiver's bytes never wait on the display), then
/// draws it on the OLED's buffer, and sends the buffer to the panel at
/// each frame's end.
pub struct Shown<'a, 'p, S> {
    stream: &'a mut S,
    rig: &'a mut Rig<'p, BinaryColor>,
    oled: &'a mut Oled,
}

impl<'a, 'p, S: Sink> Shown<'a, 'p, S> {
    /// Streams into `stream` and draws with `rig` on `oled`.
    pub fn new(
        stream: &'a mut S,
        rig: &'a mut Rig<'p, BinaryColor>,
        oled: &'a mut Oled,
    ) -> Shown<'a, 'p, S> {
        Shown { stream, rig, oled }
    }
}

impl<S: Sink> Sink for Shown<'_, '_, S> {
    /// A display that fails (a loose wire: the I²C write is not
    /// acknowledged) is [`SinkError::Write`], as a failed UART is.
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.stream.record(record)?;
        self.rig
            .draw(record, self.oled)
            .map_err(|_| SinkError::Write)?;
        if matches!(record, Record::FrameEnd { .. }) {
            self.oled.flush().map_err(|_| SinkError::Write)?;
        }
        Ok(())
    }
}
