//! What the OLED shows while a preset streams ([`Screen`], [`Drawing`]),
//! and the handshake that lets a check script photograph it
//! ([`ScreenSync`]).

use morphogen::embedded_io::Write;
use morphogen::rig::embedded_graphics::pixelcolor::Gray4;
use morphogen::rig::{PALETTE_GRAY4, Rig, View};
use morphogen::stream::{Record, Sink, SinkError};

use crate::MARGIN;
use crate::board::Uart1;
use crate::link::Linked;
use crate::oled::{self, Frame, Oled};

/// The OLED and what a sender draws on it with.
pub struct Screen {
    /// The panel.
    pub oled: Oled,
    /// The picture being drawn.
    pub frame: &'static mut Frame,
    /// The rig's cell plane (idle between runs: a sent scenario is read
    /// into it).
    pub plane: &'static mut [u8],
    /// The check script's handshake, if asked for.
    pub sync: Option<ScreenSync>,
}

impl core::fmt::Debug for Screen {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Screen")
            .field("sync", &self.sync)
            .finish_non_exhaustive()
    }
}

impl Screen {
    /// Runs `run` into a [`Drawing`]: `stream` and this screen, its view
    /// fitted to the stream's extent.
    pub fn draw<W: Write, T>(
        &mut self,
        stream: Linked<'_, W>,
        run: impl FnOnce(&mut dyn Sink) -> T,
    ) -> T {
        let mut rig = Rig::new(
            View::fit(stream.extent, oled::SIZE, MARGIN),
            &PALETTE_GRAY4,
            &mut *self.plane,
        );
        run(&mut Drawing {
            stream,
            rig: &mut rig,
            frame: &mut *self.frame,
            oled: &mut self.oled,
        })
    }

    /// With the handshake: announces that `name`'s last frame is shown and
    /// waits until it is photographed.
    pub fn shown(&mut self, name: &str) {
        if let Some(sync) = self.sync.as_mut() {
            sync.shown(name);
        }
    }
}

/// A sink that sends each record on to the stream, draws it into the
/// frame, and shows the frame on the OLED at each frame's end.
pub struct Drawing<'a, 'p, W: Write> {
    /// Where the stream goes.
    pub stream: Linked<'a, W>,
    /// The rig renderer, fitted to the preset.
    pub rig: &'a mut Rig<'p, Gray4>,
    /// The picture being drawn.
    pub frame: &'a mut Frame,
    /// Where it is shown.
    pub oled: &'a mut Oled,
}

impl<W: Write> core::fmt::Debug for Drawing<'_, '_, W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Drawing")
            .field("stream", &self.stream)
            .finish_non_exhaustive()
    }
}

impl<W: Write> Sink for Drawing<'_, '_, W> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.stream.record(record)?;
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

impl core::fmt::Debug for ScreenSync {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ScreenSync").finish_non_exhaustive()
    }
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
