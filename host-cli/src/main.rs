//! `morphogen`: run, draw, export and verify Morphogen's simulations.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use morphogen::stream::Decoder;
use morphogen_cli::{Outcome, capture, exec, fixture, jsonl, outputs, verify};

/// The workspace's fixtures folder, the default for `verify` and `bless`.
const WORKSPACE_FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures");

/// Deterministic growth simulations: horns, bodies, plants, bones and cell
/// mosaics, bit-identical on a workstation and a microcontroller.
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
    /// Run a preset and write its stream, its records as JSON Lines and the
    /// model's own files (PNG, OBJ, CSV).
    Run {
        /// The preset's name (see `morphogen list`); omit it (or say
        /// `custom`) with --grammar.
        #[arg(required_unless_present = "grammar")]
        preset: Option<String>,
        /// Run an L-system grammar file instead of a preset (format:
        /// docs/lsystems.md); writes plant.png, plant.obj, segments.csv.
        #[arg(long, value_name = "FILE")]
        grammar: Option<PathBuf>,
        /// The seed (default: the preset's own, the one fixtures use).
        #[arg(long)]
        seed: Option<u64>,
        /// The output folder (default: out/<preset>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// With a body preset: grow this OBJ mesh instead of the built-in
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
        /// (LED matrix, OLED) shows it, drawn by the core's rig renderer.
        #[arg(long, value_name = "WxH")]
        rig: Option<String>,
        /// With a mosaic preset: where F cells may start instead of the
        /// preset's mask, a PBM (P1/P4) or PNG stretched over the whole
        /// domain (the control cylinder); white allows F (in a PNG: luminance
        /// and alpha both ≥ 50 %).
        #[arg(long, value_name = "FILE", conflicts_with_all = ["grammar", "mesh"])]
        mask: Option<PathBuf>,
    },
    /// Re-run presets and compare their streams with the golden fixtures,
    /// or check a device capture with --stream.
    Verify {
        /// Presets to verify (default: all).
        presets: Vec<String>,
        /// The fixtures folder.
        #[arg(long, default_value = WORKSPACE_FIXTURES)]
        fixtures: PathBuf,
        /// A capture from a device (one or more streams back to back, each
        /// starting with its header) to check instead of re-running.
        #[arg(long, conflicts_with = "presets")]
        stream: Option<PathBuf>,
    },
    /// Write the golden fixtures of presets (the only writer of fixtures).
    Bless {
        /// Presets to bless.
        #[arg(required = true)]
        presets: Vec<String>,
        /// The fixtures folder.
        #[arg(long, default_value = WORKSPACE_FIXTURES)]
        fixtures: PathBuf,
        /// The seed (default: the preset's own).
        #[arg(long)]
        seed: Option<u64>,
    },
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
    let cli = Cli::parse();
    match dispatch(cli.command) {
        Ok(Outcome::Ok) => ExitCode::SUCCESS,
        Ok(Outcome::Mismatch) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn dispatch(command: Command) -> Result<Outcome> {
    match command {
        Command::List => {
            let width = exec::all().map(|p| p.name().len()).max().unwrap_or(0);
            for p in exec::all() {
                let note = p
                    .host()
                    .map(|h| format!("  ({})", h.host_only_note()))
                    .unwrap_or_default();
                println!(
                    "{:width$}  seed {:<4} {}{note}",
                    p.name(),
                    p.default_seed(),
                    p.summary()
                );
            }
            Ok(Outcome::Ok)
        }
        Command::Run {
            preset,
            grammar: Some(file),
            seed,
            out,
            ..
        } => match preset.as_deref() {
            None | Some("custom") => run_grammar(&file, seed, out),
            Some(other) => bail!(
                "--grammar runs a grammar file: give no preset name (got '{other}'), or `custom`"
            ),
        },
        Command::Run {
            preset: Some(preset),
            grammar: None,
            seed,
            out,
            mesh: Some(mesh),
            cylinders: Some(cylinders),
            ..
        } => morphogen_cli::body_input::run(&preset, seed, out, &mesh, &cylinders),
        Command::Run {
            preset: Some(preset),
            grammar: None,
            seed,
            out,
            rig,
            mask,
            ..
        } => run(&preset, seed, out, rig.as_deref(), mask.as_deref()),
        Command::Run {
            preset: None,
            grammar: None,
            ..
        } => {
            bail!("give a preset name (see `morphogen list`) or --grammar FILE")
        }
        Command::Verify {
            presets,
            fixtures,
            stream: Some(file),
        } => {
            debug_assert!(presets.is_empty());
            verify_capture(&file, &fixtures)
        }
        Command::Verify {
            presets,
            fixtures,
            stream: None,
        } => verify_presets(presets, &fixtures),
        Command::Bless {
            presets,
            fixtures,
            seed,
        } => bless(&presets, &fixtures, seed),
        Command::Decode { file, out } => decode(&file, out.as_deref()),
    }
}

fn run(
    name: &str,
    seed: Option<u64>,
    out: Option<PathBuf>,
    rig: Option<&str>,
    mask: Option<&Path>,
) -> Result<Outcome> {
    let rig = rig.map(morphogen_cli::rig::parse_rig_size).transpose()?;
    let preset = exec::find(name)?;
    let preset = match mask {
        Some(file) => exec::with_mask(preset, file)?,
        None => preset,
    };
    let seed = seed.unwrap_or(preset.default_seed());
    let dir = out.unwrap_or_else(|| Path::new("out").join(preset.name()));
    fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    let run = exec::run(preset, seed, true)?;
    let written = exec::write_outputs(&dir, &run, |records, dir| {
        // With a user's mask, the name no longer gives the parameters.
        let mut files = match (mask, preset.mosaic()) {
            (Some(_), Some(params)) => outputs::mosaic::write(params, records, dir)?,
            _ => outputs::write(preset.name(), records, dir)?,
        };
        if let Some((w, h)) = rig {
            let path = dir.join(format!("rig-{w}x{h}.png"));
            morphogen_cli::rig::render_rig_png(records, w, h, &path)?;
            files.push(path);
        }
        Ok(files)
    })?;
    println!(
        "{} seed {}: {} frames, {} bytes, digest {:016x}",
        preset.name(),
        seed,
        run.frames,
        run.stream.len(),
        run.digest
    );
    for path in written {
        println!("  wrote {}", path.display());
    }
    Ok(Outcome::Ok)
}

fn run_grammar(file: &Path, seed: Option<u64>, out: Option<PathBuf>) -> Result<Outcome> {
    let text = fs::read_to_string(file)
        .with_context(|| format!("cannot read grammar {}", file.display()))?;
    let seed = seed.unwrap_or(0);
    let stem = file
        .file_stem()
        .map_or_else(|| "grammar".into(), |s| s.to_string_lossy().into_owned());
    let run = outputs::plant::run_grammar(file, &text, seed)?;
    let dir = out.unwrap_or_else(|| Path::new("out").join(&stem));
    let written = exec::write_outputs(&dir, &run, outputs::plant::write)?;
    println!(
        "{} seed {}: {} frames, {} bytes, digest {:016x}",
        file.display(),
        seed,
        run.frames,
        run.stream.len(),
        run.digest
    );
    for path in written {
        println!("  wrote {}", path.display());
    }
    Ok(Outcome::Ok)
}

fn verify_presets(names: Vec<String>, fixtures: &Path) -> Result<Outcome> {
    let names: Vec<String> = if names.is_empty() {
        exec::all().map(|p| p.name().to_string()).collect()
    } else {
        names
    };
    let mut outcome = Outcome::Ok;
    for name in names {
        let preset = exec::find(&name)?;
        let fixture = fixture::load(fixtures, preset.name())?;
        let run = exec::run(preset, fixture.summary.seed, true)?;
        match verify::compare(&fixture.stream, &run.stream) {
            None => println!(
                "ok        {} ({} frames, digest {:016x})",
                preset.name(),
                run.frames,
                run.digest
            ),
            Some(diff) => {
                println!("MISMATCH  {}: {diff}", preset.name());
                outcome = Outcome::Mismatch;
            }
        }
    }
    Ok(outcome)
}

fn verify_capture(file: &Path, fixtures: &Path) -> Result<Outcome> {
    let bytes =
        fs::read(file).with_context(|| format!("cannot read capture {}", file.display()))?;
    let parts = capture::split(&bytes);
    if parts.is_empty() {
        bail!("capture {} holds no frames", file.display());
    }
    let mut outcome = Outcome::Ok;
    let mut missing = Vec::new();
    for part in &parts {
        let actual = &bytes[part.range.clone()];
        let Some(header) = &part.header else {
            println!(
                "MISMATCH  {} bytes before the first readable header (at byte 0)",
                actual.len()
            );
            outcome = Outcome::Mismatch;
            continue;
        };
        let fixture = match fixture::load(fixtures, header.preset.as_str()) {
            Ok(fixture) => fixture,
            Err(e) => {
                println!("ERROR     {}: {e:#}", header.preset);
                missing.push(header.preset.to_string());
                continue;
            }
        };
        match verify::compare(&fixture.stream, actual) {
            None => println!(
                "ok        {} (bytes {}..{} of the capture)",
                header.preset, part.range.start, part.range.end
            ),
            Some(diff) => {
                println!(
                    "MISMATCH  {} (capture bytes {}..): {diff}",
                    header.preset, part.range.start
                );
                outcome = Outcome::Mismatch;
            }
        }
    }
    println!("{} stream(s) in {}", parts.len(), file.display());
    if !missing.is_empty() {
        bail!(
            "the capture holds streams without a fixture: {}",
            missing.join(", ")
        );
    }
    Ok(outcome)
}

fn bless(names: &[String], fixtures: &Path, seed: Option<u64>) -> Result<Outcome> {
    for name in names {
        let preset = exec::find(name)?;
        let seed = seed.unwrap_or(preset.default_seed());
        let run = exec::run(preset, seed, true)?;
        let summary = fixture::summarise(preset, seed, &run);
        let dir = fixture::bless(fixtures, &summary, &run)?;
        println!(
            "blessed   {} seed {seed}: {} frames, digest {:016x} -> {}",
            preset.name(),
            run.frames,
            run.digest,
            dir.display()
        );
    }
    Ok(Outcome::Ok)
}

fn decode(file: &Path, out: Option<&Path>) -> Result<Outcome> {
    let bytes = fs::read(file).with_context(|| format!("cannot read {}", file.display()))?;
    let text = jsonl::stream(&bytes);
    match out {
        Some(path) => fixture::write_atomic(path, text.as_bytes())?,
        None => print!("{text}"),
    }
    let corrupt = Decoder::new(&bytes).filter(|d| d.result.is_err()).count();
    if corrupt > 0 {
        bail!(
            "{corrupt} corrupt or truncated frame(s) in {} (shown as \"kind\":\"error\" lines)",
            file.display()
        );
    }
    Ok(Outcome::Ok)
}
