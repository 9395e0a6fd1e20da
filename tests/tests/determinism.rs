//! The determinism contract across build profiles: the stream a release
//! build writes equals, byte for byte, the one this (debug) test build
//! computes in process.

use std::path::Path;
use std::process::Command;

use morphogen_cli::exec;

/// Presets whose release stream is compared with the debug one: one per
/// model, small enough to run unoptimised.
const PROBES: &[&str] = &[
    "growth-curve",
    "ram-horn",
    "abop-shrub",
    "croton-mcu",
    "horse-growth",
    "long-bone",
];

/// The release `morphogen`: `$MORPHOGEN_RELEASE_BIN` when set (CI builds
/// it once for every check), else built here into `target/determinism`.
fn release_binary() -> std::path::PathBuf {
    if let Some(path) = std::env::var_os("MORPHOGEN_RELEASE_BIN") {
        return path.into();
    }
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = workspace.join("target/determinism");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .args([
            "build",
            "--release",
            "--quiet",
            "-p",
            "morphogen-cli",
            "--target-dir",
        ])
        .arg(&target)
        .current_dir(&workspace)
        .status()
        .expect("start cargo");
    assert!(status.success(), "release build failed");
    target.join("release/morphogen")
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "compares a release build with this one: run it in a debug build"
)]
fn release_build_writes_the_same_bytes_as_debug() {
    let binary = release_binary();
    let tmp = tempfile::tempdir().unwrap();
    for name in PROBES {
        let out = tmp.path().join(name);
        let o = Command::new(&binary)
            .args(["run", name, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let release = std::fs::read(out.join("stream.bin")).unwrap();
        let scenario = exec::find(name, &[]).unwrap();
        let debug = exec::run(&scenario, scenario.seed(), false).unwrap();
        assert_eq!(release.len(), debug.stream.len(), "{name}: lengths differ");
        assert!(
            release == debug.stream,
            "{name}: release and debug streams differ"
        );
    }
}
