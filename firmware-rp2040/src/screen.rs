//! The presets drawn on the OLED and the LED matrix by the core's rig
//! renderer ([`morphogen::rig`]): one palette for a monochrome panel, the
//! one place the OLED's [`Rig`] is built, and a sink that streams each
//! record and draws it on both.

use morphogen::embedded_io::Write;
use morphogen::rig::embedded_graphics::geometry::Size;
use morphogen::rig::embedded_graphics::pixelcolor::{BinaryColor, Rgb888};
use morphogen::rig::{Bounds, Rig, View, plane_bytes};
use morphogen::stream::{Encoder, Record, Sink, SinkError};

use crate::board::Oled;
use crate::leds::{Chain, Matrix};

/// The rig's palette on a monochrome panel: the background (what a frame
/// start clears to) is dark; inks alternate lit and dark (ink `n` is
/// `PALETTE[1 + n mod 2]`), so that everything drawn in ink 0 — lines,
/// points, the first mosaic type — is lit, and two mosaic types stay apart.
pub const PALETTE: [BinaryColor; 3] = [BinaryColor::Off, BinaryColor::On, BinaryColor::Off];

/// The OLED's size in pixels.
pub const SIZE: Size = Size::new(128, 64);

/// The cell plane a 128×64 panel needs (4 KiB).
pub const PLANE_BYTES: usize = plane_bytes(SIZE);

/// The rig that draws a preset through `view`, with the cell `plane` of
/// [`PLANE_BYTES`].
pub fn rig(view: View, plane: &mut [u8]) -> Rig<'_, BinaryColor> {
    Rig::new(view, &PALETTE, plane)
}

/// The OLED's rig and the panel it draws on.
pub type Screen<'a, 'p> = (&'a mut Rig<'p, BinaryColor>, &'a mut Oled);

/// The LED matrix's rig, the picture it draws and the chain that shows it.
pub type Lights<'a, 'p> = (&'a mut Rig<'p, Rgb888>, &'a mut Matrix, &'a mut Chain);

/// A [`Sink`] that writes each record to `stream` (the framed UART
/// stream, first, so the receiver's bytes never wait on the displays),
/// then draws it on the OLED's buffer and the LED matrix's picture, and
/// at each frame's end sends the buffer to the panel and the picture down
/// the LED chain. After the header it sends the run's `extent` (a link
/// record, outside the stream's digest), which a receiver fits its view
/// to.
pub struct Shown<'a, 'p, W> {
    stream: &'a mut Encoder<W>,
    extent: &'a Bounds,
    screen: Option<Screen<'a, 'p>>,
    lights: Lights<'a, 'p>,
}

impl<'a, 'p, W: Write> Shown<'a, 'p, W> {
    /// Streams into `stream`, with `extent` after the header, and draws on
    /// `screen` (when an OLED answered) and `lights`.
    pub fn new(
        stream: &'a mut Encoder<W>,
        extent: &'a Bounds,
        screen: Option<Screen<'a, 'p>>,
        lights: Lights<'a, 'p>,
    ) -> Shown<'a, 'p, W> {
        Shown {
            stream,
            extent,
            screen,
            lights,
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
        let frame_end = matches!(record, Record::FrameEnd { .. });
        if let Some((rig, oled)) = self.screen.as_mut() {
            rig.draw(record, *oled).map_err(|_| SinkError::Write)?;
            if frame_end {
                oled.flush().map_err(|_| SinkError::Write)?;
            }
        }
        let (rig, matrix, chain) = &mut self.lights;
        rig.draw(record, *matrix).map_err(|_| SinkError::Write)?;
        if frame_end {
            chain.show(matrix);
        }
        Ok(())
    }
}
