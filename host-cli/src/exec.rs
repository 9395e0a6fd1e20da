//! Finding a scenario (a built-in preset by name, or a scenario file) and
//! running it into an in-memory stream, with a progress bar on runs longer
//! than a second. The presets are the scenario files of `scenarios/`,
//! embedded by [`morphogen_scenario`].

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use morphogen::preset::{Model, Preset};
use morphogen::sim::Progress;
use morphogen::stream::{ByteSink, Decoder, Encoder, Record, SinkError};
use morphogen_scenario::Scenario;

use crate::atomic::OutputFile;

/// The default cap on a run's stream, MiB (`--max-stream-mb`): far above
/// every preset (the largest streams 4 MB), and small enough that a
/// runaway grammar stops in seconds on a laptop.
pub const DEFAULT_MAX_STREAM_MB: u32 = 128;

/// A growable byte sink for the host, holding at most `limit` bytes.
#[derive(Debug)]
pub struct Bytes(pub Vec<u8>, pub u64);

impl Default for Bytes {
    fn default() -> Bytes {
        Bytes(Vec::new(), u64::from(DEFAULT_MAX_STREAM_MB) << 20)
    }
}

impl ByteSink for Bytes {
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), SinkError> {
        if (self.0.len() + bytes.len()) as u64 > self.1 {
            return Err(SinkError::Full {
                capacity: u32::try_from(self.1 >> 20).unwrap_or(u32::MAX),
            });
        }
        self.0.extend_from_slice(bytes);
        Ok(())
    }
}

/// A finished run: the encoded stream and its digest.
#[derive(Debug)]
pub struct Run {
    /// Every byte, exactly as `stream.bin` holds it.
    pub stream: Vec<u8>,
    /// CRC-64/XZ of `stream`.
    pub digest: u64,
    /// Frames (= records) written.
    pub frames: u32,
}

/// Whether `target` names a scenario file rather than a preset: it ends in
/// `.toml` or contains a path separator.
#[must_use]
pub fn is_file(target: &str) -> bool {
    target.ends_with(".toml") || target.contains('/') || target.contains('\\')
}

/// The scenario `target` names: a scenario file (`*.toml`, or any path),
/// or a built-in preset; with `sets` (dotted `key=value`) applied.
///
/// # Errors
/// An unknown preset (with a did-you-mean), or the scenario's first bad
/// value, located in its file.
pub fn find(target: &str, sets: &[(String, String)]) -> Result<Scenario> {
    if is_file(target) {
        return Ok(Scenario::load(Path::new(target), sets)?);
    }
    let builtin = morphogen_scenario::builtin(target).ok_or_else(|| {
        let hint = morphogen_scenario::closest_builtin(target)
            .map(|n| format!("did you mean '{n}'? "))
            .unwrap_or_default();
        anyhow!(
            "unknown preset '{target}' ({hint}see `morphogen list`; a scenario file ends in .toml)"
        )
    })?;
    if sets.is_empty() {
        Ok(builtin)
    } else {
        Ok(builtin.clone_with_sets(sets)?)
    }
}

/// `scenario` with its mosaic mask replaced by the mask file `file` (a PBM
/// or a PNG, read and checked first, then set inline).
///
/// # Errors
/// When `scenario` is not a mosaic, or the file is not a usable mask.
pub fn with_mask(scenario: &Scenario, file: &Path) -> Result<Scenario> {
    if !matches!(
        scenario.checked(),
        morphogen_scenario::Checked::Mosaic { .. }
    ) {
        let mosaics: Vec<String> = morphogen_scenario::builtins()
            .iter()
            .filter(|s| matches!(s.checked(), morphogen_scenario::Checked::Mosaic { .. }))
            .map(|s| s.name().to_string())
            .collect();
        anyhow::bail!(
            "--mask needs a mosaic preset, and '{}' is not one (mosaics: {})",
            scenario.name(),
            mosaics.join(", ")
        );
    }
    let bytes = morphogen_scenario::read_limited(file)
        .map_err(|e| anyhow!("cannot read mask {}: {e}", file.display()))?;
    let (width, height, bits) = morphogen_scenario::mask::read(&bytes)
        .map_err(|e| anyhow!("mask {}: {e}", file.display()))?;
    let pbm = morphogen_scenario::mask::to_pbm(&morphogen::mosaic::Mask {
        width,
        height,
        bits: &bits,
    });
    let mut inline = toml_edit::InlineTable::new();
    inline.insert("text", pbm.into());
    Ok(scenario.clone_with_sets(&[("mosaic.mask".into(), inline.to_string())])?)
}

