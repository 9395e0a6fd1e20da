//! What the OLED shows while a preset streams ([`Drawing`]), and the
//! handshake that lets a check script photograph it ([`ScreenSync`]).

use morphogen::embedded_io::Write;
use morphogen::rig::Rig;
use morphogen::rig::embedded_graphics::pixelcolor::Gray4;
use morphogen::stream::{Encoder, Record, Sink, SinkError};

use crate::board::Uart1;
use crate::oled::{Frame, Oled};

/// A sink that sends each record to the UART encoder, draws it into the
/// frame, and shows the frame on the OLED at each frame's end.
pub struct Drawing<'a, 'p, W: Write> {
    /// Where the stream goes.
    pub encoder: &'a mut Encoder<W>,
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

/// The semihosting argument that turns the handshake on.
const FLAG: &str = "--screen-sync";

/// UART1, when the firmware was started with `--screen-sync`: after each
/// preset's last frame it sends the preset's name and a newline, and waits
/// for any byte back before the next preset draws (in QEMU the check
/// script answers once it has taken the OLED's `screendump`).
pub struct ScreenSync {
    uart: Uart1,
}

impl ScreenSync {
    /// The handshake, if the semihosting arguments name [`FLAG`] (never on
    /// an RTT build: it has no semihosting).
    pub fn from_args() -> Option<ScreenSync> {
        #[cfg(feature = "semihosting")]
        {
            let args = semihosting::experimental::env::args::<64>().ok()?;
            if (&args).into_iter().any(|arg| arg == Ok(FLAG)) {
                return Some(ScreenSync {
                    uart: Uart1::init(),
                });
            }
        }
        None
    }

    /// Announces that `name`'s last frame is on the OLED, and waits.
    pub fn shown(&mut self, name: &str) {
        let Ok(()) = self.uart.write_all(name.as_bytes());
        let Ok(()) = self.uart.write_all(b"\n");
        self.uart.read_byte();
    }
}
