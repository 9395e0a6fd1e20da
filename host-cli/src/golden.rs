//! `morphogen verify` over fixtures: each re-run and compared with its golden
//! stream, side by side on worker threads, reported in order to a terminal
//! or as JSON lines, and to CI systems ([`crate::ci_report`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use morphogen_scenario::Scenario;
use morphogen_stream_text::verify;

use crate::verdict::{Case, Counts, Mismatch, Pending, Verdict};
use crate::{Outcome, ci_report, exec, fixture, report, say};

/// How `verify` prints its cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Format {
    /// A line per fixture and a summary line.
    #[default]
    Text,
    /// A JSON object per fixture and a last one with the counts.
    Json,
}

/// `morphogen verify`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Presets or scenario files to verify (default: every fixture in
    /// the fixtures folder, built-in or not).
    pub targets: Vec<String>,
    /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
    /// `fixtures/` in this folder or the nearest parent that has one).
    #[arg(long)]
    pub fixtures: Option<PathBuf>,
    /// A capture from a device (one or more streams back to back, each
    /// starting with its header) to check instead of re-running.
    #[arg(long, conflicts_with = "targets")]
    pub stream: Option<PathBuf>,
    /// Threads re-running fixtures side by side, 1 to 256 (default:
    /// all cores).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub jobs: Option<u16>,
    /// Also write a JUnit XML report to FILE: a test case per fixture,
    /// a failure for a mismatch or a missing fixture, an error for one
    /// that cannot be checked (what GitLab, Jenkins and GitHub's test
    /// reporters read).
    #[arg(long, value_name = "FILE", conflicts_with = "stream")]
    pub junit: Option<PathBuf>,
    /// Print a line per fixture (text) or a JSON object per fixture and
    /// one with the counts (json).
    #[arg(long, value_enum, default_value_t, conflicts_with = "stream")]
    pub format: Format,
    /// Leave a mismatch's new stream beside its fixture even when CI is
    /// set (under CI nothing is written into the fixtures folder
    /// otherwise). With GITHUB_ACTIONS=true each failing fixture is
    /// also an `::error` annotation and the counts a table in the job
    /// summary.
    #[arg(long, conflicts_with = "stream")]
    pub pending: bool,
    /// Draw each mismatch's pictures into DIR/NAME/ (default: beside
    /// its pending stream, in the fixture's report/; under CI only
    /// with this): the model's pictures of the expected and the actual
    /// stream up to the end of the first frame that differs, in
    /// expected/ and actual/, and their difference in difference/
    /// (changed pixels red), for each picture that is not the same.
    #[arg(long, value_name = "DIR", conflicts_with = "stream")]
    pub report: Option<PathBuf>,
}

/// `morphogen verify`: a device capture (`--stream`) or the fixtures.
///
/// # Errors
/// As [`run`] and [`crate::capture::verify`].
pub fn command(args: Args) -> Result<Outcome> {
    let fixtures = fixture::locate(args.fixtures, false)?;
    if let Some(file) = &args.stream {
        return crate::capture::verify(file, &fixtures);
    }
    run(&Options {
        targets: args.targets,
        fixtures,
        jobs: args.jobs,
        junit: args.junit,
        format: args.format,
        pending: args.pending,
        report: args.report,
    })
}

/// What to verify and how to report it.
#[derive(Debug, Clone)]
pub struct Options {
    /// Presets or scenario files (none: every fixture in the folder).
    pub targets: Vec<String>,
    /// The fixtures folder.
    pub fixtures: PathBuf,
    /// Worker threads (none: every core).
    pub jobs: Option<u16>,
    /// The JUnit XML report to write.
    pub junit: Option<PathBuf>,
    /// The output format.
    pub format: Format,
    /// Whether to leave a mismatch's new stream beside its fixture even
    /// under CI.
    pub pending: bool,
    /// The folder for the pictures of mismatches (none: beside each
    /// pending stream).
    pub report: Option<PathBuf>,
}

/// The fixture folder's scenarios to check: every one in the folder, or
/// `targets`'; one whose scenario cannot be read is an error of its own
/// case, never a fixture left out.
fn scenarios(targets: &[String], fixtures: &Path) -> Result<Vec<(String, Result<Scenario>)>> {
    let scenarios: Vec<(String, Result<Scenario>)> = if targets.is_empty() {
        fixture::names(fixtures)?
            .into_iter()
            .map(|name| {
                let scenario = fixture::scenario(fixtures, &name);
                (name, scenario)
            })
            .collect()
    } else {
        targets
            .iter()
            .map(|t| fixture::target(t, fixtures).map(|s| (s.name().to_string(), Ok(s))))
            .collect::<Result<_>>()?
    };
    if scenarios.is_empty() {
        bail!("no fixtures in {}", fixtures.display());
    }
    Ok(scenarios)
}

