//! `morphogen bless`, the only writer of fixtures: from runs of presets
//! and scenario files, from every fixture's own scenario and seed
//! (`--all`), or from the pending streams `verify` left (`--accept`, and
//! [`crate::review`]).

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use morphogen_scenario::Scenario;

use crate::{Outcome, exec, fixture, say};

/// `morphogen bless`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Presets or scenario files to bless.
    #[arg(required_unless_present_any = ["accept", "all"])]
    pub targets: Vec<String>,
    /// Take the new streams `verify` left as `stream.bin.pending`,
    /// with their `scenario.toml.pending` where there is one (all of
    /// them, or those of TARGETS).
    #[arg(long, conflicts_with_all = ["all", "sets", "seed"])]
    pub accept: bool,
    /// Re-bless every fixture in the folder, each from its own scenario
    /// and seed.
    #[arg(long, conflicts_with_all = ["targets", "sets", "seed"])]
    pub all: bool,
    /// Change a parameter (as `run --set`); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
    /// `fixtures/` in this folder or the nearest parent that has one,
    /// else a new `fixtures/` here).
    #[arg(long)]
    pub fixtures: Option<PathBuf>,
    /// The seed (default: the scenario's own).
    #[arg(long)]
    pub seed: Option<u64>,
}

/// `morphogen bless`: the targets, every fixture (`--all`) or the pending
/// streams (`--accept`).
///
/// # Errors
/// As [`targets`], [`all`] and [`accept`].
pub fn command(args: &Args) -> Result<Outcome> {
    if args.accept {
        accept(
            &args.targets,
            &fixture::locate(args.fixtures.clone(), false)?,
        )
    } else if args.all {
        all(&fixture::locate(args.fixtures.clone(), false)?)
    } else {
        targets(
            &args.targets,
            &exec::parse_sets(&args.sets)?,
            &fixture::locate(args.fixtures.clone(), true)?,
            args.seed,
        )
    }
}

/// `bless TARGETS`: each preset or scenario file (with `sets`) run with
/// `seed` or its own, and blessed.
///
/// # Errors
/// A target that is not one, a run that fails, or a fixture that cannot
/// be written.
pub fn targets(
    targets: &[String],
    sets: &[(String, String)],
    fixtures: &Path,
    seed: Option<u64>,
) -> Result<Outcome> {
    for target in targets {
        let scenario = exec::find(target, sets)?;
        exec::warn_unused_seed(&scenario, seed);
        let seed = seed.unwrap_or(scenario.seed());
        let run = exec::run(&scenario, seed, true)?;
        write(fixtures, &scenario, seed, &run)?;
    }
    Ok(Outcome::Ok)
}

/// Writes `run` as `scenario`'s fixture and says so.
fn write(fixtures: &Path, scenario: &Scenario, seed: u64, run: &exec::Run) -> Result<()> {
    let summary = fixture::summarise(scenario, seed, run);
    let dir = fixture::bless(fixtures, scenario, &summary, run)?;
    say!(
        "blessed   {} seed {seed}: {} frames, digest {:016x} -> {}",
        scenario.name(),
        run.frames,
        run.digest,
        dir.display()
    )?;
    Ok(())
}

/// `bless --all`: every fixture in `fixtures` re-run from its own scenario
/// and seed, and re-blessed.
///
/// # Errors
/// No fixtures, or one that cannot be read, run or written.
pub fn all(fixtures: &Path) -> Result<Outcome> {
    let names = fixture::names(fixtures)?;
    if names.is_empty() {
        bail!("no fixtures in {}", fixtures.display());
    }
    for name in names {
        let scenario = fixture::scenario(fixtures, &name)?;
        let seed = fixture::load(fixtures, &name)?.summary.seed;
        let run = exec::run(&scenario, seed, true)?;
        write(fixtures, &scenario, seed, &run)?;
    }
    Ok(Outcome::Ok)
}

/// `bless --accept`: the pending streams `verify` left (all, or those of
/// `targets`) become the fixtures.
///
/// # Errors
/// A target that is not a fixture, or a pending stream that cannot be
/// read or blessed.
pub fn accept(targets: &[String], fixtures: &Path) -> Result<Outcome> {
    let names: Vec<String> = if targets.is_empty() {
        fixture::pending_names(fixtures)?
    } else {
        targets
            .iter()
            .map(|t| fixture::target(t, fixtures).map(|s| s.name().to_string()))
            .collect::<Result<_>>()?
    };
    if names.is_empty() {
        say!("nothing pending in {}", fixtures.display())?;
        return Ok(Outcome::Ok);
    }
    for name in names {
        accept_one(fixtures, &name)?;
    }
    Ok(Outcome::Ok)
}

/// `name`'s pending stream, made from its pending scenario, blessed with
/// the fixture's seed.
///
/// # Errors
/// No pending stream, or one that cannot be read or blessed.
pub fn accept_one(fixtures: &Path, name: &str) -> Result<()> {
    let scenario = fixture::pending_scenario(fixtures, name)?;
    let seed = fixture::load(fixtures, name)?.summary.seed;
    let run = fixture::read_pending(fixtures, name)?;
    write(fixtures, &scenario, seed, &run)
}
