//! `morphogen`: run, draw, export and verify Morphogen's simulations.
// No function of the host over `too-many-lines-threshold` (clippy.toml).
#![deny(clippy::too_many_lines)]

use std::process::ExitCode;

use anyhow::Result;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use morphogen_cli::stdout::StdoutError;
use morphogen_cli::{
    Outcome, atomic, bless, decode, fixture, golden, list, listen, provenance, review, run, send,
    serve, sweep,
};

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
    Run(run::Args),
    /// Re-run scenarios and compare their streams with the golden fixtures,
    /// or check a device capture with --stream. Every fixture folder is
    /// checked; a mismatch leaves the new stream beside the fixture as
    /// `stream.bin.pending`, and the scenario file it was made from, when
    /// that is not the fixture's own, as `scenario.toml.pending`
    /// (`bless --accept` takes both; under CI only with --pending). Exit 1
    /// on any mismatch or missing fixture, 2 when one cannot be checked.
    Verify(golden::Args),
    /// Write the golden fixtures of presets or scenario files (the only
    /// writer of fixtures). A scenario file's fixture keeps a
    /// self-contained copy of it, so `verify` re-runs it from there.
    Bless(bless::Args),
    /// Go through the pending streams `verify` left (all, or those of
    /// TARGETS), one fixture at a time: what differs, the changed keys and
    /// the pictures, then accept (bless it), reject (remove it), skip, or
    /// accept all. Asks at a terminal; scripts use `bless --accept`.
    Review(review::Args),
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
    Decode(decode::Args),
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

fn dispatch(command: Command) -> Result<Outcome> {
    match command {
        Command::List => list::list(),
        Command::Show { preset } => list::show(&preset),
        Command::Run(args) => run::run(args),
        Command::Verify(args) => golden::command(args),
        Command::Bless(args) => bless::command(&args),
        Command::Review(args) => {
            review::run(&args.targets, &fixture::locate(args.fixtures, false)?)
        }
        Command::Sweep(args) => sweep::run(&args),
        Command::Listen(args) => listen::run(&args),
        Command::Send(args) => send::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Decode(args) => decode::run(&args),
    }
}
