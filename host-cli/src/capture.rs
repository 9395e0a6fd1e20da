//! Splitting a device capture into the streams it holds: each starts with
//! a header record, back to back.

use std::ops::Range;
use std::path::Path;

use anyhow::{Context, Result, bail};

use morphogen::stream::{Decoder, Header, Record};

use crate::{Outcome, fixture, say, verify};

/// One stream within a capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Its header (`None` for bytes before the first readable header).
    pub header: Option<Header>,
    /// Where it lies in the capture.
    pub range: Range<usize>,
    /// Its bytes: those of `range` but the frames of link records
    /// ([`Record::Extent`]), which are not part of a stream.
    pub stream: Vec<u8>,
}

/// The streams of a capture, in order. Bytes before the first readable
/// header form a part without a header.
#[must_use]
pub fn split(capture: &[u8]) -> Vec<Part> {
    let mut parts: Vec<Part> = Vec::new();
    for d in Decoder::new(capture) {
        let end = d.offset + d.len;
        let bytes = &capture[d.offset..end];
        match d.result {
            Ok(Record::Header(h)) => parts.push(Part {
                header: Some(h),
                range: d.offset..end,
                stream: bytes.to_vec(),
            }),
            result => {
                let link = matches!(result, Ok(Record::Extent { .. }));
                match parts.last_mut() {
                    Some(last) => {
                        last.range.end = end;
                        if !link {
                            last.stream.extend_from_slice(bytes);
                        }
                    }
                    None => parts.push(Part {
                        header: None,
                        range: d.offset..end,
                        stream: if link { Vec::new() } else { bytes.to_vec() },
                    }),
                }
            }
        }
    }
    parts
}

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
