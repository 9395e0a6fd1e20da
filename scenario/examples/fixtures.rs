//! Every built-in scenario run with its default seed, its stream compared
//! byte for byte with its fixture (`<FIXTURES>/<name>/stream.bin`): what
//! `morphogen verify` checks, without the host's outputs and their
//! dependencies, so that it cross-builds in a fraction of the CLI's time.
//! `scripts/targets-check.sh` runs it on s390x (big-endian) under qemu-user.
//!
//! ```sh
//! cargo run --release -p morphogen-scenario --example fixtures -- fixtures
//! ```
//!
//! Prints `ok NAME (FRAMES frames, digest DIGEST)` per preset, then
//! `N ok, M mismatch`; exits 1 on any mismatch or missing fixture.

use std::path::Path;
use std::process::ExitCode;

use morphogen::stream::Encoder;
use morphogen_scenario::Scenario;
use rayon::prelude::*;

/// One preset's run against its fixture: the line to print, and whether
/// the stream was the fixture's.
fn check(scenario: &Scenario, fixtures: &Path) -> (String, bool) {
    let name = scenario.name();
    let mut encoder = Encoder::new(Vec::new());
    let ran = scenario.with_preset(|preset| {
        morphogen_scenario::run::run(preset, scenario.seed(), &mut encoder, &mut |_| {})
    });
    if let Err(e) = ran {
        return (format!("FAILED {name}: {e}"), false);
    }
    let (frames, digest) = (encoder.frames(), encoder.digest());
    let path = fixtures.join(name).join("stream.bin");
    match std::fs::read(&path) {
        Ok(expected) if expected == *encoder.writer() => (
            format!("ok {name} ({frames} frames, digest {digest:016x})"),
            true,
        ),
        Ok(expected) => (
            format!(
                "MISMATCH {name}: {} bytes, digest {digest:016x}; {} has {} bytes",
                encoder.writer().len(),
                path.display(),
                expected.len()
            ),
            false,
        ),
        Err(e) => (format!("MISSING {name}: {}: {e}", path.display()), false),
    }
}

fn main() -> ExitCode {
    let fixtures = std::env::args_os()
        .nth(1)
        .unwrap_or_else(|| "fixtures".into());
    let results: Vec<(String, bool)> = morphogen_scenario::builtins()
        .par_iter()
        .map(|scenario| check(scenario, Path::new(&fixtures)))
        .collect();
    let ok = results.iter().filter(|(_, same)| *same).count();
    for (line, _) in &results {
        println!("{line}");
    }
    println!("{ok} ok, {} mismatch", results.len() - ok);
    if ok == results.len() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
