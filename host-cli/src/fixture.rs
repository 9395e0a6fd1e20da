//! Golden fixtures: `fixtures/<preset>/stream.bin` (the encoded stream) and
//! `summary.toml` (a human-readable summary). `bless` is the only writer;
//! each file is written to a temporary file beside it and renamed.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen::stream::{Decoder, Record};
use serde::{Deserialize, Serialize};

use morphogen_scenario::Scenario;

use crate::atomic::write_atomic;
use crate::exec::Run;

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
    /// The Morphogen that blessed it ([`crate::provenance::maker`]; none
    /// in a fixture blessed before summaries named it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blessed_by: Option<String>,
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

/// The scenario file inside a fixture folder of a scenario that is not a
/// built-in preset (self-contained: `verify` re-runs it from there).
pub const SCENARIO_FILE: &str = "scenario.toml";

/// The scenario `target` names for `verify` and `bless --accept`: a
/// scenario file, else the fixture of that name (from its own
/// `scenario.toml` when it has one), else a built-in preset.
///
/// # Errors
/// When it names none of these, or its scenario cannot be read.
pub fn target(target: &str, fixtures: &Path) -> Result<Scenario> {
    if !crate::exec::is_file(target)
        && morphogen_scenario::check::name(target).is_ok()
        && dir(fixtures, target).is_dir()
    {
        return scenario(fixtures, target);
    }
    crate::exec::find(target, &[])
}

/// The new stream `verify` leaves beside a fixture it does not match.
pub const PENDING_FILE: &str = "stream.bin.pending";

/// The scenario of the pending stream, where it is not the fixture's own
/// (`verify FILE.toml` of an edited file): `bless --accept` takes both.
pub const PENDING_SCENARIO_FILE: &str = "scenario.toml.pending";

/// The environment variable naming the fixtures folder.
pub const FIXTURES_ENV: &str = "MORPHOGEN_FIXTURES";

/// The fixtures folder: `given` (`--fixtures`), else
/// `$MORPHOGEN_FIXTURES`, else `fixtures/` in the current folder or the
/// nearest parent that has one (as a path from here: `../fixtures`) — so
/// an installed `morphogen` works inside the repository and inside a
/// user's project alike. With nothing found, a
/// writer (`bless`) gets a new `fixtures/` here.
///
/// # Errors
/// Nothing found for a reader, or no current folder.
pub fn locate(given: Option<PathBuf>, for_writing: bool) -> Result<PathBuf> {
    if let Some(dir) = given {
        return Ok(dir);
    }
    if let Some(dir) = std::env::var_os(FIXTURES_ENV).filter(|d| !d.is_empty()) {
        return Ok(PathBuf::from(dir));
    }
    let here = std::env::current_dir().context("cannot read the current folder")?;
    // As a path from here (`fixtures`, `../fixtures`), as messages show it.
    if let Some(up) = here.ancestors().position(|a| a.join("fixtures").is_dir()) {
        return Ok(std::iter::repeat_n("..", up)
            .collect::<PathBuf>()
            .join("fixtures"));
    }
    if for_writing {
        return Ok(PathBuf::from("fixtures"));
    }
    bail!(
        "no fixtures folder: give --fixtures DIR, set {FIXTURES_ENV}, or run inside a folder that has fixtures/ (searched {} and its parents)",
        here.display()
    )
}

/// Writes `stream`, made from `scenario`, as `name`'s pending stream, with
/// the scenario beside it when it is not the fixture's own; returns the
/// stream's path.
///
/// # Errors
/// When it cannot be written, or the fixture's scenario cannot be read.
pub fn write_pending(
    fixtures: &Path,
    name: &str,
    scenario: &Scenario,
    stream: &[u8],
) -> Result<PathBuf> {
    let folder = dir(fixtures, name);
    let path = folder.join(PENDING_FILE);
    let own = self::scenario(fixtures, name)?;
    let pending_scenario = folder.join(PENDING_SCENARIO_FILE);
    if same_scenario(&own, scenario) {
        remove_if_there(&pending_scenario)?;
    } else {
        write_atomic(&pending_scenario, scenario.self_contained().as_bytes())?;
    }
    write_atomic(&path, stream)?;
    Ok(path)
}

