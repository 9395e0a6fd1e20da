//! What the OLED shows while a preset streams ([`Drawing`]), and the
//! handshake that lets a check script photograph it ([`ScreenSync`]).

use morphogen::embedded_io::Write;
use morphogen::rig::embedded_graphics::pixelcolor::Gray4;
use morphogen::rig::{Bounds, Rig};
use morphogen::stream::{Encoder, Record, Sink, SinkError};

use crate::board::Uart1;
use crate::oled::{Frame, Oled};

/// A sink that sends each record to the UART encoder, draws it into the
/// frame, and shows the frame on the OLED at each frame's end. After the
/// header it sends the run's extent (a link record, outside the stream's
/// digest), so that a receiver can fit its view to it before frame 0.
pub struct Drawing<'a, 'p, W: Write> {
    /// Where the stream goes.
    pub encoder: &'a mut Encoder<W>,
    /// What the run draws, measured by a first run.
    pub extent: &'a Bounds,
    /// The rig renderer, fitted to the preset.
    pub rig: &'a mut Rig<'p, Gray4>,
    /// The picture being drawn.
    pub frame: &'a mut Frame,
    /// Where it is shown.
    pub oled: &'a mut Oled,
}

impl<W: Write> Sink for Drawing<'_, '_, W> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.encoder.record(record)?;
        if let Record::Header(_) = record {
            self.encoder.link(&self.extent.to_record())?;
        }
        // The frame never fails to draw; a rig error is a too-small plane.
        self.rig
            .draw(record, self.frame)
            .map_err(|_| SinkError::Write)?;
        if let Record::FrameEnd { .. } = record {
            self.oled.show(self.frame);
        }
        Ok(())
    }
}

/// The argument that turns the handshake on.
const FLAG: &str = "--screen-sync";

/// UART1, when the program was started with `--screen-sync`: after each
/// preset's last frame it sends the preset's name and a newline, and waits
/// for any byte back before the next preset draws (in QEMU the check
/// script answers once it has taken the OLED's `screendump`).
pub struct ScreenSync {
    uart: Uart1,
}

impl ScreenSync {
    /// The handshake, if the arguments name `--screen-sync`
    /// ([`crate::args`]).
    pub fn from_args() -> Option<ScreenSync> {
        crate::args::flag(FLAG).then(|| ScreenSync {
            uart: Uart1::init(),
        })
    }

    /// Announces that `name`'s last frame is on the OLED, and waits.
    pub fn shown(&mut self, name: &str) {
        let Ok(()) = self.uart.write_all(name.as_bytes());
        let Ok(()) = self.uart.write_all(b"\n");
        self.uart.read_byte();
    }
}
