//! A horn from a scenario file turned into Rust at build time: `build.rs`
//! reads `scenarios/ram-horn.toml` (or the file `MORPHOGEN_EXAMPLE_HORN`
//! names) with `morphogen_scenario`, on the host, and writes it as a
//! `static` preset and its parameter digest (`$OUT_DIR/example_horn.rs`,
//! by `morphogen_scenario::codegen`, as the firmware's `presets.rs`). The
//! device links no reader and no serializer, and drives the horn directly
//! (`docs/embedding.md`, "From a scenario file, at build time").
//!
//! ```text
//! MORPHOGEN_EXAMPLE_HORN=my-horn.toml cargo build --release --example horn_scenario
//! ```
#![no_std]
#![no_main]

/// The scenario file as Rust: `PRESETS` (one preset) and `PARAMS_DIGEST`.
mod scenario {
    include!(concat!(env!("OUT_DIR"), "/example_horn.rs"));
}

use cortex_m_rt::entry;
use morphogen::Error;
use morphogen::embedded_io::Write;
use morphogen::horn::{Horn, HornParams};
use morphogen::preset::{self, Model};
use morphogen::sim::Start;
use morphogen::stream::Encoder;
use morphogen_firmware::board::{self, Uart0};
use morphogen_firmware::cost::StackPaint;
use morphogen_firmware::exit;

/// Starts the horn in a stack frame of its own (see `horn_direct`).
#[inline(never)]
fn start(
    horn: &mut Horn<'static>,
    params: &'static HornParams<'static>,
    seed: u64,
) -> Result<(), Error> {
    horn.start(params, seed)
}

#[entry]
fn main() -> ! {
    // The horn's state in `.bss` (see `horn_direct`).
    static mut HORN: Horn<'static> = Horn::IDLE;

    board::init_clock();
    let mut encoder = Encoder::new(Uart0::init());
    let [preset] = scenario::PRESETS else {
        exit::failure()
    };
    // The scenario file names its model: this program grows horns.
    let Model::Horn(params) = preset.model else {
        defmt::error!("{=str} is not a horn", preset.name);
        exit::failure()
    };
    let seed = preset.default_seed;
    let header = preset::header(preset.name, seed, scenario::PARAMS_DIGEST);
    let ran = start(HORN, params, seed)
        .and_then(|()| preset::drive(HORN, &header, &mut encoder, &mut |_| {}));
    let Ok(()) = encoder.writer().flush();
    defmt::info!(
        "{=str}: {=u32} frames, stream digest {=u64:#018x}",
        preset.name,
        encoder.frames(),
        encoder.digest()
    );
    // The deepest the stack went (cortex-m-rt's `paint-stack`).
    defmt::info!("peak stack {=u32} B", StackPaint::measure().peak_bytes);
    match ran {
        Ok(()) => exit::success(),
        Err(e) => {
            defmt::error!("{}", e);
            exit::failure()
        }
    }
}
