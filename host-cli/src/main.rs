//! `morphogen`: run, draw, export and verify Morphogen's simulations.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use morphogen::preset::PRESETS;
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
        /// The preset's name (see `morphogen list`).
        preset: String,
        /// The seed (default: the preset's own, the one fixtures use).
        #[arg(long)]
        seed: Option<u64>,
        /// The output folder (default: out/<preset>).
        #[arg(long)]
        out: Option<PathBuf>,
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
            let width = PRESETS.iter().map(|p| p.name.len()).max().unwrap_or(0);
            for p in PRESETS {
                println!(
                    "{:width$}  seed {:<4} {}",
                    p.name, p.default_seed, p.summary
                );
            }
            Ok(Outcome::Ok)
        }
        Command::Run { preset, seed, out } => run(&preset, seed, out),
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

fn run(name: &str, seed: Option<u64>, out: Option<PathBuf>) -> Result<Outcome> {
    let preset = exec::find(name)?;
    let seed = seed.unwrap_or(preset.default_seed);
    let dir = out.unwrap_or_else(|| Path::new("out").join(preset.name));
    fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    let run = exec::run(preset, seed, true)?;
    let stream_path = dir.join("stream.bin");
    fixture::write_atomic(&stream_path, &run.stream)?;
    let jsonl_path = dir.join("records.jsonl");
    fixture::write_atomic(&jsonl_path, jsonl::stream(&run.stream).as_bytes())?;
    let records: Vec<_> = Decoder::new(&run.stream)
        .filter_map(|d| d.result.ok())
        .collect();
    let mut written = vec![stream_path, jsonl_path];
    written.extend(outputs::write(preset.name, &records, &dir)?);
    println!(
        "{} seed {}: {} frames, {} bytes, digest {:016x}",
        preset.name,
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
        PRESETS.iter().map(|p| p.name.to_string()).collect()
    } else {
        names
    };
    let mut outcome = Outcome::Ok;
    for name in names {
        let preset = exec::find(&name)?;
        let fixture = fixture::load(fixtures, preset.name)?;
        let run = exec::run(preset, fixture.summary.seed, true)?;
        match verify::compare(&fixture.stream, &run.stream) {
            None => println!(
                "ok        {} ({} frames, digest {:016x})",
                preset.name, run.frames, run.digest
            ),
            Some(diff) => {
                println!("MISMATCH  {}: {diff}", preset.name);
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
        let fixture = fixture::load(fixtures, header.preset.as_str())?;
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
    Ok(outcome)
}

fn bless(names: &[String], fixtures: &Path, seed: Option<u64>) -> Result<Outcome> {
    for name in names {
        let preset = exec::find(name)?;
        let seed = seed.unwrap_or(preset.default_seed);
        let run = exec::run(preset, seed, true)?;
        let summary = fixture::summarise(preset, seed, &run);
        let dir = fixture::bless(fixtures, &summary, &run)?;
        println!(
            "blessed   {} seed {seed}: {} frames, digest {:016x} -> {}",
            preset.name,
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
