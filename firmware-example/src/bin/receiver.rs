//! The receiving end of a display rig: reads a sender's framed stream on
//! UART0 (115 200 baud, 8N1), one byte at a time through the core's
//! [`Reader`], and draws it on the board's 128×64 grey OLED through a
//! [`Receiver`]: each stream fitted to the extent its sender measured
//! (`Record::Extent`, after the header), each frame shown whole or not at
//! all — a frame with a damaged record, or whose start or end was lost, is
//! skipped and the OLED keeps the last good one. It logs every stream, bad
//! frame and skipped frame with `defmt`.
//!
//! Semihosting arguments (QEMU's `-semihosting-config arg=…`):
//! `--screen-sync` photographs each stream's last frame as the sender does
//! (`screen.rs`), and `--streams N` exits after N streams (a real receiver
//! listens for ever). `scripts/firmware-check.sh` feeds it the sender's
//! capture and compares its OLED with the sender's, picture for picture.
//!
//! Log lines that start with `report` are machine-read by the check script.
#![no_std]
#![no_main]

use cortex_m_rt::{ExceptionFrame, entry, exception};
use morphogen::rig::{self, PALETTE_GRAY4, Receiver};
use morphogen::stream::{PresetName, Reader, Record};
use morphogen_firmware::board::{self, Uart0};
use morphogen_firmware::oled::{self, Frame, Oled};
use morphogen_firmware::screen::ScreenSync;
use morphogen_firmware::{MARGIN, args, exit};

/// The OLED's picture (4 KiB, all zeros: black, in `.bss`).
static mut FRAME: Frame = Frame::new();

/// The rig's cell plane: ½ byte per OLED pixel (4 KiB, in `.bss`).
static mut PLANE: [u8; rig::plane_bytes(oled::SIZE)] = [0; rig::plane_bytes(oled::SIZE)];

/// What became of one stream's frames.
#[derive(Default)]
struct Tally {
    shown: u32,
    skipped: u32,
    bad: u32,
}

#[entry]
#[allow(
    unsafe_code,
    reason = "the one reference to each of the program's statics"
)]
fn main() -> ! {
    // SAFETY: `main` runs once and never returns, and nothing else names
    // FRAME or PLANE, so these are the only references to them, ever.
    let (frame, plane): (&'static mut Frame, &'static mut [u8]) = unsafe {
        let (frame, plane) = (&raw mut FRAME, &raw mut PLANE);
        (&mut *frame, &mut *plane)
    };
    board::init_clock();
    let mut uart = Uart0::init();
    let mut oled = Oled::init();
    let mut sync = ScreenSync::from_args();
    let streams = args::number("--streams");
    defmt::info!("morphogen receiver: reading frames on UART0");

    let mut reader = Reader::new();
    let mut receiver = Receiver::new(oled::SIZE, MARGIN, &PALETTE_GRAY4, plane);
    let mut preset = PresetName::new();
    let mut tally = Tally::default();
    let mut ended = 0u32;
    loop {
        let Some(result) = reader.push(uart.read_byte()) else {
            continue;
        };
        match &result {
            Ok(Record::Header(header)) => {
                preset.clone_from(&header.preset);
                tally = Tally::default();
                defmt::info!("stream {=str}: seed {=u64}", preset, header.seed);
            }
            Err(e) if e.is_corrupt() => {
                tally.bad += 1;
                defmt::warn!("  bad frame: {}", e);
            }
            _ => {}
        }
        let done = match receiver.take(&result, frame) {
            Ok(done) => done,
            Err(e) => {
                // Only a plane smaller than the OLED: not this program.
                defmt::error!("the rig cannot draw: {}", defmt::Debug2Format(&e));
                exit::failure()
            }
        };
        let Some(done) = done else { continue };
        if done.shown {
            oled.show(frame);
            tally.shown += 1;
        } else {
            tally.skipped += 1;
            defmt::warn!(
                "  frame {=u32} skipped ({=str})",
                done.frame,
                if receiver.fitted() {
                    "damaged"
                } else {
                    "no extent"
                }
            );
        }
        if done.last {
            defmt::info!(
                "report received preset={=str} shown={=u32} skipped={=u32} bad={=u32}",
                preset,
                tally.shown,
                tally.skipped,
                tally.bad
            );
            if let Some(sync) = sync.as_mut() {
                sync.shown(&preset);
            }
            ended += 1;
            if streams == Some(ended) {
                defmt::info!("all {=u32} streams received", ended);
                exit::success()
            }
        }
    }
}

#[exception]
#[allow(
    unsafe_code,
    reason = "cortex-m-rt declares the hard-fault handler unsafe"
)]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!("hard fault at pc={=u32:#010x}", frame.pc());
    exit::failure()
}
