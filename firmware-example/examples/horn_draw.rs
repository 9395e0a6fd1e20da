//! A sink that streams and draws at once: the ram horn of `horn_direct`
//! driven directly, each record encoded onto UART0 and drawn by the core's
//! rig renderer into the OLED's 4-bit framebuffer (an `embedded-graphics`
//! `DrawTarget`), the frame shown at each frame's end
//! (`docs/embedding.md`, "Streaming and drawing"). The horn runs twice:
//! first into [`Bounds`] to fit the view to everything it will draw, then
//! into the sink; the stream is the golden fixture's, and the OLED shows
//! the picture `morphogen run ram-horn --rig 128x64:grey4` draws.
//!
//! ```text
//! cargo run --release --example horn_draw --features oled
//! ```
#![no_std]
#![no_main]

#[path = "shared/ram_horn.rs"]
mod ram_horn;

use cortex_m_rt::entry;
use morphogen::Error;
use morphogen::embedded_io::Write;
use morphogen::horn::Horn;
use morphogen::preset;
use morphogen::rig::embedded_graphics::pixelcolor::Gray4;
use morphogen::rig::{Bounds, PALETTE_GRAY4, Rig, View};
use morphogen::sim::Start;
use morphogen::stream::{Encoder, Record, Sink, SinkError};
use morphogen_firmware::board::{self, Uart0};
use morphogen_firmware::cost::StackPaint;
use morphogen_firmware::oled::{self, Frame, Oled};
use morphogen_firmware::{MARGIN, exit};

/// Streams each record and draws it: encoded onto the writer `W`, drawn
/// into `frame`, and `frame` shown on the OLED at each frame's end.
struct StreamAndDraw<'a, W: Write> {
    encoder: Encoder<W>,
    rig: Rig<'a, Gray4>,
    frame: &'a mut Frame,
    oled: Oled,
}

impl<W: Write> Sink for StreamAndDraw<'_, W> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.encoder.record(record)?;
        // Drawing into a framebuffer never fails; a rig error is a cell
        // plane too small for a mosaic's cells.
        self.rig
            .draw(record, self.frame)
            .map_err(|_| SinkError::Write)?;
        if let Record::FrameEnd { .. } = record {
            self.oled.show(self.frame);
        }
        Ok(())
    }
}

/// Starts the horn in a stack frame of its own (see `horn_direct`).
#[inline(never)]
fn start(horn: &mut Horn<'static>, seed: u64) -> Result<(), Error> {
    horn.start(&ram_horn::PARAMS, seed)
}

#[entry]
fn main() -> ! {
    // The horn's state and the OLED's picture (4 KiB) in `.bss`.
    static mut HORN: Horn<'static> = Horn::IDLE;
    static mut FRAME: Frame = Frame::new();

    board::init_clock();
    let seed = 0;
    let header = preset::header(ram_horn::NAME, seed, ram_horn::PARAMS_DIGEST);
    // First run: what the horn draws, to fit the view to it.
    let mut bounds = Bounds::new();
    let measured =
        start(HORN, seed).and_then(|()| preset::drive(HORN, &header, &mut bounds, &mut |_| {}));
    // A horn draws rings and points, no cells: its rig needs no cell plane
    // (a mosaic's would need `rig::plane_bytes(oled::SIZE)`, 4 KiB).
    let mut sink = StreamAndDraw {
        encoder: Encoder::new(Uart0::init()),
        rig: Rig::new(
            View::fit(&bounds, oled::SIZE, MARGIN),
            &PALETTE_GRAY4,
            &mut [],
        ),
        frame: FRAME,
        oled: Oled::init(),
    };
    let ran = measured
        .and_then(|()| start(HORN, seed))
        .and_then(|()| preset::drive(HORN, &header, &mut sink, &mut |_| {}));
    let Ok(()) = sink.encoder.writer().flush();
    defmt::info!(
        "{=str}: {=u32} frames streamed and drawn, stream digest {=u64:#018x}",
        ram_horn::NAME,
        sink.encoder.frames(),
        sink.encoder.digest()
    );
    // The deepest the stack went (cortex-m-rt's `paint-stack`).
    defmt::info!("peak stack {=u32} B", StackPaint::measure().peak_bytes);
    match ran {
        Ok(()) if sink.encoder.digest() == ram_horn::STREAM_DIGEST => exit::success(),
        Ok(()) => exit::failure(),
        Err(e) => {
            defmt::error!("{}", e);
            exit::failure()
        }
    }
}