/// Whether two scenarios are the same file once self-contained.
fn same_scenario(a: &Scenario, b: &Scenario) -> bool {
    a.self_contained() == b.self_contained()
}

/// The keys whose values differ between the scenario a fixture was blessed
/// from and `run`, each as `key: blessed -> now` (a key one side lacks
/// reads `(none)`), in the files' order; dotted as `--set` takes them.
#[must_use]
pub fn changed_keys(blessed: &Scenario, run: &Scenario) -> Vec<String> {
    fn flatten(prefix: &str, v: &toml::Value, out: &mut Vec<(String, String)>) {
        match v {
            toml::Value::Table(t) => {
                for (k, v) in t {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    flatten(&key, v, out);
                }
            }
            toml::Value::Array(a) if a.iter().any(toml::Value::is_table) => {
                for (i, v) in a.iter().enumerate() {
                    flatten(&format!("{prefix}[{i}]"), v, out);
                }
            }
            other => {
                // An inline grammar or mask reads as its length.
                let text = other.to_string();
                let shown = if text.chars().count() > 60 {
                    format!("({} characters)", text.chars().count())
                } else {
                    text
                };
                out.push((prefix.to_string(), shown));
            }
        }
    }
    let keys = |s: &Scenario| {
        let mut out = Vec::new();
        if let Ok(v) = s.self_contained().parse::<toml::Table>() {
            flatten("", &toml::Value::Table(v), &mut out);
        }
        out
    };
    let (before, now) = (keys(blessed), keys(run));
    let find = |list: &[(String, String)], key: &str| {
        list.iter()
            .find(|(k, _)| k == key)
            .map_or("(none)".to_string(), |(_, v)| v.clone())
    };
    let mut changed = Vec::new();
    for (key, _) in before.iter().chain(&now) {
        let (a, b) = (find(&before, key), find(&now, key));
        let line = format!("{key}: {a} -> {b}");
        if a != b && !changed.contains(&line) {
            changed.push(line);
        }
    }
    changed
}

/// Removes `name`'s pending stream when `scenario` (which now matches the
/// fixture) is what it was made from: a stream left by `verify FILE.toml`
/// of another scenario stays for `bless --accept`.
///
/// # Errors
/// When it exists and cannot be removed.
pub fn drop_pending(fixtures: &Path, name: &str, scenario: &Scenario) -> Result<()> {
    let folder = dir(fixtures, name);
    let pending_scenario = folder.join(PENDING_SCENARIO_FILE);
    let made_from = if pending_scenario.is_file() {
        scenario_file(&pending_scenario)?
    } else {
        self::scenario(fixtures, name)?
    };
    if !same_scenario(&made_from, scenario) {
        return Ok(());
    }
    remove_if_there(&folder.join(PENDING_FILE))?;
    remove_if_there(&pending_scenario)?;
    crate::report::clear(&folder.join(crate::report::REPORT_DIR))
}

/// Removes `name`'s pending stream, the scenario it was made from and its
/// pictures (`review`'s reject).
///
/// # Errors
/// When one exists and cannot be removed.
pub fn reject_pending(fixtures: &Path, name: &str) -> Result<()> {
    let folder = dir(fixtures, name);
    remove_if_there(&folder.join(PENDING_FILE))?;
    remove_if_there(&folder.join(PENDING_SCENARIO_FILE))?;
    crate::report::clear(&folder.join(crate::report::REPORT_DIR))
}

fn remove_if_there(path: &Path) -> Result<()> {
    match fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("cannot remove {}", path.display()))
        }
        _ => Ok(()),
    }
}

/// The scenario `name`'s pending stream was made from: the one `verify`
/// left beside it, else the fixture's own.
///
/// # Errors
/// Either file is unreadable or invalid.
pub fn pending_scenario(fixtures: &Path, name: &str) -> Result<Scenario> {
    let path = dir(fixtures, name).join(PENDING_SCENARIO_FILE);
    if path.is_file() {
        return scenario_file(&path);
    }
    scenario(fixtures, name)
}

/// The fixtures with a pending stream, sorted.
///
/// # Errors
/// When the folder cannot be read.
pub fn pending_names(fixtures: &Path) -> Result<Vec<String>> {
    Ok(names(fixtures)?
        .into_iter()
        .filter(|n| dir(fixtures, n).join(PENDING_FILE).is_file())
        .collect())
}