/// Parses `KEY=VALUE`.
///
/// # Errors
/// When there is no `=`.
pub fn parse_set(text: &str) -> Result<(String, String)> {
    let (key, value) = text
        .split_once('=')
        .ok_or_else(|| anyhow!("--set {text}: give KEY=VALUE (e.g. mosaic.days=20)"))?;
    Ok((key.trim().to_string(), value.trim().to_string()))
}

/// Runs `scenario` with `seed`; shows a progress bar once the run has
/// taken more than a second and `progress` is set.
///
/// # Errors
/// The core's error, with the scenario named.
pub fn run(scenario: &Scenario, seed: u64, progress: bool) -> Result<Run> {
    run_limited(scenario, seed, progress, DEFAULT_MAX_STREAM_MB)
}

/// [`run`] with the stream capped at `max_mb` MiB.
///
/// # Errors
/// The core's error, with the scenario named; a stream past the cap names
/// the cap and the flag that raises it.
pub fn run_limited(scenario: &Scenario, seed: u64, progress: bool, max_mb: u32) -> Result<Run> {
    let bar = Bar::new(scenario.name(), progress);
    let run = scenario.with_preset(|p| run_preset(p, seed, scenario.name(), &bar, max_mb))?;
    bar.finish();
    Ok(run)
}

/// Runs `preset` into a stream of at most `max_mb` MiB; errors name
/// `what` (the scenario or the file).
fn run_preset(preset: &Preset<'_>, seed: u64, what: &str, bar: &Bar, max_mb: u32) -> Result<Run> {
    let mut encoder = Encoder::new(Bytes(Vec::new(), u64::from(max_mb) << 20));
    morphogen_scenario::run::run(preset, seed, &mut encoder, &mut |p| bar.report(p)).map_err(
        |e| match e {
            morphogen::Error::Sink(SinkError::Full { .. }) => anyhow!(
                "{what}: the stream passed {max_mb} MiB and was stopped (raise the cap with --max-stream-mb)"
            ),
            e => anyhow!("{what}: {e}"),
        },
    )?;
    let digest = encoder.digest();
    let frames = encoder.frames();
    Ok(Run {
        stream: encoder.into_writer().0,
        digest,
        frames,
    })
}

/// A progress bar on standard error that appears once a run has taken a
/// second (and never when `shown` is false).
#[derive(Debug)]
pub struct Bar {
    bar: ProgressBar,
    start: Instant,
    enabled: bool,
}

