//! Finding a scenario (a built-in preset by name, or a scenario file) and
//! running it into an in-memory stream ([`run`], for fixtures) or straight
//! into its stream file and `records.jsonl` ([`run_to_file`], for
//! `morphogen run`, whose other files are then drawn in passes over the
//! stream file), with a progress bar on
//! runs longer than a second. The presets are the scenario files of `scenarios/`,
//! embedded by [`morphogen_scenario`].

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use indicatif::{HumanCount, HumanDuration, ProgressBar, ProgressDrawTarget, ProgressStyle};
use morphogen::embedded_io::{ErrorKind, ErrorType, Write};
use morphogen::preset::{Model, Preset};
use morphogen::sim::Progress;
use morphogen::stream::{Encoder, Record, Sink, SinkError};
use morphogen_scenario::Scenario;
use morphogen_scenario::quoted;
use morphogen_stream_text::jsonl::Lines;

use crate::atomic::OutputFile;
use crate::records::StreamFile;

/// The default cap on a run's stream, MiB (`--max-stream-mb`): far above
/// every preset (the largest streams 4 MB), and small enough that a
/// runaway grammar stops in seconds on a laptop.
pub const DEFAULT_MAX_STREAM_MB: u32 = 128;

/// The name of a run's stream file in its output folder.
pub const STREAM_FILE: &str = "stream.bin";

/// The name of a run's records as JSON Lines in its output folder.
pub const JSONL_FILE: &str = "records.jsonl";

/// A growable byte buffer for the host, holding at most `limit` bytes;
/// past it, writes fail.
#[derive(Debug)]
struct Bytes {
    bytes: Vec<u8>,
    limit: u64,
    past_cap: bool,
}

impl ErrorType for Bytes {
    type Error = ErrorKind;
}

