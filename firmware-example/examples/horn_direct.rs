//! The ram horn driven directly: its parameters written in Rust
//! (`shared/ram_horn.rs`, the built-in scenario's bits), the model's own
//! state in a `static`, its stream encoded onto UART0 — no `Runner`, no
//! scenario crate, no other model linked (`docs/embedding.md`, "One model,
//! driven directly"). Ends successfully when the stream's digest is the
//! golden fixture's.
//!
//! ```text
//! cargo run --release --example horn_direct                                   # thumbv7m, in QEMU
//! cargo run --profile small --target thumbv6m-none-eabi --example horn_direct # Cortex-M0+ code, same QEMU
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
use morphogen::sim::Start;
use morphogen::stream::Encoder;
use morphogen_firmware::board::{self, Uart0};
use morphogen_firmware::cost::StackPaint;
use morphogen_firmware::exit;

/// Starts the horn in a stack frame of its own, as the `Runner` starts a
/// model: the start's temporaries (the kernel, built before it is moved
/// into the `static`) are then gone before the steps run, instead of
/// staying in `main`'s frame under every step.
#[inline(never)]
fn start(horn: &mut Horn<'static>, seed: u64) -> Result<(), Error> {
    horn.start(&ram_horn::PARAMS, seed)
}

#[entry]
fn main() -> ! {
    // A `static` that `cortex-m-rt` hands to `main` as `&'static mut`:
    // the horn's state (about 1 KB) in `.bss`, not on the stack.
    static mut HORN: Horn<'static> = Horn::IDLE;

    board::init_clock();
    let mut encoder = Encoder::new(Uart0::init());
    // A horn grows deterministically: the seed is the header's only.
    let seed = 0;
    let header = preset::header(ram_horn::NAME, seed, ram_horn::PARAMS_DIGEST);
    let ran =
        start(HORN, seed).and_then(|()| preset::drive(HORN, &header, &mut encoder, &mut |_| {}));
    let Ok(()) = encoder.writer().flush();
    defmt::info!(
        "{=str}: {=u32} frames, stream digest {=u64:#018x}",
        ram_horn::NAME,
        encoder.frames(),
        encoder.digest()
    );
    // The deepest the stack went (cortex-m-rt's `paint-stack`).
    defmt::info!("peak stack {=u32} B", StackPaint::measure().peak_bytes);
    match ran {
        Ok(()) if encoder.digest() == ram_horn::STREAM_DIGEST => exit::success(),
        Ok(()) => exit::failure(),
        Err(e) => {
            defmt::error!("{}", e);
            exit::failure()
        }
    }
}
