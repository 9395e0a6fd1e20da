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

#[test]
fn a_mosaic_relaxes_to_the_same_bytes_on_any_number_of_threads() {
    // The host's relaxation keeps the cells in grid order through a day's
    // steps and shares the grid slots out among the threads, each summing
    // the pushes of its pairs in its share of the sums (those past its end
    // kept aside): 2 000 croton cells over 6 days, and a
    // watermelon's cells on its ellipsoid over 2, each day's cells
    // streamed, on 1, 2 and 3 threads give one stream each.
    for (name, days) in [("croton", "6"), ("watermelon-fruit", "2")] {
        let sets = [("mosaic.days", days), ("mosaic.frames", "\"every-day\"")]
            .map(|(k, v)| (k.to_owned(), v.to_owned()));
        let scenario = exec::find(name, &sets).unwrap();
        let streams: Vec<Vec<u8>> = [1, 2, 3]
            .into_iter()
            .map(|threads| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| exec::run(&scenario, scenario.seed(), false).unwrap().stream)
            })
            .collect();
        assert!(
            streams[0].len() > 1_000 * 3 * 10,
            "{name}: every day's cells"
        );
        assert!(streams[1] == streams[0], "{name}: 2 threads differ from 1");
        assert!(streams[2] == streams[0], "{name}: 3 threads differ from 1");
    }
}