/// `name`'s pending stream as a run, checked: every frame whole, and its
/// header naming `name`.
///
/// # Errors
/// No pending stream, or one that is corrupt or of another preset.
pub fn read_pending(fixtures: &Path, name: &str) -> Result<Run> {
    let path = dir(fixtures, name).join(PENDING_FILE);
    // verify's runs are capped at the default stream cap.
    let stream = read_at_most(
        &path,
        u64::from(crate::exec::DEFAULT_MAX_STREAM_MB) << 20,
        "the default --max-stream-mb",
    )
    .with_context(|| {
        format!(
            "cannot read {} (`morphogen verify` writes it on a mismatch)",
            path.display()
        )
    })?;
    let mut frames = 0u32;
    for (i, d) in Decoder::new(&stream).enumerate() {
        match &d.result {
            Err(e) => bail!("{}: byte {}: {e}", path.display(), d.offset),
            Ok(Record::Header(h)) if i == 0 && h.preset.as_str() != name => bail!(
                "{} is a stream of '{}', not of '{name}'",
                path.display(),
                h.preset.as_str()
            ),
            Ok(_) => frames += 1,
        }
    }
    Ok(Run {
        digest: morphogen::stream::StreamDigest::of(&stream),
        frames,
        stream,
    })
}

/// The folder of `name`'s fixture. Names are checked scenario names (no
/// `/`, no leading `.`), so this never leaves `fixtures`.
#[must_use]
pub fn dir(fixtures: &Path, name: &str) -> PathBuf {
    fixtures.join(name)
}

/// Reads `name`'s fixture and checks it against its own summary (size and
/// digest), so that a corrupt fixture is never taken for a regression.
///
/// # Errors
/// As [`read`] and [`Unchecked::checked`].
pub fn load(fixtures: &Path, name: &str) -> Result<Fixture> {
    read(fixtures, name)?.checked(None)
}

/// A fixture read from disk, its stream not yet checked against its
/// summary ([`Unchecked::checked`]).
#[derive(Debug)]
pub struct Unchecked {
    fixture: Fixture,
    name: String,
    stream_path: PathBuf,
}

impl Unchecked {
    /// Its summary, as read.
    #[must_use]
    pub fn summary(&self) -> &Summary {
        &self.fixture.summary
    }

    /// Its stream bytes, as read.
    #[must_use]
    pub fn stream(&self) -> &[u8] {
        &self.fixture.stream
    }

    /// The fixture, once its stream has the size and digest its summary
    /// states and a header that names it. `same` is the digest of a stream
    /// known to hold the same bytes (a run that matched it byte for byte),
    /// which spares computing it again.
    ///
    /// # Errors
    /// A stream that does not match its summary, or a header of another
    /// preset ("fixture corrupt"), naming the file.
    pub fn checked(self, same: Option<u64>) -> Result<Fixture> {
        let Unchecked {
            fixture,
            name,
            stream_path,
        } = self;
        let (summary, stream) = (&fixture.summary, &fixture.stream);
        let digest = same.unwrap_or_else(|| morphogen::stream::StreamDigest::of(stream));
        let digest = format!("{digest:016x}");
        if stream.len() as u64 != summary.bytes || digest != summary.stream_digest {
            bail!(
                "fixture corrupt: {} has {} bytes with digest {digest}, its summary says {} bytes with digest {} (re-bless it if the summary is right about nothing else)",
                stream_path.display(),
                stream.len(),
                summary.bytes,
                summary.stream_digest
            );
        }
        // A header that reads names this fixture (one that does not read is a
        // difference for `verify` to name).
        if let Some(Ok(Record::Header(h))) = Decoder::new(stream).next().map(|d| d.result)
            && h.preset.as_str() != name
        {
            bail!(
                "fixture corrupt: {} is a stream of '{}', but lives in the folder of '{name}'",
                stream_path.display(),
                h.preset.as_str().escape_debug()
            );
        }
        Ok(fixture)
    }
}

