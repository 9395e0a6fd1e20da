//! Puts `memory.x` where the linker finds it, and writes `presets.rs`:
//! the presets the firmware runs, generated from scenario files by
//! `morphogen_scenario::firmware` (the built-in ones that fit the MCU, or
//! those `MORPHOGEN_SCENARIOS` names), as for `firmware-example`.

#![allow(
    clippy::expect_used,
    reason = "a build script reports a failure by panicking"
)]

use std::env;
use std::fs;
use std::path::PathBuf;
use std::process;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    // The interrupt vectors and `device.x` come from rp2040-pac (feature
    // `rt` of rp2040-hal).
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x is readable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");

    // No surface mosaics: the Pico's runner is built without the core's
    // feature `surface-runner`.
    morphogen_scenario::firmware::write_presets(false).unwrap_or_else(|e| fail(&e));
}

/// Fails the build with `message`.
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    process::exit(1)
}
