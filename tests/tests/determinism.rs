//! The determinism contract across build profiles: the stream a release
//! build writes equals, byte for byte, the one this (debug) test build
//! computes in process.

use std::process::Command;

use morphogen_cli::exec;
use morphogen_tests::release_binary;

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