/// Reads `name`'s fixture: its summary, and no more of its stream than the
/// summary says it holds.
///
/// # Errors
/// A name that is not a scenario name, a missing or unreadable file, or a
/// summary that is not valid TOML of the expected shape or lives in
/// another preset's folder ("fixture corrupt"); each names the file.
pub fn read(fixtures: &Path, name: &str) -> Result<Unchecked> {
    morphogen_scenario::check::name(name).map_err(|e| {
        anyhow::anyhow!(
            "'{}' is not a fixture name: {}",
            name.escape_debug(),
            e.message
        )
    })?;
    let dir = dir(fixtures, name);
    if !dir.is_dir() {
        bail!(
            "no fixture for '{name}' at {} (create it with `morphogen bless {name}`)",
            dir.display()
        );
    }
    let summary_path = dir.join(SUMMARY_FILE);
    let text = read_at_most(&summary_path, MAX_SUMMARY_BYTES, "MAX_SUMMARY_BYTES")
        .and_then(|bytes| String::from_utf8(bytes).map_err(|_| anyhow::anyhow!("not UTF-8 text")))
        .with_context(|| format!("cannot read {}", summary_path.display()))?;
    let summary: Summary = toml::from_str(&text).with_context(|| {
        format!(
            "fixture corrupt: {} is not a valid fixture summary",
            summary_path.display()
        )
    })?;
    if summary.preset != name {
        bail!(
            "fixture corrupt: {} names '{}', but lives in the folder of '{name}'",
            summary_path.display(),
            summary.preset
        );
    }
    // Never more than the summary says it holds.
    let stream_path = dir.join(STREAM_FILE);
    let stream = read_at_most(&stream_path, summary.bytes, "the size its summary states")
        .with_context(|| format!("cannot read {}", stream_path.display()))?;
    Ok(Unchecked {
        fixture: Fixture { summary, stream },
        name: name.to_string(),
        stream_path,
    })
}

/// The scenario a fixture was made from: its `scenario.toml`, or else the
/// built-in preset of its name. A built-in preset's fixture has no
/// `scenario.toml`, and a `scenario.toml` names its own folder's fixture.
///
/// # Errors
/// Neither exists, the scenario file is invalid, or either rule is broken.
pub fn scenario(fixtures: &Path, name: &str) -> Result<Scenario> {
    let path = dir(fixtures, name).join(SCENARIO_FILE);
    if path.is_file() {
        if morphogen_scenario::builtin(name).is_some() {
            bail!(
                "fixture corrupt: {} replaces the built-in preset '{name}' (a built-in preset's fixture has no {SCENARIO_FILE}; remove it, or give the scenario another name)",
                path.display()
            );
        }
        let scenario = scenario_file(&path)?;
        if scenario.name() != name {
            bail!(
                "fixture corrupt: {} names '{}', but lives in the folder of '{name}'",
                path.display(),
                scenario.name()
            );
        }
        return Ok(scenario);
    }
    morphogen_scenario::builtin(name).ok_or_else(|| {
        anyhow::anyhow!("fixture '{name}' has no {SCENARIO_FILE} and is not a built-in preset")
    })
}

fn scenario_file(path: &Path) -> Result<Scenario> {
    let text = morphogen_scenario::read_limited(path)
        .and_then(morphogen_scenario::utf8)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
    Ok(Scenario::from_text(&path.display().to_string(), &text)?)
}

/// The largest `summary.toml` read (one is about 500 bytes).
const MAX_SUMMARY_BYTES: u64 = 1 << 16;

/// At most `limit` bytes of the regular file at `path`.
fn read_at_most(path: &Path, limit: u64, limit_name: &str) -> Result<Vec<u8>> {
    morphogen_scenario::read_at_most(path, limit, limit_name).map_err(|e| anyhow::anyhow!(e))
}