impl Write for Bytes {
    fn write(&mut self, bytes: &[u8]) -> Result<usize, ErrorKind> {
        if (self.bytes.len() + bytes.len()) as u64 > self.limit {
            self.past_cap = true;
            return Err(ErrorKind::OutOfMemory);
        }
        self.bytes.extend_from_slice(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> Result<(), ErrorKind> {
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
    let value = morphogen_scenario::mask::set_value(&bytes)
        .map_err(|e| anyhow!("mask {}: {e}", file.display()))?;
    Ok(scenario.clone_with_sets(&[("mosaic.mask".into(), value)])?)
}

/// `scenario` with its skeleton or L-system grammar replaced by the grammar
/// file `file` (read here, then set inline).
///
/// # Errors
/// When `scenario` has no grammar, or the file cannot be read or checked.
pub fn with_grammar(scenario: &Scenario, file: &Path) -> Result<Scenario> {
    let key = match scenario.checked() {
        morphogen_scenario::Checked::LSystem(_) => "lsystem.grammar",
        morphogen_scenario::Checked::Bones { .. } => "bones.grammar",
        _ => anyhow::bail!(
            "--grammar with a preset needs an L-system or a bone preset, and '{}' is neither \
             (or give no preset to run the grammar on its own)",
            scenario.name()
        ),
    };
    let value = read_included(key, &file.display().to_string())?;
    scenario
        .clone_with_sets(&[(key.into(), value)])
        .map_err(|e| anyhow!("{} with --grammar: {}", scenario.name(), e.message))
}

/// Parses `KEY=VALUE`. A file named on the command line (`--set
/// bones.grammar=my.lsys`, any of [`morphogen_scenario::INCLUDES`]) is
/// relative to the current folder, as every path given to a command is,
/// and is read here and set inline; one named in a scenario file is
/// relative to that file.
///
/// # Errors
/// When there is no `=`, or a named file cannot be read.
pub fn parse_set(text: &str) -> Result<(String, String)> {
    let (key, value) = split_set(text)?;
    let value = set_value(&key, &value).map_err(|e| anyhow!("--set {}: {e}", quoted(text)))?;
    Ok((key, value))
}

/// Splits `KEY=VALUE` (trimmed), reading no file.
///
/// # Errors
/// When there is no `=`.
pub fn split_set(text: &str) -> Result<(String, String)> {
    let (key, value) = text.split_once('=').ok_or_else(|| {
        anyhow!(
            "--set {}: give KEY=VALUE (e.g. mosaic.days=20)",
            quoted(text)
        )
    })?;
    Ok((key.trim().to_string(), value.trim().to_string()))
}

/// The value to set for `key`: for a file key (one of
/// [`morphogen_scenario::INCLUDES`]) given a path, the file read from the
/// current folder and inlined; else `value` itself.
///
/// # Errors
/// A named file that cannot be read.
pub fn set_value(key: &str, value: &str) -> Result<String> {
    if morphogen_scenario::INCLUDES.contains(&key) && !value.starts_with('{') {
        return read_included(key, value.trim_matches('"'));
    }
    Ok(value.to_string())
}

/// The inline value of the file at `path` for the include `key`.
fn read_included(key: &str, path: &str) -> Result<String> {
    let bytes = morphogen_scenario::read_limited(Path::new(path))
        .map_err(|e| anyhow!("cannot read {path}: {e}"))?;
    morphogen_scenario::inline_value(key, path, bytes).map_err(|e| anyhow!("{path}: {e}"))
}

/// Runs `scenario` with `seed` into memory; shows a progress bar once the
/// run has taken more than a second and `progress` is set.
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
    let mut encoder = Encoder::new(Bytes {
        bytes: Vec::new(),
        limit: u64::from(max_mb) << 20,
        past_cap: false,
    });
    let ran = scenario.with_preset(|p| run_preset(p, seed, &bar, &mut encoder));
    explain(ran, scenario.name(), max_mb, encoder.writer().past_cap)?;
    bar.finish();
    Ok(Run {
        digest: encoder.digest(),
        frames: encoder.frames(),
        stream: encoder.into_writer().bytes,
    })
}

/// A run written to a stream file as it went.
#[derive(Debug, Clone)]
pub struct RunFile {
    /// The stream file (`stream.bin`), in place once the run ended.
    pub path: PathBuf,
    /// Its size in bytes.
    pub bytes: u64,
    /// CRC-64/XZ of its bytes.
    pub digest: u64,
    /// Frames (= records) written.
    pub frames: u32,
    /// Of those, the `FrameStart` records (a mosaic's days, a horn's
    /// frames), so that the outputs need not read the stream to count them.
    pub frame_starts: usize,
    /// Its records as JSON Lines, when they were written.
    pub jsonl: Option<PathBuf>,
}

/// A stream file being written: buffered into a temporary file beside it
/// (renamed into place by [`FileSink::finish`]), at most `limit` bytes.
#[derive(Debug)]
pub struct FileSink {
    file: OutputFile,
    written: u64,
    limit: u64,
    failure: Option<std::io::Error>,
    past_cap: bool,
}

impl FileSink {
    /// Starts writing `path`, capped at `max_mb` MiB.
    ///
    /// # Errors
    /// When the folder is not writable.
    pub fn create(path: &Path, max_mb: u32) -> Result<FileSink> {
        Ok(FileSink {
            file: OutputFile::create(path)?,
            written: 0,
            limit: u64::from(max_mb) << 20,
            failure: None,
            past_cap: false,
        })
    }

    /// Flushes, syncs and renames the file into place.
    ///
    /// # Errors
    /// When a write, the sync or the rename fails.
    pub fn finish(self) -> Result<()> {
        self.file.finish()
    }
}

impl ErrorType for FileSink {
    type Error = ErrorKind;
}

impl Write for FileSink {
    fn write(&mut self, bytes: &[u8]) -> Result<usize, ErrorKind> {
        let total = self.written + bytes.len() as u64;
        if total > self.limit {
            self.past_cap = true;
            return Err(ErrorKind::OutOfMemory);
        }
        std::io::Write::write_all(&mut self.file, bytes).map_err(|e| {
            let kind = ErrorKind::from(e.kind());
            self.failure = Some(e);
            kind
        })?;
        self.written = total;
        Ok(bytes.len())
    }

    fn flush(&mut self) -> Result<(), ErrorKind> {
        std::io::Write::flush(&mut self.file).map_err(|e| ErrorKind::from(e.kind()))
    }
}

/// Where a run's files go: the stream file, and the JSON Lines file when
/// one is wanted; each written whole or not at all.
#[derive(Debug, Clone, Copy)]
pub struct RunPaths<'a> {
    /// The stream file, e.g. `out/ram-horn/stream.bin`.
    pub stream: &'a Path,
    /// Its records as JSON Lines, written as they come.
    pub jsonl: Option<&'a Path>,
}

/// Runs `scenario` with `seed` straight into its files `paths`, the
/// stream capped at `max_mb` MiB; shows a progress bar once the run has
/// taken more than a second and `progress` is set. Errors name `what`
/// (the scenario, and the user's files it was given).
///
/// # Errors
/// As [`run_limited`], or when a file cannot be written.
pub fn run_to_file(
    scenario: &Scenario,
    what: &str,
    seed: u64,
    progress: bool,
    max_mb: u32,
    paths: RunPaths<'_>,
) -> Result<RunFile> {
    let bar = Bar::new(scenario.name(), progress);
    let run = scenario.with_preset(|p| preset_to_file(p, seed, what, &bar, max_mb, paths))?;
    bar.finish();
    Ok(run)
}

/// Runs `preset` into its files `paths`; errors name `what`.
fn preset_to_file(
    preset: &Preset<'_>,
    seed: u64,
    what: &str,
    bar: &Bar,
    max_mb: u32,
    paths: RunPaths<'_>,
) -> Result<RunFile> {
    let path = paths.stream;
    let mut encoder = Encoder::new(FileSink::create(path, max_mb)?);
    let mut jsonl = None;
    let (ran, frame_starts) = match paths.jsonl {
        Some(jsonl_path) => {
            let mut lines = Lines::new(&mut encoder, OutputFile::create(jsonl_path)?);
            let mut tally = FrameStarts::new(&mut lines);
            let ran = run_preset(preset, seed, bar, &mut tally);
            let frame_starts = tally.count;
            jsonl = Some(
                lines
                    .into_inner()
                    .with_context(|| format!("cannot write {}", jsonl_path.display())),
            );
            (ran, frame_starts)
        }
        None => {
            let mut tally = FrameStarts::new(&mut encoder);
            let ran = run_preset(preset, seed, bar, &mut tally);
            (ran, tally.count)
        }
    };
    if let Some(e) = encoder.writer().failure.take() {
        return Err(anyhow!(e).context(format!("cannot write {}", path.display())));
    }
    let jsonl = jsonl.transpose()?;
    explain(ran, what, max_mb, encoder.writer().past_cap)?;
    let run = RunFile {
        path: path.to_path_buf(),
        bytes: encoder.bytes(),
        digest: encoder.digest(),
        frames: encoder.frames(),
        frame_starts,
        jsonl: paths.jsonl.map(Path::to_path_buf),
    };
    encoder.into_writer().finish()?;
    if let Some(file) = jsonl {
        file.finish()?;
    }
    Ok(run)
}

/// A sink that counts the `FrameStart` records it hands on to `next`.
struct FrameStarts<'a> {
    next: &'a mut (dyn Sink + Send),
    count: usize,
}

