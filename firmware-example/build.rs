//! Puts `memory.x` (and an empty `device.x`) where the linker finds them,
//! and writes `presets.rs`: the presets the firmware runs, generated from
//! scenario files by `morphogen_scenario::firmware` (the built-in ones that
//! fit the MCU, or those `MORPHOGEN_SCENARIOS` names).

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
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x is readable");
    // cortex-m-rt's `device` feature includes `device.x`, where a device
    // crate names its interrupt handlers; this firmware has none (its
    // vectors are in src/board/lm3s6965.rs).
    // ARMv6-M takes at most 32 device interrupts (cfg `armv6m`, as in
    // cortex-m-rt).
    println!("cargo::rustc-check-cfg=cfg(armv6m)");
    if env::var("TARGET").is_ok_and(|t| t.starts_with("thumbv6m-")) {
        println!("cargo::rustc-cfg=armv6m");
    }
    fs::write(
        out.join("device.x"),
        "/* No device interrupt handlers: every vector is DefaultHandler (src/board/lm3s6965.rs). */\n",
    )
    .expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    // QEMU's RISC-V `virt` machine's map, which the riscv32 build names
    // itself (`-Tmemory-virt.x`, .cargo/config.toml).
    println!("cargo:rerun-if-changed=memory-virt.x");
    println!("cargo:rerun-if-changed=build.rs");

    // Mosaics on a surface only with the feature `surface` (the runner
    // then runs them).
    morphogen_scenario::firmware::write_presets(env::var_os("CARGO_FEATURE_SURFACE").is_some())
        .unwrap_or_else(|e| fail(&e));
    write_example_horn(&out).unwrap_or_else(|e| fail(&e));
}

/// The variable naming the horn scenario file of the example
/// `horn_scenario` (default: the built-in `scenarios/ram-horn.toml`).
const EXAMPLE_HORN_VAR: &str = "MORPHOGEN_EXAMPLE_HORN";

/// Writes `example_horn.rs` for `examples/horn_scenario.rs`: one scenario
/// file as a `static` preset (`PRESETS`, by `morphogen_scenario::codegen`,
/// as `presets.rs`) and its parameter digest (`PARAMS_DIGEST`), computed
/// here so that the device needs no serializer for it. The summary, which
/// the device never shows, is left out.
fn write_example_horn(out: &std::path::Path) -> Result<(), String> {
    println!("cargo:rerun-if-env-changed={EXAMPLE_HORN_VAR}");
    let file = env::var_os(EXAMPLE_HORN_VAR).map_or_else(
        || PathBuf::from("../scenarios/ram-horn.toml"),
        PathBuf::from,
    );
    println!("cargo:rerun-if-changed={}", file.display());
    let scenario = morphogen_scenario::Scenario::load(&file, &[]).map_err(|e| e.to_string())?;
    let mut source = morphogen_scenario::codegen::presets(std::slice::from_ref(&scenario))?
        .replace(
            &format!("summary: {:?}", scenario.summary()),
            "summary: \"\"",
        );
    source.push_str(&format!(
        "\n/// The parameter digest of `PRESETS[0]` (computed by `build.rs`).\n\
         pub const PARAMS_DIGEST: u64 = {:#018x};\n",
        scenario.with_preset(|p| p.model.params_digest())
    ));
    fs::write(out.join("example_horn.rs"), source)
        .map_err(|e| format!("writing example_horn.rs: {e}"))
}

/// Fails the build with `message`.
fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    process::exit(1)
}
