//! Morphogen on a Cortex-M: runs every preset of the core's registry
//! ([`morphogen::preset::PRESETS`]) with its default seed and writes the
//! framed streams to UART0, back to back — the same bytes `morphogen run`
//! writes to `stream.bin` — while logging progress and costs with `defmt`.
//!
//! Built for QEMU's `lm3s6965evb` (TI Stellaris LM3S6965: Cortex-M3, no FPU,
//! 64 KB SRAM, 256 KB flash); see `README.md` for the check script, the
//! cost report and real hardware.
//!
//! Log lines that start with `report` are machine-read by
//! `scripts/firmware-check.sh` and go into `REPORT.md`.
#![no_std]
#![no_main]
#![deny(missing_docs, clippy::unwrap_used, clippy::expect_used)]

#[cfg(all(feature = "semihosting", feature = "rtt"))]
compile_error!(
    "choose one defmt transport: `semihosting` (default) or `rtt` (with --no-default-features)"
);
#[cfg(not(any(feature = "semihosting", feature = "rtt")))]
compile_error!("enable a defmt transport: `semihosting` (default) or `rtt`");

#[cfg(feature = "rtt")]
use defmt_rtt as _;
#[cfg(feature = "semihosting")]
use defmt_semihosting as _;

mod board;
mod cost;
mod exit;

use core::mem::MaybeUninit;

use cortex_m_rt::{ExceptionFrame, entry, exception};
use morphogen::preset::{self, PRESETS, Runner};
use morphogen::sim::Progress;
use morphogen::stream::Encoder;

use crate::board::Uart0;
use crate::cost::{InstructionClock, StackPaint};

/// The preset runner, the largest object of the program (tens of KB: it
/// holds the biggest model's state). In `.uninit`, neither copied from
/// flash (as `.data` would be: `Runner::Idle` is not all zeros) nor zeroed
/// at reset; `main` writes `Runner::Idle` into it in place.
#[unsafe(link_section = ".uninit.morphogen.RUNNER")]
static mut RUNNER: MaybeUninit<Runner> = MaybeUninit::uninit();

#[entry]
fn main() -> ! {
    // SAFETY: `main` runs once and never returns, and nothing else names
    // RUNNER, so this is the only reference to it, ever.
    let runner: &'static mut Runner = unsafe {
        let slot = (&raw mut RUNNER).cast::<Runner>();
        slot.write(Runner::new());
        &mut *slot
    };

    let Some(peripherals) = cortex_m::Peripherals::take() else {
        exit::failure()
    };
    board::init_clock();
    let uart = Uart0::init();
    let clock = InstructionClock::start(peripherals.SYST);

    defmt::info!(
        "morphogen firmware: {=usize} presets; runner {=usize} bytes in static RAM",
        PRESETS.len(),
        core::mem::size_of::<Runner>()
    );
    defmt::info!(
        "report clock qemu_cpu_hz={=u32} runner_bytes={=usize}",
        board::QEMU_CPU_HZ,
        core::mem::size_of::<Runner>()
    );
    // Each model's share of the Runner: what it needs beyond the baseline.
    defmt::info!(
        "report state growth-curve={=usize} horn={=usize} lsystem={=usize} body={=usize} mosaic={=usize} bones={=usize}",
        core::mem::size_of::<morphogen::growth_curve::GrowthCurve>(),
        core::mem::size_of::<morphogen::horn::Horn>(),
        core::mem::size_of::<morphogen::lsys::LSystem>(),
        core::mem::size_of::<morphogen::body::Body<'static>>(),
        core::mem::size_of::<morphogen::mosaic::Mosaic<morphogen::mosaic::presets::McuStore>>(),
        core::mem::size_of::<
            morphogen::bones::Bones<
                { morphogen::bones::presets::MCU_VERTICES },
                { morphogen::bones::presets::MCU_TRIANGLES },
            >,
        >()
    );

    let mut failed = 0u32;
    for preset in PRESETS {
        defmt::info!("{=str}: seed {=u64}", preset.name, preset.default_seed);
        let mut encoder = Encoder::new(uart);
        let mut next_quarter = 1u64;
        let mut log_progress = |p: Progress| {
            // Four lines per preset: at 25, 50, 75 and 100 %.
            if u64::from(p.done) * 4 >= next_quarter * u64::from(p.total) {
                defmt::info!("  {=u32}/{=u32}", p.done, p.total);
                next_quarter = u64::from(p.done) * 4 / u64::from(p.total).max(1) + 1;
            }
        };
        let start = clock.now();
        let result = preset::run(
            preset,
            preset.default_seed,
            runner,
            &mut encoder,
            &mut log_progress,
        );
        let ticks = clock.now().wrapping_sub(start);
        match result {
            Ok(()) => defmt::info!(
                "report preset={=str} seed={=u64} frames={=u32} bytes={=u64} digest={=u64:016x} systicks={=u64}",
                preset.name,
                preset.default_seed,
                encoder.frames(),
                encoder.bytes(),
                encoder.digest(),
                ticks
            ),
            Err(e) => {
                defmt::error!("report preset={=str} failed: {}", preset.name, e);
                failed += 1;
            }
        }
    }
    uart.flush();

    let stack = StackPaint::measure();
    defmt::info!(
        "report stack peak={=u32} region={=u32} static={=u32}",
        stack.peak_bytes,
        stack.region_bytes,
        stack.static_bytes
    );
    if failed == 0 {
        defmt::info!("all {=usize} presets streamed", PRESETS.len());
        exit::success()
    } else {
        defmt::error!("{=u32} presets failed", failed);
        exit::failure()
    }
}

#[exception]
fn SysTick() {
    cost::on_systick_wrap();
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!("hard fault at pc={=u32:#010x}", frame.pc());
    exit::failure()
}

/// Logs where the panic happened (no message formatting: it would pull
/// `core::fmt` into flash) and exits with a failure code.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    match info.location() {
        Some(at) => defmt::error!("panicked at {=str}:{=u32}", at.file(), at.line()),
        None => defmt::error!("panicked"),
    }
    exit::failure()
}

/// `defmt::panic!` and friends end here.
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    exit::failure()
}
