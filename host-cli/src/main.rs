//! `morphogen`: run, draw, export and verify Morphogen's simulations.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use morphogen_cli::folder_lock::FolderLock;
use morphogen_cli::outputs::{Kind, Kinds};
use morphogen_cli::stdout::StdoutError;
use morphogen_cli::{
    Outcome, atomic, bless, body_input, capture, exec, fixture, golden, jsonl, listen, outputs,
    provenance, review, say, send, serve, sweep, verify, written,
};
use morphogen_scenario::Scenario;

/// Deterministic growth simulations: horns, bodies, plants, bones and cell
/// mosaics, bit-identical on a workstation and a microcontroller.
///
/// Every run is a scenario: a built-in preset (`morphogen list`, `morphogen
/// show NAME`) or a scenario file of your own (TOML, docs/scenarios.md).
///
/// Exit codes: 0 success, 1 a stream differs from its fixture, 2 bad input
/// or usage.
#[derive(Debug, Parser)]
#[command(name = "morphogen", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the built-in presets, one per line: name, default seed, summary.
    List,
    /// Print a built-in preset's scenario file, self-contained (grammars and
    /// masks inline): the way to start your own (`morphogen show ram-horn >
    /// my-horn.toml`).
    Show {
        /// The preset's name.
        preset: String,
    },
    /// Run a preset or a scenario file and write its stream, its records as
    /// JSON Lines and the model's own files (PNG, OBJ, CSV).
    Run {
        /// A preset's name (see `morphogen list`) or a scenario file
        /// (`*.toml`); may be omitted with --grammar.
        #[arg(required_unless_present = "grammar")]
        target: Option<String>,
        /// Change a parameter: a dotted key of the scenario file and a value
        /// (`--set mosaic.days=20`, `--set horn.modules[0].bend=80`, a
        /// grammar's setting or constant `--set lsystem.delta=30`);
        /// repeatable. A file (`--set bones.grammar=my.lsys`) is relative
        /// to the current folder.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// An L-system grammar file (format: docs/lsystems.md). Alone, it
        /// runs as a plant (plant.png, plant.obj, segments.csv); with an
        /// L-system or bone preset or scenario, it replaces that one's
        /// grammar (a bone preset wraps your skeleton).
        #[arg(long, value_name = "FILE")]
        grammar: Option<PathBuf>,
        /// The seed (default: the scenario's own, the one fixtures use).
        #[arg(long)]
        seed: Option<u64>,
        /// The output folder (default: `out/NAME`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// With a body scenario: grow this OBJ mesh instead of the built-in
        /// body (needs --cylinders; format: docs/body.md).
        #[arg(
            long,
            value_name = "FILE",
            requires = "cylinders",
            conflicts_with = "grammar"
        )]
        mesh: Option<PathBuf>,
        /// The cylinder file for --mesh (docs/body.md).
        #[arg(long, value_name = "FILE", requires = "mesh")]
        cylinders: Option<PathBuf>,
        /// Also write rig-WxH.png: the last frame as a W×H display rig
        /// (LED matrix, OLED) shows it, drawn by the core's rig renderer;
        /// `WxH:grey4` draws the 16 greys of a 4-bit OLED, as the firmware
        /// draws its SSD0323 (rig-WxH-grey4.png). In colour, mosaics and
        /// plants take the colours of their main pictures. Also writes
        /// rig-WxH[-grey4]-preview.png, enlarged as the LEDs or the OLED
        /// look lit.
        #[arg(long, value_name = "WxH[:grey4]")]
        rig: Option<String>,
        /// With a mosaic: where F cells may start instead of the scenario's
        /// mask, a PBM (P1/P4) or PNG stretched over the whole domain; white
        /// allows F (in a PNG: luminance and alpha both ≥ 50 %).
        #[arg(long, value_name = "FILE", conflicts_with_all = ["grammar", "mesh"])]
        mask: Option<PathBuf>,
        /// Stop a run whose stream grows past this many MiB (a runaway
        /// grammar, a huge mosaic).
        #[arg(
            long,
            value_name = "MB",
            default_value_t = exec::DEFAULT_MAX_STREAM_MB,
            value_parser = clap::value_parser!(u32).range(1..)
        )]
        max_stream_mb: u32,
        /// Write only these kinds of file, a comma list of png (pictures
        /// and chart bitmaps), obj (meshes and their .mtl), glb
        /// (model.glb), anim (animation.png), svg (charts), csv (tables),
        /// jsonl (records.jsonl); stream.bin and summary.txt are always
        /// written. Default: all of them.
        #[arg(long, value_name = "KINDS", value_parser = parse_kinds)]
        only: Option<Kinds>,
        /// Print nothing on standard output (no summary, no "wrote"
        /// lines) and show no progress bar; errors still go to standard
        /// error.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Re-run scenarios and compare their streams with the golden fixtures,
    /// or check a device capture with --stream. Every fixture folder is
    /// checked; a mismatch leaves the new stream beside the fixture as
    /// `stream.bin.pending`, and the scenario file it was made from, when
    /// that is not the fixture's own, as `scenario.toml.pending`
    /// (`bless --accept` takes both; under CI only with --pending). Exit 1
    /// on any mismatch or missing fixture, 2 when one cannot be checked.
    Verify {
        /// Presets or scenario files to verify (default: every fixture in
        /// the fixtures folder, built-in or not).
        targets: Vec<String>,
        /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
        /// `fixtures/` in this folder or the nearest parent that has one).
        #[arg(long)]
        fixtures: Option<PathBuf>,
        /// A capture from a device (one or more streams back to back, each
        /// starting with its header) to check instead of re-running.
        #[arg(long, conflicts_with = "targets")]
        stream: Option<PathBuf>,
        /// Threads re-running fixtures side by side, 1 to 256 (default:
        /// all cores).
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
        jobs: Option<u16>,
        /// Also write a JUnit XML report to FILE: a test case per fixture,
        /// a failure for a mismatch or a missing fixture, an error for one
        /// that cannot be checked (what GitLab, Jenkins and GitHub's test
        /// reporters read).
        #[arg(long, value_name = "FILE", conflicts_with = "stream")]
        junit: Option<PathBuf>,
        /// Print a line per fixture (text) or a JSON object per fixture and
        /// one with the counts (json).
        #[arg(long, value_enum, default_value_t, conflicts_with = "stream")]
        format: golden::Format,
        /// Leave a mismatch's new stream beside its fixture even when CI is
        /// set (under CI nothing is written into the fixtures folder
        /// otherwise). With GITHUB_ACTIONS=true each failing fixture is
        /// also an `::error` annotation and the counts a table in the job
        /// summary.
        #[arg(long, conflicts_with = "stream")]
        pending: bool,
        /// Draw each mismatch's pictures into DIR/NAME/ (default: beside
        /// its pending stream, in the fixture's report/; under CI only
        /// with this): the model's pictures of the expected and the actual
        /// stream up to the end of the first frame that differs, in
        /// expected/ and actual/, and their difference in difference/
        /// (changed pixels red), for each picture that is not the same.
        #[arg(long, value_name = "DIR", conflicts_with = "stream")]
        report: Option<PathBuf>,
    },
    /// Write the golden fixtures of presets or scenario files (the only
    /// writer of fixtures). A scenario file's fixture keeps a
    /// self-contained copy of it, so `verify` re-runs it from there.
    Bless {
        /// Presets or scenario files to bless.
        #[arg(required_unless_present_any = ["accept", "all"])]
        targets: Vec<String>,
        /// Take the new streams `verify` left as `stream.bin.pending`,
        /// with their `scenario.toml.pending` where there is one (all of
        /// them, or those of TARGETS).
        #[arg(long, conflicts_with_all = ["all", "sets", "seed"])]
        accept: bool,
        /// Re-bless every fixture in the folder, each from its own scenario
        /// and seed.
        #[arg(long, conflicts_with_all = ["targets", "sets", "seed"])]
        all: bool,
        /// Change a parameter (as `run --set`); repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
        /// `fixtures/` in this folder or the nearest parent that has one,
        /// else a new `fixtures/` here).
        #[arg(long)]
        fixtures: Option<PathBuf>,
        /// The seed (default: the scenario's own).
        #[arg(long)]
        seed: Option<u64>,
    },
    /// Go through the pending streams `verify` left (all, or those of
    /// TARGETS), one fixture at a time: what differs, the changed keys and
    /// the pictures, then accept (bless it), reject (remove it), skip, or
    /// accept all. Asks at a terminal; scripts use `bless --accept`.
    Review {
        /// Presets or scenario files whose pending streams to review.
        targets: Vec<String>,
        /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
        /// `fixtures/` in this folder or the nearest parent that has one).
        #[arg(long)]
        fixtures: Option<PathBuf>,
    },
    /// Run every combination of parameter values (on all cores) and
    /// tabulate the results in DIR/sweep.csv, one folder per run.
    Sweep(sweep::Args),
    /// Decode records live from a serial port, a file or standard input
    /// (SOURCE), check each stream against its fixture as it completes,
    /// and draw it with --rig. Exit 1 on a mismatch or a stream without a
    /// fixture (with --strict, on any bad frame too).
    Listen(listen::Args),
    /// Send a scenario (a growth curve, a horn, an L-system or a bone) to a
    /// device
    /// over a serial port, or into a file: the firmware runs it and
    /// streams and draws the result, without being reflashed.
    Send(send::Args),
    /// Serve the web page (built by `bash scripts/web-build.sh` into
    /// web/dist) on http://127.0.0.1:8000/: every preset and your scenario
    /// files run in the browser, bit-exact (docs/web.md).
    Serve(serve::Args),
    /// Decode a stream file into JSON Lines (the same as `records.jsonl`).
    Decode {
        /// The stream file.
        file: PathBuf,
        /// Write to this file instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    // The version with the commit of a checkout's build.
    let matches = Cli::command().version(provenance::version()).get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Err(e) = atomic::remove_unfinished_when_stopped() {
        eprintln!("error: {e:#}");
        return ExitCode::from(2);
    }
    match dispatch(cli.command) {
        Ok(Outcome::Ok) => ExitCode::SUCCESS,
        Ok(Outcome::Mismatch) => ExitCode::from(1),
        Err(e) => match e.downcast_ref::<StdoutError>() {
            Some(closed) if closed.is_closed_pipe() => ExitCode::SUCCESS,
            _ => {
                eprintln!("error: {}", clamped(&format!("{e:#}")));
                ExitCode::from(2)
            }
        },
    }
}

