//! What the two Morphogen programs for the LM3S6965 evaluation board share:
//! the board (`board`: clock, UART0/UART1, instruction clock), the stream a
//! sender writes (`link`), its OLED (`oled`), what the OLED shows and the
//! screen handshake of the check script (`screen`), the semihosting
//! arguments (`args`), stack costs (`cost`), how a program ends (`exit`)
//! and where its `defmt` logs and panics go.
//!
//! The sender also runs on riscv32 (QEMU's RISC-V `virt` machine): the same
//! program on the board `board` chooses by target, streaming only (no OLED,
//! hence none of `oled`, `serve` or the receiver), its `defmt` logs and
//! exit code over RISC-V semihosting.
//!
//! - The **sender** (`src/main.rs`, binary `morphogen-firmware`) runs every
//!   built-in preset, streams it on UART0 and draws it on the OLED.
//! - The **receiver** (`src/bin/receiver.rs`, binary `morphogen-receiver`)
//!   reads a sender's stream on UART0 and draws it on its own OLED.
//!
//! Cargo features choose what a sender does besides streaming (each costs
//! flash, measured in `REPORT.md`): `extent` sends each run's extent
//! (`link`), `oled` draws on the OLED (`oled`, `screen`; needs `extent`;
//! the receiver needs it), `serve` runs scenarios sent over UART0 (and
//! needs `oled`, whose idle cell plane holds the message).
#![no_std]

#[cfg(all(feature = "semihosting", feature = "rtt"))]
compile_error!(
    "choose one defmt transport: `semihosting` (default) or `rtt` (with --no-default-features)"
);
#[cfg(not(any(feature = "semihosting", feature = "rtt")))]
compile_error!("enable a defmt transport: `semihosting` (default) or `rtt`");

#[cfg(all(feature = "oled", not(target_arch = "arm")))]
compile_error!(
    "the OLED is the LM3S6965's: on RISC-V build the stream-only sender (--no-default-features --features semihosting)"
);

#[cfg(feature = "rtt")]
use defmt_rtt as _;
#[cfg(feature = "semihosting")]
use defmt_semihosting as _;
// The runtime (entry, trap handler, linker script) and the critical
// section that defmt's logger takes.
#[cfg(target_arch = "riscv32")]
use {riscv as _, riscv_rt as _};

pub mod args;
pub mod board;
#[cfg(target_arch = "arm")]
pub mod cost;
pub mod exit;
#[cfg(feature = "extent")]
pub mod link;
#[cfg(feature = "oled")]
pub mod oled;
#[cfg(feature = "oled")]
pub mod screen;

/// The margin around a fitted view, in pixels (as the host's `--rig`).
pub const MARGIN: u32 = 1;

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
