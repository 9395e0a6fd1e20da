//! Fuzzes scenario files (`docs/scenarios.md`): any UTF-8 input is read
//! with `Scenario::from_text`. An input whose first line is
//! `--set KEY=VALUE` is the rest of the file with that `--set` applied.
//! A refused file's error names where (`fuzz.toml:LINE: …`, `fuzz.toml: …`
//! or `--set KEY=VALUE: …`) in under 4 KB; an accepted one written out
//! self-contained reads back to the same model (parameter digest, name,
//! seed). No input may panic.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run scenario` from the repository root
//! (or `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen_scenario::{Error, Scenario};

/// The file name errors must start with.
const ORIGIN: &str = "fuzz.toml";
/// The longest error message accepted.
const MAX_ERROR_BYTES: usize = 4096;

fn check_error(e: &Error) {
    let shown = e.to_string();
    assert!(
        shown.starts_with(ORIGIN) || shown.starts_with("--set "),
        "error without its place: {shown}"
    );
    assert!(
        shown.len() < MAX_ERROR_BYTES,
        "error of {} bytes: {}…",
        shown.len(),
        &shown[..shown.floor_char_boundary(200)]
    );
}

/// What identifies a checked scenario's model.
fn identity(s: &Scenario) -> (u64, String, u64) {
    s.with_preset(|p| (p.model.params_digest(), p.name.to_string(), p.default_seed))
}

fn check_ok(s: &Scenario) {
    let text = s.self_contained();
    let back = Scenario::from_text(ORIGIN, &text).map(|back| identity(&back));
    assert_eq!(
        back,
        Ok(identity(s)),
        "its self-contained text reads back to the same model:\n{text}"
    );
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = core::str::from_utf8(data) else {
        return;
    };
    let set = text.strip_prefix("--set ").and_then(|rest| {
        let (line, file) = rest.split_once('\n').unwrap_or((rest, ""));
        let (key, value) = line.split_once('=')?;
        Some(((key.to_string(), value.to_string()), file))
    });
    let (set, text) = match set {
        Some((set, file)) => (Some(set), file),
        None => (None, text),
    };
    match Scenario::from_text(ORIGIN, text) {
        Err(e) => check_error(&e),
        Ok(base) => {
            check_ok(&base);
            if let Some(set) = set {
                match base.clone_with_sets(&[set]) {
                    Err(e) => check_error(&e),
                    Ok(changed) => check_ok(&changed),
                }
            }
        }
    }
});