impl<'a> FrameStarts<'a> {
    fn new(next: &'a mut (dyn Sink + Send)) -> FrameStarts<'a> {
        FrameStarts { next, count: 0 }
    }
}

impl Sink for FrameStarts<'_> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.count += usize::from(matches!(record, Record::FrameStart { .. }));
        self.next.record(record)
    }
}

/// Runs `preset` into `sink`, on a worker of rayon's pool: a mosaic's
/// relaxation goes parallel a few times a step, and from a thread outside
/// the pool each of those would wake a worker and sleep until it is done
/// (a futex round trip: 16 % of `run croton`'s CPU on one thread).
fn run_preset(
    preset: &Preset<'_>,
    seed: u64,
    bar: &Bar,
    sink: &mut (dyn Sink + Send),
) -> Result<(), morphogen::Error> {
    let mut counted = Counted {
        next: sink,
        records: &bar.records,
    };
    rayon::scope(|_| {
        morphogen_scenario::run::run(preset, seed, &mut counted, &mut |p| bar.report(p))
    })
}

/// A run's error, naming `what` (the scenario or the file); a stream
/// stopped `past_cap` names the cap of `max_mb` MiB and its flag.
fn explain(
    ran: Result<(), morphogen::Error>,
    what: &str,
    max_mb: u32,
    past_cap: bool,
) -> Result<()> {
    ran.map_err(|e| match e {
        morphogen::Error::Sink(SinkError::Write) if past_cap => anyhow!(
            "{what}: the stream passed {max_mb} MiB and was stopped (raise the cap with --max-stream-mb)"
        ),
        e => anyhow!("{what}: {e}"),
    })
}

