//! Puts `memory.x` (and an empty `device.x`) where the linker finds them,
//! and writes `presets.rs`: the presets the firmware runs, generated from
//! scenario files by `morphogen_scenario::firmware` (the built-in ones that
//! fit the MCU, or those `MORPHOGEN_SCENARIOS` names).

use std::env;
use std::fs;
use std::path::PathBuf;
use std::process;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x is readable");
    // cortex-m-rt's `device` feature includes `device.x`, where a device
    // crate names its interrupt handlers; this firmware has none (its
    // vectors are in src/board.rs).
    // ARMv6-M takes at most 32 device interrupts (cfg `armv6m`, as in
    // cortex-m-rt).
    println!("cargo::rustc-check-cfg=cfg(armv6m)");
    if env::var("TARGET").is_ok_and(|t| t.starts_with("thumbv6m-")) {
        println!("cargo::rustc-cfg=armv6m");
    }
    fs::write(
        out.join("device.x"),
        "/* No device interrupt handlers: every vector is DefaultHandler (src/board.rs). */\n",
    )
    .expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");

    // Mosaics on a surface only with the feature `surface` (the runner
    // then runs them).
    morphogen_scenario::firmware::write_presets(env::var_os("CARGO_FEATURE_SURFACE").is_some())
        .unwrap_or_else(|e| fail(&e));
}

/// Fails the build with `message`.
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    process::exit(1)
}