/// Re-runs `scenario` with its fixture's seed and compares; `target` is
/// the command line's name for it, if it named one. Writes (or removes) the
/// pending stream when `writes`, and draws a mismatch's pictures into
/// `report` or else, when `writes`, beside the pending stream. With the
/// verdict, a note when `target` is a scenario file whose own seed is not
/// its fixture's: its edited seed is not what was checked.
fn check(
    scenario: &Scenario,
    target: Option<&str>,
    (fixtures, report): (&Path, Option<&Path>),
    alone: bool,
    writes: bool,
) -> Result<(Verdict, Option<String>)> {
    let name = scenario.name();
    if !fixture::dir(fixtures, name).is_dir() {
        let verdict = Verdict::Missing(format!(
            "no fixture in {} (create it with `morphogen bless {}`)",
            fixtures.display(),
            if scenario.is_builtin() {
                name
            } else {
                scenario.origin()
            }
        ));
        return Ok((verdict, None));
    }
    let fixture = fixture::read(fixtures, name)?;
    let seed = fixture.summary().seed;
    let note = (target.is_some_and(exec::is_file) && scenario.seed() != seed).then(|| {
        format!(
            "run with the fixture's seed {seed}; {} says seed = {} (bless it to take that seed)",
            scenario.origin(),
            scenario.seed()
        )
    });
    let run = exec::run(scenario, seed, alone)?;
    let first = verify::compare(fixture.stream(), &run.stream);
    // A fixture the run matched byte for byte has the run's digest.
    let fixture = fixture.checked(first.is_none().then_some(run.digest))?;
    let verdict = match first {
        None => {
            if writes {
                fixture::drop_pending(fixtures, name, scenario)?;
            }
            Verdict::Ok {
                frames: run.frames,
                digest: run.digest,
            }
        }
        Some(first) => {
            let pictures = match report {
                Some(dir) => Some(dir.join(name)),
                None => writes.then(|| fixture::dir(fixtures, name).join(report::REPORT_DIR)),
            }
            .ok_or_else(|| "not drawn: CI is set (give --report DIR for the pictures)".to_string());
            // A mismatch is a mismatch (exit 1) in a folder that cannot be
            // written too.
            let pending = if writes {
                match fixture::write_pending(fixtures, name, scenario, &run.stream) {
                    Ok(path) => Pending::Written(path),
                    Err(e) => Pending::Failed(format!("{e:#}")),
                }
            } else {
                Pending::HeldBack
            };
            let blessed = fixture::scenario(fixtures, name)?;
            Verdict::Mismatch(Box::new(Mismatch::new(
                first,
                (&blessed, &fixture.stream),
                (scenario, &run.stream),
                pictures,
                pending,
            )))
        }
    };
    Ok((verdict, note))
}

/// Re-runs the fixtures of `options` on worker threads and compares each
/// stream with its fixture; a case per fixture, printed in order as soon
/// as it and those before it are done, then the counts; then the JUnit
/// report and, on GitHub Actions, the annotations and the job summary.
///
/// # Errors
/// No fixtures, a target that is not one, a report that cannot be
/// written, or a fixture that could not be checked (after every other is).
pub fn run(options: &Options) -> Result<Outcome> {
    use rayon::prelude::*;
    let fixtures = &options.fixtures;
    let scenarios = scenarios(&options.targets, fixtures)?;
    let writes = options.pending || !ci_report::detected();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.map_or(0, usize::from))
        .build()
        .context("cannot start the worker threads")?;
    let alone = scenarios.len() == 1;
    let report = options.report.as_deref();
    let case = |i: usize, name: &str, scenario: &Result<Scenario>| -> Case {
        let start = Instant::now();
        let target = options.targets.get(i).map(String::as_str);
        let (verdict, note) = scenario
            .as_ref()
            .map_err(|e| anyhow::anyhow!("{e:#}"))
            .and_then(|s| check(s, target, (fixtures, report), alone, writes))
            .unwrap_or_else(|e| (Verdict::Error(format!("{e:#}")), None));
        Case {
            name: name.to_string(),
            folder: fixture::dir(fixtures, name),
            seconds: start.elapsed().as_secs_f64(),
            verdict,
            note,
        }
    };
    let (done, results) = std::sync::mpsc::channel();
    let cases = std::thread::scope(|scope| -> Result<Vec<Case>> {
        scope.spawn(|| {
            pool.install(|| {
                scenarios
                    .par_iter()
                    .enumerate()
                    .try_for_each_with(done, |done, (i, (name, s))| {
                        // A failed send: the printer stopped early.
                        done.send((i, case(i, name, s))).map_err(drop)
                    })
            })
        });
        let mut cases = Vec::with_capacity(scenarios.len());
        let mut waiting = std::collections::BTreeMap::new();
        for (i, case) in results {
            waiting.insert(i, case);
            while let Some(case) = waiting.remove(&cases.len()) {
                match options.format {
                    Format::Text => say!("{}", case.text())?,
                    Format::Json => say!("{}", ci_report::json(&case))?,
                }
                cases.push(case);
            }
        }
        Ok(cases)
    })?;
    conclude(options, &cases, writes)
}

/// After the cases: the counts, the JUnit report and, on GitHub Actions,
/// the annotations and the job summary; then the outcome (`writes`: the
/// pending streams were written).
fn conclude(options: &Options, cases: &[Case], writes: bool) -> Result<Outcome> {
    let fixtures = &options.fixtures;
    let counts = Counts::of(cases);
    match options.format {
        Format::Text => {
            say!("{counts}")?;
            if !writes && counts.mismatch > 0 {
                say!(
                    "CI is set: no new stream was written into {} (give --pending to leave them for `bless --accept`)",
                    fixtures.display()
                )?;
            }
        }
        Format::Json => say!("{}", ci_report::json_summary(counts))?,
    }
    if let Some(path) = &options.junit {
        let xml = ci_report::junit(cases, fixtures)?;
        crate::atomic::write_atomic(path, xml.as_bytes())
            .with_context(|| format!("cannot write the JUnit report {}", path.display()))?;
    }
    if ci_report::on_github() {
        for annotation in cases.iter().filter_map(ci_report::annotation) {
            say!("{annotation}")?;
        }
        ci_report::append_step_summary(&ci_report::step_summary(cases))?;
    }
    if let Some(first) = cases
        .iter()
        .find(|c| matches!(c.verdict, Verdict::Error(_)))
    {
        bail!(
            "{} fixture(s) could not be checked; first: {}: {}",
            counts.error,
            first.name,
            first.problem().unwrap_or_default()
        );
    }
    Ok(if counts.mismatch + counts.missing > 0 {
        Outcome::Mismatch
    } else {
        Outcome::Ok
    })
}