/// The names of every fixture folder in `fixtures` (every folder whose
/// name does not start with a dot: one without a summary is a fixture
/// that cannot be read, not no fixture), sorted.
///
/// # Errors
/// When the folder cannot be read, or holds a folder whose name is not
/// UTF-8.
pub fn names(fixtures: &Path) -> Result<Vec<String>> {
    let mut names = Vec::new();
    for entry in fs::read_dir(fixtures)
        .with_context(|| format!("cannot read the fixtures folder {}", fixtures.display()))?
    {
        let entry = entry
            .with_context(|| format!("cannot read the fixtures folder {}", fixtures.display()))?;
        if !entry.path().is_dir() {
            continue;
        }
        let name = entry.file_name().into_string().map_err(|n| {
            anyhow::anyhow!(
                "{}: a folder whose name is not UTF-8 cannot be a fixture",
                fixtures.join(n).display()
            )
        })?;
        if !name.starts_with('.') {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// The summary of a run of `scenario`.
#[must_use]
pub fn summarise(scenario: &Scenario, seed: u64, run: &Run) -> Summary {
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
        preset: scenario.name().to_string(),
        seed,
        description: scenario.summary().to_string(),
        format_version: version,
        params_digest: format!("{params:016x}"),
        stream_digest: format!("{:016x}", run.digest),
        bytes: run.stream.len() as u64,
        frames: run.frames,
        blessed_by: Some(crate::provenance::maker()),
        records,
    }
}

/// Writes `scenario`'s fixture from `run`, the folder as a whole (a
/// pending stream goes with the old one); a scenario that is not a
/// built-in preset goes in as `scenario.toml`, under a name that is not a
/// built-in preset's.
///
/// # Errors
/// A scenario other than the built-in preset of its name, or the folder
/// cannot be created or a file cannot be written; nothing is left
/// half-written.
pub fn bless(
    fixtures: &Path,
    scenario: &Scenario,
    summary: &Summary,
    run: &Run,
) -> Result<PathBuf> {
    if !scenario.is_builtin() && morphogen_scenario::builtin(scenario.name()).is_some() {
        bail!(
            "{} is not the built-in preset '{}' but has its name: its fixture would take the built-in's place, which then goes unguarded (give it a name of its own: name = \"my-{}\" in the file, or --set name=my-{})",
            scenario.origin(),
            scenario.name(),
            scenario.name(),
            scenario.name()
        );
    }
    let dir = dir(fixtures, &summary.preset);
    fs::create_dir_all(fixtures)
        .with_context(|| format!("cannot create {}", fixtures.display()))?;
    clean_leftovers(fixtures);
    let text = toml::to_string(summary).context("cannot render the summary")?;
    // The whole fixture is written into a hidden folder beside it, then
    // swapped in: a reader sees the old fixture or the new one, never a
    // mix. Hidden folders are never read as fixtures (names cannot start
    // with a dot) and the next bless removes any a kill left behind.
    let staging = tempfile::Builder::new()
        .prefix(STAGING_PREFIX)
        .tempdir_in(fixtures)
        .with_context(|| format!("cannot write in {}", fixtures.display()))?;
    if !scenario.is_builtin() {
        write_atomic(
            &staging.path().join(SCENARIO_FILE),
            scenario.self_contained().as_bytes(),
        )?;
    }
    write_atomic(&staging.path().join(STREAM_FILE), &run.stream)?;
    write_atomic(&staging.path().join(SUMMARY_FILE), text.as_bytes())?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        fs::set_permissions(staging.path(), fs::Permissions::from_mode(0o755))
            .with_context(|| format!("cannot write in {}", fixtures.display()))?;
    }
    let staged = staging.keep();
    if dir.exists() {
        let old = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(fixtures)
            .with_context(|| format!("cannot write in {}", fixtures.display()))?
            .keep();
        fs::rename(&dir, old.join("fixture"))
            .with_context(|| format!("cannot replace {}", dir.display()))?;
        fs::rename(&staged, &dir).with_context(|| format!("cannot replace {}", dir.display()))?;
        let _ = fs::remove_dir_all(&old);
    } else {
        fs::rename(&staged, &dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    Ok(dir)
}

/// The prefix of the hidden folders `bless` stages fixtures in.
const STAGING_PREFIX: &str = ".morphogen-bless-";

/// Removes staging folders that an interrupted `bless` left behind (those
/// untouched for a minute: a `bless` running beside this one keeps its own).
fn clean_leftovers(fixtures: &Path) {
    let Ok(entries) = fs::read_dir(fixtures) else {
        return;
    };
    let stale = |e: &fs::DirEntry| {
        e.metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age.as_secs() > 60)
    };
    for e in entries.flatten() {
        if e.file_name().to_string_lossy().starts_with(STAGING_PREFIX) && stale(&e) {
            let _ = fs::remove_dir_all(e.path());
        }
    }
}