/// A progress bar on standard error that appears once a run has taken a
/// second (and never when `shown` is false): steps done of all, and the
/// records streamed so far, which move on where steps are few (a whole
/// plant of `run --grammar` is one step).
#[derive(Debug)]
pub struct Bar {
    bar: ProgressBar,
    start: Instant,
    enabled: bool,
    /// Records streamed, counted by the sink [`run_preset`] wraps.
    records: AtomicU64,
    /// When the message is next due, in milliseconds from `start`.
    next_message: AtomicU64,
}

/// How often the bar's message is written again, in milliseconds.
const MESSAGE_EVERY_MS: u64 = 100;

impl Bar {
    /// A hidden bar named `name`.
    #[must_use]
    pub fn new(name: &str, enabled: bool) -> Bar {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{prefix} [{bar:40}] {pos}/{len} steps, {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_prefix(name.to_string());
        Bar {
            bar,
            start: Instant::now(),
            enabled,
            records: AtomicU64::new(0),
            next_message: AtomicU64::new(0),
        }
    }

    /// Records progress `p`; shows the bar after the first second.
    pub fn report(&self, p: Progress) {
        self.bar.set_length(u64::from(p.total));
        self.bar.set_position(u64::from(p.done));
        if !self.enabled {
            return;
        }
        let elapsed = self.start.elapsed();
        let ms = u64::try_from(elapsed.as_millis()).unwrap_or(u64::MAX);
        if ms < 1000 || ms < self.next_message.load(Ordering::Relaxed) {
            return;
        }
        self.next_message
            .store(ms + MESSAGE_EVERY_MS, Ordering::Relaxed);
        self.bar
            .set_message(status(p, self.records.load(Ordering::Relaxed), elapsed));
        if self.bar.is_hidden() {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The bar's message: records streamed, time taken and, once a step is
/// done, the time left at the pace so far.
fn status(p: Progress, records: u64, elapsed: Duration) -> String {
    let mut text = format!(
        "{} records, {}",
        HumanCount(records),
        HumanDuration(elapsed)
    );
    if p.done > 0 && p.done < p.total {
        let left = elapsed.mul_f64(f64::from(p.total - p.done) / f64::from(p.done));
        let _ = write!(text, " (eta {})", HumanDuration(left));
    }
    text
}

/// A sink that counts the records it hands on to `next` into a [`Bar`].
struct Counted<'a> {
    next: &'a mut (dyn Sink + Send),
    records: &'a AtomicU64,
}

impl Sink for Counted<'_> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        // One writer: a plain load and store, no locked add per record.
        let counted = self.records.load(Ordering::Relaxed) + 1;
        self.records.store(counted, Ordering::Relaxed);
        self.next.record(record)
    }
}

/// The preset name in the header of a `run --grammar` stream.
pub const GRAMMAR_PRESET: &str = "grammar";

/// Runs the grammar `text` (read from `file`, named in errors) with
/// `seed` straight into its files `paths`, as the stream of a preset
/// called [`GRAMMAR_PRESET`]: streaming when context-free, otherwise
/// buffered ([`morphogen_scenario::run::HOST_BUFFER_MODULES`] modules a
/// buffer).
///
/// # Errors
/// A located parse error (`file:line:column: …`), a run error, or a file
/// that cannot be written.
pub fn run_grammar(
    file: &Path,
    text: &str,
    seed: u64,
    max_stream_mb: u32,
    paths: RunPaths<'_>,
    progress: bool,
) -> Result<RunFile> {
    drop(
        morphogen_scenario::check::grammar(text, &file.display().to_string(), |_, _| {})
            .map_err(|e| anyhow!(e))?,
    );
    let preset = Preset {
        name: GRAMMAR_PRESET,
        summary: "",
        default_seed: seed,
        model: Model::LSystem(text),
    };
    let bar = Bar::new(GRAMMAR_PRESET, progress);
    let run = preset_to_file(
        &preset,
        seed,
        &file.display().to_string(),
        &bar,
        max_stream_mb,
        paths,
    )?;
    bar.finish();
    Ok(run)
}

/// Writes the rest of a run's files into `dir`, where its stream file
/// (and `records.jsonl`) already are: the files `model` draws in passes
/// over the stream file, with a spinner on standard error once this has
/// taken a second (when `progress`). Returns every path written, the
/// stream file first.
///
/// # Errors
/// When the stream cannot be read back or a file cannot be written.
pub fn write_outputs(
    dir: &Path,
    run: &RunFile,
    progress: bool,
    model: impl FnOnce(&StreamFile, &Path) -> Result<Vec<PathBuf>>,
) -> Result<Vec<PathBuf>> {
    let _spinner = progress.then(|| Spinner::after_a_second(&format!("writing {}", dir.display())));
    let stream = StreamFile::new(&run.path).with_frame_starts(run.frame_starts);
    let mut written = vec![run.path.clone()];
    written.extend(run.jsonl.clone());
    written.extend(model(&stream, dir)?);
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

/// Every `--set KEY=VALUE` of `sets`, parsed ([`parse_set`]).
///
/// # Errors
/// The first that is not `KEY=VALUE`.
pub fn parse_sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    sets.iter().map(|s| parse_set(s)).collect()
}

/// Warns on standard error when `--seed` was given to a scenario whose
/// stream does not depend on it (only its header records the seed).
pub fn warn_unused_seed(scenario: &Scenario, seed: Option<u64>) {
    if seed.is_some() && !scenario.uses_seed() {
        eprintln!(
            "warning: --seed has no effect on {}: its model draws no random numbers (only the stream header records the seed)",
            scenario.name()
        );
    }
}

#[cfg(test)]
mod tests {
    use morphogen::stream::Record;