impl Bar {
    /// A hidden bar named `name`.
    #[must_use]
    pub fn new(name: &str, enabled: bool) -> Bar {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(
                "{prefix} [{bar:40}] {pos}/{len} steps, {elapsed} (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        bar.set_prefix(name.to_string());
        Bar {
            bar,
            start: Instant::now(),
            enabled,
        }
    }

    /// Records progress `p`; shows the bar after the first second.
    pub fn report(&self, p: Progress) {
        self.bar.set_length(u64::from(p.total));
        self.bar.set_position(u64::from(p.done));
        if self.enabled && self.bar.is_hidden() && self.start.elapsed() > Duration::from_secs(1) {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The preset name in the header of a `run --grammar` stream.
pub const GRAMMAR_PRESET: &str = "grammar";

/// Runs the grammar `text` (read from `file`, named in errors) with
/// `seed`, as the stream of a preset called [`GRAMMAR_PRESET`]: streaming
/// when context-free, otherwise buffered
/// ([`morphogen_scenario::run::HOST_BUFFER_MODULES`] modules a buffer).
///
/// # Errors
/// A located parse error (`file:line:column: …`) or a run error.
pub fn run_grammar(file: &Path, text: &str, seed: u64, max_stream_mb: u32) -> Result<Run> {
    let mut probe = Box::new(morphogen::lsys::Grammar::new());
    probe
        .parse(text)
        .map_err(|p| anyhow!("{}:{}:{}: {}", file.display(), p.line, p.column, p.kind))?;
    let preset = Preset {
        name: GRAMMAR_PRESET,
        summary: "",
        default_seed: seed,
        model: Model::LSystem(text),
    };
    let bar = Bar::new(GRAMMAR_PRESET, true);
    let run = run_preset(
        &preset,
        seed,
        &file.display().to_string(),
        &bar,
        max_stream_mb,
    )?;
    bar.finish();
    Ok(run)
}

/// Writes a finished run into `dir` (created if missing): `stream.bin`,
/// `records.jsonl` (streamed as the frames decode), then the files `model`
/// draws from the decoded records, with a spinner on standard error once
/// this has taken a second. Returns every path written, in order.
///
/// # Errors
/// When the folder cannot be created or a file cannot be written.
pub fn write_outputs(
    dir: &Path,
    run: &Run,
    model: impl FnOnce(&[Record], &Path) -> Result<Vec<PathBuf>>,
) -> Result<Vec<PathBuf>> {
    fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    let _spinner = Spinner::after_a_second(&format!("writing {}", dir.display()));
    let stream_path = dir.join("stream.bin");
    crate::atomic::write_atomic(&stream_path, &run.stream)?;
    let jsonl_path = dir.join("records.jsonl");
    OutputFile::write_with(&jsonl_path, |file| {
        crate::jsonl::write_stream(&run.stream, file)
    })?;
    let records: Vec<Record> = Decoder::new(&run.stream)
        .filter_map(|d| d.result.ok())
        .collect();
    let mut written = vec![stream_path, jsonl_path];
    written.extend(model(&records, dir)?);
    Ok(written)
}

/// A spinner on standard error for work of unknown length: it appears
/// once the work has taken a second and is cleared when dropped.
#[derive(Debug)]
struct Spinner {
    bar: ProgressBar,
}

impl Spinner {
    fn after_a_second(message: &str) -> Spinner {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(message.to_string());
        let shown = bar.clone();
        // A detached timer: after a second it shows the bar, which then
        // ticks on its own; a finished bar is left hidden.
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_secs(1));
            if !shown.is_finished() {
                shown.set_draw_target(ProgressDrawTarget::stderr());
                shown.enable_steady_tick(Duration::from_millis(120));
            }
        });
        Spinner { bar }
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outputs::plant;

    #[test]
    fn grammar_errors_name_the_file_line_and_column() {
        let e = run_grammar(Path::new("my.lsys"), "n = 2\naxiom: F\nF -> F(1", 0, 128).unwrap_err();
        assert_eq!(e.to_string(), "my.lsys:3:9: expected `,` or `)`");
    }

    #[test]
    fn context_sensitive_grammars_run_buffered_and_draw() {
        let text = include_str!("../../grammars/abop-context-1-31a.lsys");
        let run = run_grammar(Path::new("ctx.lsys"), text, 0, 128).unwrap();
        let records: Vec<Record> = morphogen::stream::Decoder::new(&run.stream)
            .filter_map(|d| d.result.ok())
            .collect();
        let segments = records
            .iter()
            .filter(|r| matches!(r, Record::Segment { .. }))
            .count();
        assert!(segments > 1000, "{segments}");
        let dir = tempfile::tempdir().unwrap();
        let written = plant::write(&records, dir.path()).unwrap();
        assert_eq!(written.len(), 3);
        let obj = std::fs::read_to_string(dir.path().join("plant.obj")).unwrap();
        assert_eq!(
            obj.lines().filter(|l| l.starts_with("v ")).count(),
            8 * segments
        );
        let csv = std::fs::read_to_string(dir.path().join("segments.csv")).unwrap();
        assert_eq!(csv.lines().count(), segments + 1);
    }
}