/// The longest line of an error printed whole.
const ERROR_LINE_CHARS: usize = 500;

/// `message` with every line past [`ERROR_LINE_CHARS`] cut: messages
/// quote at most `QUOTED_CHARS` of an input, and this is the bound where
/// one does not.
fn clamped(message: &str) -> String {
    message
        .lines()
        .map(|line| match line.char_indices().nth(ERROR_LINE_CHARS) {
            None => line.to_string(),
            Some((end, _)) => format!(
                "{}… ({} more characters)",
                &line[..end],
                line[end..].chars().count()
            ),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn parse_kinds(list: &str) -> Result<Kinds> {
    Kinds::parse(list)
}

/// What `run` writes and says: the kinds of file, and whether it is quiet.
#[derive(Debug, Clone, Copy)]
struct Writing {
    kinds: Kinds,
    quiet: bool,
}

fn sets(sets: &[String]) -> Result<Vec<(String, String)>> {
    sets.iter().map(|s| exec::parse_set(s)).collect()
}

/// Why the mosaic `m` is host only (it does not fit the MCU's stores).
fn mcu_note(m: &morphogen::mosaic::Params<'_>) -> String {
    use morphogen::mosaic::surface::{McuMeshStore, McuSurfaceStore};
    let peak = morphogen::mosaic::expected_peak_cells(m);
    let capacity = match m.surface {
        Some(_) => McuSurfaceStore::CAPACITY,
        None => morphogen::mosaic::McuStore::CAPACITY,
    };
    let surface = m.surface.map(|s| s.counts());
    if peak > capacity as u64 {
        format!(
            "  (host only: up to ~{peak} cells at the fastest type's doubling, an MCU store holds {capacity})"
        )
    } else if m.momentum != morphogen::fx::Fx::ZERO {
        "  (host only: momentum needs a velocity per cell, an MCU store keeps none)".to_owned()
    } else if m.anisotropy.is_some() && surface.is_some() {
        "  (host only: the MCU's mesh store keeps no anisotropy field)".to_owned()
    } else if let Some((vertices, faces)) = surface {
        format!(
            "  (host only: a mesh of {vertices} vertices and {faces} triangles, the MCU's mesh store holds {} and {})",
            McuMeshStore::VERTICES,
            McuMeshStore::FACES
        )
    } else {
        String::new()
    }
}

fn dispatch(command: Command) -> Result<Outcome> {
    match command {
        Command::List => {
            let all = morphogen_scenario::builtins();
            let width = all.iter().map(|s| s.name().len()).max().unwrap_or(0);
            for s in &all {
                let note = s.with_preset(|p| match p.model {
                    morphogen::preset::Model::Mosaic(m) if !p.model.fits_mcu() => mcu_note(m),
                    morphogen::preset::Model::Bones(_) if !p.model.fits_mcu() => {
                        "  (host only: its skeleton grammar needs buffered derivation; the MCU streams)"
                            .to_owned()
                    }
                    _ => match morphogen_scenario::firmware::on_own_mesh(s) {
                        Some(bytes) => format!(
                            "  (on the MCU only when named by MORPHOGEN_SCENARIOS: its own mesh takes {} KB of flash)",
                            bytes.div_ceil(1000)
                        ),
                        None => String::new(),
                    },
                });
                say!(
                    "{:width$}  seed {:<4} {}{note}",
                    s.name(),
                    s.seed(),
                    s.summary()
                )?;
            }
            Ok(Outcome::Ok)
        }
        Command::Show { preset } => {
            let scenario = exec::find(&preset, &[])?;
            morphogen_cli::stdout::text(&scenario.self_contained())?;
            Ok(Outcome::Ok)
        }
        Command::Run {
            target,
            sets: set_args,
            grammar: Some(file),
            seed,
            out,
            max_stream_mb,
            only,
            quiet,
            ..
        } if target.as_deref().is_none_or(|t| t == "custom") => {
            if let Some(set) = set_args.first() {
                bail!(
                    "--set {set}: a grammar run on its own has no scenario to change (name a preset or a scenario file, whose grammar --grammar then replaces)"
                );
            }
            run_grammar(
                &file,
                seed,
                out,
                max_stream_mb,
                Writing {
                    kinds: only.unwrap_or(Kinds::ALL),
                    quiet,
                },
            )
        }
        Command::Run {
            target: Some(target),
            sets: set_args,
            grammar,
            seed,
            out,
            mesh,
            cylinders,
            rig,
            mask,
            max_stream_mb,
            only,
            quiet,
        } => {
            let writing = Writing {
                kinds: only.unwrap_or(Kinds::ALL),
                quiet,
            };
            let scenario = exec::find(&target, &sets(&set_args)?)?;
            let scenario = match &mask {
                Some(file) => exec::with_mask(&scenario, file)?,
                None => scenario,
            };
            // What a run's errors name: the user's files too.
            let mut what = scenario.name().to_string();
            let (scenario, out) = match &grammar {
                Some(file) => {
                    let stem = file
                        .file_stem()
                        .map_or_else(|| "grammar".into(), |s| s.to_string_lossy().into_owned());
                    let out = out.unwrap_or_else(|| {
                        Path::new("out").join(format!("{}-{stem}", scenario.name()))
                    });
                    what = format!("{what} with the grammar {}", file.display());
                    (exec::with_grammar(&scenario, file)?, Some(out))
                }
                None => (scenario, out),
            };
            match (mesh, cylinders) {
                (Some(mesh), Some(cylinders)) => {
                    let body = body_input::with_body_files(&scenario, &mesh, &cylinders)?;
                    let stem = mesh
                        .file_stem()
                        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
                    let out = out.unwrap_or_else(|| {
                        Path::new("out").join(format!("{}-{stem}", scenario.name()))
                    });
                    what = format!("{what} on {} and {}", mesh.display(), cylinders.display());
                    run(
                        &body,
                        &what,
                        seed,
                        Some(out),
                        rig.as_deref(),
                        max_stream_mb,
                        writing,
                    )
                }
                _ => run(
                    &scenario,
                    &what,
                    seed,
                    out,
                    rig.as_deref(),
                    max_stream_mb,
                    writing,
                ),
            }
        }
        Command::Run { target: None, .. } => {
            bail!("give a preset name (see `morphogen list`), a scenario file, or --grammar FILE")
        }
        Command::Verify {
            fixtures,
            stream: Some(file),
            ..
        } => verify_capture(&file, &fixture::locate(fixtures, false)?),
        Command::Verify {
            targets,
            fixtures,
            stream: None,
            jobs,
            junit,
            format,
            pending,
            report,
        } => golden::run(&golden::Options {
            targets,
            fixtures: fixture::locate(fixtures, false)?,
            jobs,
            junit,
            format,
            pending,
            report,
        }),
        Command::Bless {
            targets,
            accept: true,
            fixtures,
            ..
        } => bless::accept(&targets, &fixture::locate(fixtures, false)?),
        Command::Bless {
            all: true,
            fixtures,
            ..
        } => bless::all(&fixture::locate(fixtures, false)?),
        Command::Bless {
            targets,
            sets: set_args,
            fixtures,
            seed,
            ..
        } => bless::targets(
            &targets,
            &sets(&set_args)?,
            &fixture::locate(fixtures, true)?,
            seed,
        ),
        Command::Review { targets, fixtures } => {
            review::run(&targets, &fixture::locate(fixtures, false)?)
        }
        Command::Sweep(args) => sweep::run(&args),
        Command::Listen(args) => listen::run(&args),
        Command::Send(args) => send::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Decode { file, out } => decode(&file, out.as_deref()),
    }
}

/// `run`: `scenario` into its folder; its errors name `what`.
fn run(
    scenario: &Scenario,
    what: &str,
    seed: Option<u64>,
    out: Option<PathBuf>,
    rig: Option<&str>,
    max_stream_mb: u32,
    writing: Writing,
) -> Result<Outcome> {
    let rig = rig.map(morphogen_cli::rig::parse_rig).transpose()?;
    exec::warn_unused_seed(scenario, seed);
    let seed = seed.unwrap_or(scenario.seed());
    let dir = out.unwrap_or_else(|| Path::new("out").join(scenario.name()));
    let lock = FolderLock::take(&dir)?;
    say_removed(&lock, &dir, writing.quiet)?;
    let (stream, jsonl) = (dir.join(exec::STREAM_FILE), dir.join(exec::JSONL_FILE));
    let paths = exec::RunPaths {
        stream: &stream,
        jsonl: writing.kinds.has(Kind::Jsonl).then_some(jsonl.as_path()),
    };
    let run = exec::run_to_file(scenario, what, seed, !writing.quiet, max_stream_mb, paths)?;
    let written = exec::write_outputs(&dir, &run, !writing.quiet, |records, dir| {
        let mut files = outputs::write(scenario, records, dir, writing.kinds)?;
        if let Some(rig) = rig {
            let inks = outputs::rig_inks(scenario);
            files.extend(morphogen_cli::rig::render_rig_png(
                records,
                rig,
                inks.as_deref(),
                dir,
            )?);
        }
        Ok(files)
    })?;
    // An earlier run's files of the series this run wrote anew, as they
    // were (their sizes), then gone.
    let stale = outputs::numbered::stale(&dir, &written)?;
    let stale_lines = written::lines(&stale);
    outputs::numbered::remove(&stale)?;
    if writing.quiet {
        return Ok(Outcome::Ok);
    }
    say!(
        "{} seed {}: {} frames, {} bytes, digest {:016x}",
        scenario.name(),
        seed,
        run.frames,
        run.bytes,
        run.digest
    )?;
    written::say_wrote(&written)?;
    for line in stale_lines {
        say!("  removed an earlier run's {line}")?;
    }
    Ok(Outcome::Ok)
}

/// Says which temporary files of a stopped run the folder lock removed.
fn say_removed(lock: &FolderLock, dir: &Path, quiet: bool) -> Result<()> {
    let (count, bytes) = lock.removed;
    if count > 0 && !quiet {
        say!(
            "removed {count} temporary file(s) ({}) that a stopped run left in {}",
            indicatif::DecimalBytes(bytes),
            dir.display()
        )?;
    }
    Ok(())
}

fn run_grammar(
    file: &Path,
    seed: Option<u64>,
    out: Option<PathBuf>,
    max_stream_mb: u32,
    writing: Writing,
) -> Result<Outcome> {
    let bytes = morphogen_scenario::read_limited(file)
        .map_err(|e| anyhow::anyhow!("cannot read grammar {}: {e}", file.display()))?;
    let text =
        morphogen_scenario::utf8(bytes).map_err(|e| anyhow::anyhow!("{}:{e}", file.display()))?;
    let seed = seed.unwrap_or(0);
    let stem = file
        .file_stem()
        .map_or_else(|| "grammar".into(), |s| s.to_string_lossy().into_owned());
    let dir = out.unwrap_or_else(|| Path::new("out").join(&stem));
    let lock = FolderLock::take(&dir)?;
    say_removed(&lock, &dir, writing.quiet)?;
    let (stream, jsonl) = (dir.join(exec::STREAM_FILE), dir.join(exec::JSONL_FILE));
    let paths = exec::RunPaths {
        stream: &stream,
        jsonl: writing.kinds.has(Kind::Jsonl).then_some(jsonl.as_path()),
    };
    let run = exec::run_grammar(file, &text, seed, max_stream_mb, paths, !writing.quiet)?;
    let written = exec::write_outputs(&dir, &run, !writing.quiet, |records, dir| {
        outputs::plant::write(records, dir, writing.kinds)
    })?;
    if writing.quiet {
        return Ok(Outcome::Ok);
    }
    say!(
        "{} seed {}: {} frames, {} bytes, digest {:016x}",
        file.display(),
        seed,
        run.frames,
        run.bytes,
        run.digest
    )?;
    written::say_wrote(&written)?;
    Ok(Outcome::Ok)
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

fn verify_capture(file: &Path, fixtures: &Path) -> Result<Outcome> {
    let bytes =
        read_capture(file).with_context(|| format!("cannot read capture {}", file.display()))?;
    let parts = capture::split(&bytes);
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

/// `decode`: the stream file read frame by frame, twice (the format
/// check, then the lines), never whole.
fn decode(file: &Path, out: Option<&Path>) -> Result<Outcome> {
    let stream = morphogen_cli::records::StreamFile::new(file);
    let start = morphogen_cli::records::Place::START;
    let unreadable = |e: std::io::Error| {
        anyhow::Error::new(e).context(format!("cannot read {}", file.display()))
    };
    let mut empty = true;
    for d in stream.frames(start)? {
        let d = d.map_err(unreadable)?;
        empty = false;
        if let Ok(morphogen::stream::Record::Header(h)) = &d.result
            && h.version != morphogen::stream::FORMAT_VERSION
        {
            bail!(
                "{}: the stream at byte {} is format version {}; this reader knows version {} (docs/stream-format.md)",
                file.display(),
                d.offset,
                h.version,
                morphogen::stream::FORMAT_VERSION
            );
        }
    }
    if empty {
        bail!("{} holds no frames", file.display());
    }
    let mut corrupt = 0usize;
    // Counts the corrupt frames on their way to `w`.
    let mut lines = |w: &mut dyn std::io::Write| -> Result<(), Written> {
        let mut line = Vec::with_capacity(256);
        for d in stream.frames(start).map_err(Written::Input)? {
            let d = d.map_err(|e| Written::Input(unreadable(e)))?;
            if d.result.as_ref().is_err_and(|e| e.is_corrupt()) {
                corrupt += 1;
            }
            line.clear();
            jsonl::decoded(&mut line, &d);
            line.push(b'\n');
            w.write_all(&line).map_err(Written::Output)?;
        }
        w.flush().map_err(Written::Output)
    };
    match out {
        Some(path) => {
            let mut file = atomic::OutputFile::create(path)?;
            lines(&mut file).map_err(|e| match e {
                Written::Input(e) => e,
                Written::Output(e) => {
                    anyhow::Error::new(e).context(format!("cannot write {}", path.display()))
                }
            })?;
            file.finish()?;
        }
        None => {
            let mut stdout = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
            lines(&mut stdout).map_err(|e| match e {
                Written::Input(e) => e,
                Written::Output(e) => StdoutError(e).into(),
            })?;
        }
    }
    if corrupt > 0 {
        bail!(
            "{corrupt} corrupt or truncated frame(s) in {} (shown as \"kind\":\"error\" lines)",
            file.display()
        );
    }
    Ok(Outcome::Ok)
}

/// Why `decode` stopped writing lines.
enum Written {
    /// The stream file could not be read.
    Input(anyhow::Error),
    /// The output could not be written.
    Output(std::io::Error),
}
