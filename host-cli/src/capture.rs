//! `verify --stream`: a device capture's streams, each against its
//! fixture.

use std::path::Path;

use anyhow::{Context, Result, bail};
use morphogen_stream_text::capture::split;
use morphogen_stream_text::verify;

use crate::{Outcome, fixture, say};

/// The largest capture `verify --stream` reads (every MCU preset streamed
/// back to back is 7.3 MB).
const MAX_CAPTURE_BYTES: u64 = 1 << 30;

/// A capture whole, up to [`MAX_CAPTURE_BYTES`] (a FIFO or a device, which
/// could block or never end, is refused by its type).
fn read_capture(path: &Path) -> Result<Vec<u8>> {
    morphogen_scenario::read_at_most(path, MAX_CAPTURE_BYTES, "MAX_CAPTURE_BYTES")
        .map_err(|e| anyhow::anyhow!(e))
}

/// `verify --stream`: each stream of the capture `file` compared with its
/// fixture in `fixtures`.
///
/// # Errors
/// An unreadable capture, one without frames, or streams without a
/// usable fixture (after every other is checked).
pub fn verify(file: &Path, fixtures: &Path) -> Result<Outcome> {
    let bytes =
        read_capture(file).with_context(|| format!("cannot read capture {}", file.display()))?;
    let parts = split(&bytes);
    if parts.is_empty() {
        bail!("capture {} holds no frames", file.display());
    }
    let mut outcome = Outcome::Ok;
    let mut missing = Vec::new();
    for part in &parts {
        let actual = &part.stream[..];
        let Some(header) = &part.header else {
            say!(
                "MISMATCH  {} bytes before the first readable header (at byte 0)",
                actual.len()
            )?;
            outcome = Outcome::Mismatch;
            continue;
        };
        let name = header.preset.as_str();
        let fixture = match fixture::load(fixtures, name) {
            Ok(fixture) => fixture,
            Err(e) => {
                say!("ERROR     {}: {e:#}", name.escape_debug())?;
                missing.push(name.escape_debug().to_string());
                continue;
            }
        };
        match verify::compare(&fixture.stream, actual) {
            None => say!(
                "ok        {name} (bytes {}..{} of the capture)",
                part.range.start,
                part.range.end
            )?,
            Some(diff) => {
                say!(
                    "MISMATCH  {name} (capture bytes {}..): {diff}",
                    part.range.start
                )?;
                outcome = Outcome::Mismatch;
            }
        }
    }
    say!("{} stream(s) in {}", parts.len(), file.display())?;
    if !missing.is_empty() {
        bail!(
            "the capture holds streams without a usable fixture: {}",
            missing.join(", ")
        );
    }
    Ok(outcome)
}
