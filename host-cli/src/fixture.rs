//! Golden fixtures: `fixtures/<preset>/stream.bin` (the encoded stream) and
//! `summary.toml` (a human-readable summary). `bless` is the only writer;
//! each file is written to a temporary file beside it and renamed.

use std::collections::BTreeMap;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen::stream::{Decoder, Record};
use serde::{Deserialize, Serialize};

use crate::exec::{PresetRef, Run};

/// The stream file inside a fixture folder.
pub const STREAM_FILE: &str = "stream.bin";
/// The summary file inside a fixture folder.
pub const SUMMARY_FILE: &str = "summary.toml";

/// What `summary.toml` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The preset's name.
    pub preset: String,
    /// The seed the stream was made with (`verify` re-runs with it).
    pub seed: u64,
    /// One line on what the preset is.
    pub description: String,
    /// Wire format version.
    pub format_version: u16,
    /// Parameter digest (hex) from the header.
    pub params_digest: String,
    /// CRC-64/XZ of `stream.bin` (hex).
    pub stream_digest: String,
    /// Size of `stream.bin`.
    pub bytes: u64,
    /// Number of frames (records).
    pub frames: u32,
    /// Records per kind.
    pub records: BTreeMap<String, u64>,
}

/// A fixture read from disk.
#[derive(Debug)]
pub struct Fixture {
    /// Its summary.
    pub summary: Summary,
    /// Its stream bytes.
    pub stream: Vec<u8>,
}

/// The folder of `preset`'s fixture.
#[must_use]
pub fn dir(fixtures: &Path, preset: &str) -> PathBuf {
    fixtures.join(preset)
}

/// Reads `preset`'s fixture.
///
/// # Errors
/// A missing or unreadable file, or a summary that is not valid TOML of
/// the expected shape; each names the file.
pub fn load(fixtures: &Path, preset: &str) -> Result<Fixture> {
    let dir = dir(fixtures, preset);
    if !dir.is_dir() {
        bail!(
            "no fixture for preset '{preset}' at {} (create it with `morphogen bless {preset}`)",
            dir.display()
        );
    }
    let summary_path = dir.join(SUMMARY_FILE);
    let text = fs::read_to_string(&summary_path)
        .with_context(|| format!("cannot read {}", summary_path.display()))?;
    let summary: Summary = toml::from_str(&text)
        .with_context(|| format!("{} is not a valid fixture summary", summary_path.display()))?;
    if summary.preset != preset {
        bail!(
            "{} names preset '{}', but lives in the folder of '{preset}'",
            summary_path.display(),
            summary.preset
        );
    }
    let stream_path = dir.join(STREAM_FILE);
    let stream =
        fs::read(&stream_path).with_context(|| format!("cannot read {}", stream_path.display()))?;
    Ok(Fixture { summary, stream })
}

/// The summary of a run of `preset`.
#[must_use]
pub fn summarise(preset: PresetRef, seed: u64, run: &Run) -> Summary {
    let mut records = BTreeMap::new();
    let mut params = 0;
    let mut version = 0;
    for d in Decoder::new(&run.stream) {
        if let Ok(r) = &d.result {
            *records.entry(r.kind().to_string()).or_insert(0) += 1;
            if let Record::Header(h) = r {
                params = h.params;
                version = h.version;
            }
        }
    }
    Summary {
        preset: preset.name().to_string(),
        seed,
        description: preset.summary().to_string(),
        format_version: version,
        params_digest: format!("{params:016x}"),
        stream_digest: format!("{:016x}", run.digest),
        bytes: run.stream.len() as u64,
        frames: run.frames,
        records,
    }
}

/// Writes `preset`'s fixture from `run`, each file atomically.
///
/// # Errors
/// When the folder cannot be created or a file cannot be written; nothing
/// is left half-written.
pub fn bless(fixtures: &Path, summary: &Summary, run: &Run) -> Result<PathBuf> {
    let dir = dir(fixtures, &summary.preset);
    fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let text = toml::to_string(summary).context("cannot render the summary")?;
    write_atomic(&dir.join(STREAM_FILE), &run.stream)?;
    write_atomic(&dir.join(SUMMARY_FILE), text.as_bytes())?;
    Ok(dir)
}

/// Writes `bytes` to a temporary file in `path`'s folder, then renames it.
///
/// # Errors
/// When the folder is not writable or the rename fails.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut tmp = tempfile::Builder::new()
        .prefix(".morphogen-")
        .tempfile_in(folder)
        .with_context(|| format!("cannot write in {}", folder.display()))?;
    tmp.write_all(bytes)
        .with_context(|| format!("cannot write {}", path.display()))?;
    tmp.as_file()
        .sync_all()
        .with_context(|| format!("cannot write {}", path.display()))?;
    // tempfile creates files 0600; outputs and fixtures are ordinary files.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(fs::Permissions::from_mode(0o644))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    tmp.persist(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}