    use super::*;
    use crate::outputs::plant;

    #[test]
    fn the_bar_counts_records_and_tells_the_time_left_once_a_step_is_done() {
        let at = |done, total| Progress { done, total };
        let s = Duration::from_secs;
        // One step for a whole plant: only the records move.
        assert_eq!(
            status(at(0, 1), 1_234_567, s(3)),
            "1,234,567 records, 3 seconds"
        );
        assert_eq!(
            status(at(1, 4), 9, s(2)),
            "9 records, 2 seconds (eta 6 seconds)"
        );
        assert_eq!(status(at(4, 4), 9, s(2)), "9 records, 2 seconds");
    }

    #[test]
    fn grammar_errors_name_the_file_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stream.bin");
        let e = run_grammar(
            Path::new("my.lsys"),
            "n = 2\naxiom: F\nF -> F(1",
            0,
            128,
            RunPaths {
                stream: &path,
                jsonl: None,
            },
            false,
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "my.lsys:3:9: expected `,` or `)`");
        assert!(!path.exists());
    }

    #[test]
    fn context_sensitive_grammars_run_buffered_and_draw() {
        let text = include_str!("../../grammars/abop-context-1-31a.lsys");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stream.bin");
        let jsonl = dir.path().join(JSONL_FILE);
        let paths = RunPaths {
            stream: &path,
            jsonl: Some(&jsonl),
        };
        let run = run_grammar(Path::new("ctx.lsys"), text, 0, 128, paths, false).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len() as u64, run.bytes);
        let records: Vec<Record> = morphogen::stream::Decoder::new(&bytes)
            .filter_map(|d| d.result.ok())
            .collect();
        assert_eq!(records.len() as u32, run.frames);
        assert_eq!(
            std::fs::read_to_string(&jsonl).unwrap(),
            morphogen_stream_text::jsonl::stream(&bytes)
        );
        let segments = records
            .iter()
            .filter(|r| matches!(r, Record::Segment { .. }))
            .count();
        assert!(segments > 1000, "{segments}");
        let written = plant::write(
            &StreamFile::new(&path),
            dir.path(),
            crate::outputs::Kinds::DEFAULT,
        )
        .unwrap();
        // plant.png, plant.obj, plant.mtl, model.glb, segments.csv.
        assert_eq!(written.len(), 5, "{written:?}");
        let obj = std::fs::read_to_string(dir.path().join("plant.obj")).unwrap();
        assert_eq!(
            obj.lines().filter(|l| l.starts_with("v ")).count(),
            8 * segments
        );
        let csv = std::fs::read_to_string(dir.path().join("segments.csv")).unwrap();
        assert_eq!(csv.lines().count(), segments + 1);
        // The same files from the records in memory.
        let again = tempfile::tempdir().unwrap();
        plant::write(&records, again.path(), crate::outputs::Kinds::DEFAULT).unwrap();
        for name in ["plant.png", "plant.obj", "model.glb", "segments.csv"] {
            assert_eq!(
                std::fs::read(again.path().join(name)).unwrap(),
                std::fs::read(dir.path().join(name)).unwrap(),
                "{name}"
            );
        }
    }

    #[test]
    fn a_run_counts_the_frame_starts_its_stream_holds() {
        use crate::records::Records;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stream.bin");
        let jsonl = dir.path().join(JSONL_FILE);
        for (preset, lines) in [("croton-mcu", true), ("ram-horn", false)] {
            let paths = RunPaths {
                stream: &path,
                jsonl: lines.then_some(jsonl.as_path()),
            };
            let scenario = find(preset, &[]).unwrap();
            let run = run_to_file(
                &scenario,
                scenario.name(),
                scenario.seed(),
                false,
                64,
                paths,
            )
            .unwrap();
            let read = StreamFile::new(&path).frame_starts().unwrap();
            assert!(read > 1, "{preset}: {read}");
            assert_eq!(run.frame_starts, read, "{preset}");
            let known = StreamFile::new(&path).with_frame_starts(run.frame_starts);
            assert_eq!(known.frame_starts().unwrap(), read, "{preset}");
        }
    }

    #[test]
    fn a_stream_file_past_the_cap_is_stopped_and_left_unwritten() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stream.bin");
        let text = "n = 12\naxiom: F\nF -> F[+F]F[-F]F\n";
        let paths = RunPaths {
            stream: &path,
            jsonl: Some(&dir.path().join(JSONL_FILE)),
        };
        let e = run_grammar(Path::new("big.lsys"), text, 0, 1, paths, false).unwrap_err();
        assert_eq!(
            e.to_string(),
            "big.lsys: the stream passed 1 MiB and was stopped (raise the cap with --max-stream-mb)"
        );
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
