//! The ram horn of `horn_direct` run through the [`Runner`], the one
//! place the firmware runs any model in: the same stream, but every model's
//! code is linked and the runner's static RAM is the biggest model's state
//! (`docs/embedding.md`, "Through the Runner"). Ends successfully when the
//! stream's digest is the golden fixture's.
#![no_std]
#![no_main]

#[path = "shared/ram_horn.rs"]
mod ram_horn;

use cortex_m_rt::entry;
use morphogen::embedded_io::Write;
use morphogen::preset::{self, Model, Preset, Runner};
use morphogen::stream::Encoder;
use morphogen_firmware::board::{self, Uart0};
use morphogen_firmware::cost::StackPaint;
use morphogen_firmware::exit;

/// The preset the runner runs.
static RAM_HORN: Preset<'static> = Preset {
    name: ram_horn::NAME,
    summary: "",
    default_seed: 0,
    model: Model::Horn(&ram_horn::PARAMS),
};

#[entry]
fn main() -> ! {
    // The runner in a `static` (`.bss`: an idle runner is all zeros).
    static mut RUNNER: Runner<'static> = Runner::new();

    board::init_clock();
    let mut encoder = Encoder::new(Uart0::init());
    let seed = RAM_HORN.default_seed;
    let ran = preset::run_with_digest(
        &RAM_HORN,
        seed,
        ram_horn::PARAMS_DIGEST,
        RUNNER,
        &mut encoder,
        &mut |_| {},
    );
    let Ok(()) = encoder.writer().flush();
    defmt::info!(
        "{=str}: runner {=usize} bytes, stream digest {=u64:#018x}",
        RAM_HORN.name,
        core::mem::size_of::<Runner<'static>>(),
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
