//! `morphogen sweep`: the cartesian product of parameter values, run on all
//! cores, one folder per run and one table (`sweep.csv`) for them all. A
//! run's row depends only on its parameters, so the table is the same for
//! any thread count; `--shard I/N` runs every N-th combination (a batch
//! scheduler's array job) and `--merge` joins the shards' tables into the
//! table an unsharded sweep writes. `sweep.toml` beside the table names
//! the sweep (its scenario's digest and value lists), so that only shards
//! of one sweep merge, and every merged row is checked against its run's
//! stream.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use morphogen::stream::{Decoder, Record, StreamDigest};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::atomic::write_atomic;
use crate::exec;
use crate::folder_lock::FolderLock;
use morphogen_scenario::quoted;

/// The table a sweep writes into its folder.
pub const TABLE: &str = "sweep.csv";

/// What the sweep in a folder is: its scenario's digest, value lists,
/// runs and shard.
pub const MANIFEST: &str = "sweep.toml";

/// The most runs one sweep may have.
pub const MAX_RUNS: usize = 100_000;

/// Arguments of `morphogen sweep`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The preset or scenario file to sweep.
    #[arg(required_unless_present = "merge")]
    target: Option<String>,
    /// A key and its values: `--set mosaic.days=10,20,30`, `--set
    /// lsystem.delta=20,25,30`; `--set seed=1..8` for seeds 1 to 8. Repeatable: every combination runs,
    /// the first key changing slowest.
    #[arg(long = "set", value_name = "KEY=V1,V2,…")]
    sets: Vec<String>,
    /// The output folder: one sub-folder per run and `sweep.csv`.
    #[arg(long, required = true)]
    out: PathBuf,
    /// Run only combinations k with k mod N = I − 1 (I from 1 to N).
    #[arg(long, value_name = "I/N", conflicts_with = "merge")]
    shard: Option<String>,
    /// Threads, 1 to 256 (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    jobs: Option<u16>,
    /// Join the `sweep.csv` of these shard folders into `--out`.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["target", "sets"])]
    merge: Vec<PathBuf>,
}

/// One swept key and its values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Axis {
    key: String,
    values: Vec<String>,
}

/// `sweep.toml`: which sweep a folder holds, and which shard of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Manifest {
    /// The scenario's name.
    scenario: String,
    /// CRC-64/XZ (hex) of the scenario as one self-contained file.
    scenario_digest: String,
    /// Combinations in the whole sweep.
    runs: usize,
    /// `I/N`, or `1/1` for a whole sweep (a merged one too).
    shard: String,
    /// The keys and their values, the first changing slowest.
    axes: Vec<Axis>,
}

impl Manifest {
    /// Whether `other` is a shard of the same sweep.
    fn same_sweep(&self, other: &Manifest) -> bool {
        (&self.scenario_digest, self.runs, &self.axes)
            == (&other.scenario_digest, other.runs, &other.axes)
    }
}

/// The combination `k` of `axes` (the first key changing slowest).
fn combination(k: usize, axes: &[Axis]) -> Vec<(String, String)> {
    let mut rest = k;
    let mut chosen = vec![(String::new(), String::new()); axes.len()];
    for (slot, axis) in chosen.iter_mut().zip(axes).rev() {
        let n = axis.values.len();
        *slot = (axis.key.clone(), axis.values[rest % n].clone());
        rest /= n;
    }
    chosen
}

/// Splits `a,b,c` at commas outside brackets, braces and quotes;
/// `seed=1..8` style ranges of integers expand.
fn values(text: &str) -> Result<Vec<String>> {
    if let Some((a, b)) = text.split_once("..")
        && let (Ok(a), Ok(b)) = (a.trim().parse::<u64>(), b.trim().parse::<u64>())
    {
        if b < a || b - a >= MAX_RUNS as u64 {
            bail!(
                "{}: a range a..b needs a ≤ b and at most {MAX_RUNS} values",
                quoted(text)
            );
        }
        return Ok((a..=b).map(|v| v.to_string()).collect());
    }
    let (mut out, mut depth, mut quote, mut current) = (Vec::new(), 0i32, None, String::new());
    for c in text.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (None, '"' | '\'') => quote = Some(c),
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                out.push(std::mem::take(&mut current).trim().to_string());
                continue;
            }
            _ => {}
        }
        current.push(c);
    }
    out.push(current.trim().to_string());
    if out.iter().any(String::is_empty) {
        bail!("{}: an empty value", quoted(text));
    }
    Ok(out)
}

/// The `--set`s of one combination for the scenario (all but the seed),
/// files named read from the current folder as `run --set` reads them
/// (`chosen` keeps the paths, for the table).
fn scenario_sets(chosen: &[(String, String)]) -> Result<Vec<(String, String)>> {
    chosen
        .iter()
        .filter(|(k, _)| k != "seed")
        .map(|(k, v)| {
            let value = exec::set_value(k, v)
                .map_err(|e| anyhow!("--set {}: {e}", quoted(&format!("{k}={v}"))))?;
            Ok((k.clone(), value))
        })
        .collect()
}

/// A sweep's combinations over a scenario, for whoever runs them: `run`
/// on all cores, or the Python package's `morphogen.sweep` on any
/// executor. Gives each combination's scenario and seed, the table's
/// header and each run's line, as `sweep.csv` holds them.
#[derive(Debug)]
pub struct Plan {
    base: morphogen_scenario::Scenario,
    axes: Vec<Axis>,
    runs: usize,
}

impl Plan {
    /// `base` swept over `sets` (`KEY=V1,V2,…` as `--set` takes them,
    /// `seed=1..8` for seeds), the first key changing slowest.
    ///
    /// # Errors
    /// A key given twice or without values, or more than [`MAX_RUNS`]
    /// combinations.
    pub fn new(base: morphogen_scenario::Scenario, sets: &[String]) -> Result<Plan> {
        let axes = axes(sets)?;
        let runs = axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .filter(|&n| n <= MAX_RUNS)
            .ok_or_else(|| anyhow!("more than {MAX_RUNS} combinations (sweep::MAX_RUNS)"))?;
        Ok(Plan { base, axes, runs })
    }

    /// The number of combinations (runs).
    #[must_use]
    pub fn runs(&self) -> usize {
        self.runs
    }

    /// The table's first line (with its line end).
    #[must_use]
    pub fn header(&self) -> String {
        header(&self.axes)
    }

    /// Run `k`'s scenario and seed.
    ///
    /// # Errors
    /// A `k` past the runs, or a bad value of the combination (named).
    pub fn scenario(&self, k: usize) -> Result<(morphogen_scenario::Scenario, u64)> {
        if k >= self.runs {
            bail!("run {k}: the sweep has {} runs", self.runs);
        }
        let chosen = combination(k, &self.axes);
        let scenario = scenario_sets(&chosen)
            .and_then(|sets| Ok(self.base.clone_with_sets(&sets)?))
            .with_context(|| {
                let sets: Vec<String> = chosen.iter().map(|(k, v)| format!("{k}={v}")).collect();
                format!("the combination {}", sets.join(" "))
            })?;
        let seed = match chosen.iter().find(|(k, _)| k == "seed") {
            Some((_, v)) => v
                .parse()
                .map_err(|_| anyhow!("--set seed={v}: a seed is a whole number"))?,
            None => scenario.seed(),
        };
        Ok((scenario, seed))
    }

    /// Run `k`'s line of the table (with its line end), its stream
    /// `stream`.
    #[must_use]
    pub fn line(&self, k: usize, stream: &[u8]) -> String {
        let mut line = row(k, &combination(k, &self.axes), stream);
        let _ = writeln!(line, ",{}", csv(&crate::provenance::maker()));
        line
    }
}

fn shard(text: &str) -> Result<(usize, usize)> {
    let bad = || anyhow!("--shard {text}: give I/N with 1 ≤ I ≤ N");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i == 0 || i > n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Runs or merges a sweep.
///
/// # Errors
/// Bad arguments, a bad value (named by the scenario's error), or an
/// unwritable folder.
pub fn run(args: &Args) -> Result<crate::Outcome> {
    if !args.merge.is_empty() {
        return merge(&args.merge, &args.out);
    }
    let target = args.target.as_deref().unwrap_or_default();
    let plan = Plan::new(exec::find(target, &[])?, &args.sets)?;
    let total = plan.runs;
    let (index, count) = args
        .shard
        .as_deref()
        .map(shard)
        .transpose()?
        .unwrap_or((1, 1));
    let combos: Vec<usize> = (0..total).filter(|k| k % count == index - 1).collect();
    // Check every combination before running any.
    for &k in &combos {
        plan.scenario(k)?;
    }
    let _lock = FolderLock::take(&args.out)?;
    let earlier = listed_runs(&args.out)?;
    let manifest = Manifest {
        scenario: plan.base.name().to_string(),
        scenario_digest: format!(
            "{:016x}",
            StreamDigest::of(plan.base.self_contained().as_bytes())
        ),
        runs: total,
        shard: format!("{index}/{count}"),
        axes: plan.axes.clone(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.map_or(0, usize::from))
        .build()
        .context("cannot start the worker threads")?;
    let rows: Vec<Result<String>> = pool.install(|| {
        combos
            .par_iter()
            .map(|&k| one_run(&plan, k, &args.out))
            .collect()
    });
    let mut table = plan.header();
    for row in rows {
        table.push_str(&row?);
    }
    write_manifest(&args.out, &manifest)?;
    write_atomic(&args.out.join(TABLE), table.as_bytes())?;
    let stale = remove_earlier_runs(&args.out, &earlier, combos.iter().copied())?;
    crate::say!(
        "{} of {total} runs (shard {index}/{count}) -> {}",
        combos.len(),
        args.out.join(TABLE).display()
    )?;
    say_removed(&stale)?;
    Ok(crate::Outcome::Ok)
}

/// The axes of `--set KEY=a,b,c` options, each key once and with values.
fn axes(sets: &[String]) -> Result<Vec<Axis>> {
    let axes: Vec<Axis> = sets
        .iter()
        .map(|s| {
            let (key, v) = exec::split_set(s)?;
            Ok(Axis {
                key,
                values: values(&v)?,
            })
        })
        .collect::<Result<_>>()?;
    for (i, axis) in axes.iter().enumerate() {
        let key = quoted(&axis.key);
        if axes[..i].iter().any(|a| a.key == axis.key) {
            bail!("--set {key} is given twice: give all its values in one (--set {key}=a,b,c)");
        }
        if axis.values.is_empty() {
            bail!("--set {key}: no values");
        }
    }
    Ok(axes)
}

/// Names the `stale` run folders an earlier sweep left and this one
/// removed.
fn say_removed(stale: &[String]) -> Result<()> {
    if let (Some(first), Some(last)) = (stale.first(), stale.last()) {
        let folders = if stale.len() == 1 {
            first.clone()
        } else {
            format!("{first} … {last} ({} folders)", stale.len())
        };
        crate::say!("removed an earlier sweep's {folders}, not in {TABLE}")?;
    }
    Ok(())
}

/// The folder of run `k`.
fn run_folder(k: usize) -> String {
    format!("run-{k:05}")
}

/// The run numbers the table in `out` lists (none without a table).
fn listed_runs(out: &Path) -> Result<Vec<usize>> {
    let path = out.join(TABLE);
    if !path.exists() {
        return Ok(Vec::new());
    }
    Ok(read_table(&path)?.1.into_iter().map(|(k, _)| k).collect())
}

/// Removes the run folders of `earlier` (the runs an earlier sweep's table
/// listed) that are not those of `runs`; returns their names, sorted. A
/// folder no table listed is not a sweep's, and stays.
fn remove_earlier_runs(
    out: &Path,
    earlier: &[usize],
    runs: impl Iterator<Item = usize>,
) -> Result<Vec<String>> {
    let ours: std::collections::HashSet<usize> = runs.collect();
    let mut stale = Vec::new();
    for &k in earlier.iter().filter(|k| !ours.contains(k)) {
        let dir = out.join(run_folder(k));
        if dir.is_dir() {
            fs::remove_dir_all(&dir).with_context(|| format!("cannot remove {}", dir.display()))?;
            stale.push(run_folder(k));
        }
    }
    stale.sort();
    Ok(stale)
}

fn write_manifest(out: &Path, manifest: &Manifest) -> Result<()> {
    let text = format!(
        "# The sweep in this folder (morphogen sweep; --merge joins only shards of one sweep)\n{}",
        toml::to_string(manifest).context("cannot render the sweep manifest")?
    );
    write_atomic(&out.join(MANIFEST), text.as_bytes())
}

fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join(MANIFEST);
    let bytes = morphogen_scenario::read_at_most(&path, 1 << 24, "scenario::MAX_FILE_BYTES")
        .map_err(|e| {
            anyhow!(
                "cannot read {}: {e} (a folder `morphogen sweep` wrote has one)",
                path.display()
            )
        })?;
    let text =
        String::from_utf8(bytes).map_err(|_| anyhow!("{}: not UTF-8 text", path.display()))?;
    let manifest: Manifest = toml::from_str(&text)
        .with_context(|| format!("{} is not a sweep manifest", path.display()))?;
    let product = manifest
        .axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.len()));
    if product != Some(manifest.runs) || manifest.runs == 0 || manifest.runs > MAX_RUNS {
        bail!(
            "{}: its {} runs are not the combinations of its values",
            path.display(),
            manifest.runs
        );
    }
    Ok(manifest)
}

/// A table's header and its rows by run number.
fn read_table(path: &Path) -> Result<(String, Vec<(usize, String)>)> {
    let bytes = morphogen_scenario::read_at_most(path, 1 << 30, "1 GiB")
        .map_err(|e| anyhow!("cannot read {}: {e}", path.display()))?;
    let text =
        String::from_utf8(bytes).map_err(|_| anyhow!("{}: not UTF-8 text", path.display()))?;
    let mut lines = text.lines();
    let header = lines
        .next()
        .ok_or_else(|| anyhow!("{} is empty", path.display()))?
        .to_string();
    let rows = lines
        .enumerate()
        .map(|(n, line)| {
            let k = line
                .split(',')
                .next()
                .and_then(|k| k.parse().ok())
                .ok_or_else(|| anyhow!("{}:{}: no run number", path.display(), n + 2))?;
            Ok((k, line.to_string()))
        })
        .collect::<Result<_>>()?;
    Ok((header, rows))
}

/// The record kinds counted in the table, in column order.
const KINDS: [&str; 9] = [
    "frame_start",
    "point",
    "segment",
    "polygon",
    "mesh_vertex",
    "triangle",
    "cell",
    "sample",
    "ring",
];

fn header(axes: &[Axis]) -> String {
    let mut h = String::from("run");
    for a in axes.iter().filter(|a| a.key != "seed") {
        let _ = write!(h, ",{}", csv(&a.key));
    }
    h.push_str(",seed,frames,bytes,stream_digest");
    for k in KINDS {
        let _ = write!(h, ",n_{k}");
    }
    h.push_str(",last_frame_cells_by_type,morphogen\n");
    h
}

fn csv(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

fn one_run(plan: &Plan, k: usize, out: &Path) -> Result<String> {
    let (scenario, seed) = plan.scenario(k)?;
    let run = exec::run(&scenario, seed, false)?;
    let dir = out.join(run_folder(k));
    fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    write_atomic(&dir.join(RUN_STREAM), &run.stream)?;
    write_atomic(
        &dir.join("scenario.toml"),
        scenario.self_contained().as_bytes(),
    )?;
    Ok(plan.line(k, &run.stream))
}

/// A run folder's stream.
const RUN_STREAM: &str = "stream.bin";

/// Run `k`'s row of the table (without its line end): its values, then
/// what its stream holds (the seed from its header).
fn row(k: usize, chosen: &[(String, String)], stream: &[u8]) -> String {
    let mut counts: BTreeMap<&str, u64> = BTreeMap::new();
    let mut last_cells: BTreeMap<u8, u64> = BTreeMap::new();
    let (mut frames, mut seed) = (0u32, 0u64);
    for d in Decoder::new(stream) {
        if let Ok(r) = &d.result {
            frames += 1;
            *counts.entry(r.kind()).or_insert(0) += 1;
            match r {
                Record::Header(h) => seed = h.seed,
                Record::FrameStart { .. } => last_cells.clear(),
                Record::Cell { kind, .. } => *last_cells.entry(*kind).or_insert(0) += 1,
                _ => {}
            }
        }
    }
    let mut row = k.to_string();
    for (_, v) in chosen.iter().filter(|(k, _)| k != "seed") {
        let _ = write!(row, ",{}", csv(v));
    }
    let _ = write!(
        row,
        ",{seed},{frames},{},{:016x}",
        stream.len(),
        StreamDigest::of(stream)
    );
    for kind in KINDS {
        let _ = write!(row, ",{}", counts.get(kind).copied().unwrap_or(0));
    }
    let cells: Vec<String> = last_cells.iter().map(|(t, n)| format!("{t}:{n}")).collect();
    let _ = write!(row, ",{}", cells.join(" "));
    row
}

/// Joins the shards of one sweep: their manifests agree, every row is its
/// run's (rebuilt from the run folder's stream and compared), no run is
/// there twice or missing; the run folders are copied into `out`, so that
/// it holds every run its table lists.
fn merge(dirs: &[PathBuf], out: &Path) -> Result<crate::Outcome> {
    let _lock = FolderLock::take(out)?;
    let mut first: Option<(Manifest, String)> = None;
    let mut rows: BTreeMap<usize, (String, PathBuf)> = BTreeMap::new();
    for dir in dirs {
        let manifest = read_manifest(dir)?;
        let path = dir.join(TABLE);
        let (header, table) = read_table(&path)?;
        match &first {
            None => first = Some((manifest.clone(), header.clone())),
            Some((m, _)) if !m.same_sweep(&manifest) => bail!(
                "{} is a shard of another sweep than {} (its scenario or its values differ): only shards of one sweep merge",
                dir.display(),
                dirs[0].display()
            ),
            Some((_, h)) if *h != header => {
                bail!(
                    "{}: its columns differ from the first table's",
                    path.display()
                )
            }
            Some(_) => {}
        }
        for (line_no, (k, line)) in table.into_iter().enumerate() {
            let at = format!("{}:{}", path.display(), line_no + 2);
            if k >= manifest.runs {
                bail!("{at}: run {k} is past the sweep's {} runs", manifest.runs);
            }
            let stream_path = dir.join(run_folder(k)).join(RUN_STREAM);
            let stream = morphogen_scenario::read_at_most(
                &stream_path,
                u64::from(exec::DEFAULT_MAX_STREAM_MB) << 20,
                "the default --max-stream-mb",
            )
            .map_err(|e| anyhow!("{at}: run {k}: cannot read {}: {e}", stream_path.display()))?;
            // The last column names the Morphogen that ran it.
            let values = line.rsplit_once(',').map_or(line.as_str(), |(v, _)| v);
            if row(k, &combination(k, &manifest.axes), &stream) != values {
                bail!(
                    "{at}: run {k}'s row is not what its stream {} holds (an edited table, or a run of another sweep)",
                    stream_path.display()
                );
            }
            if rows.insert(k, (line, dir.clone())).is_some() {
                bail!("{at}: run {k} is in two tables");
            }
        }
    }
    let Some((mut manifest, header)) = first else {
        bail!("nothing to merge");
    };
    if rows.len() != manifest.runs {
        let missing = (0..manifest.runs)
            .find(|k| !rows.contains_key(k))
            .unwrap_or(0);
        bail!(
            "the tables hold {} of the sweep's {} runs (run {missing} is in none): a shard is missing",
            rows.len(),
            manifest.runs
        );
    }
    let here = fs::canonicalize(out).with_context(|| format!("cannot read {}", out.display()))?;
    for (k, (_, dir)) in &rows {
        if fs::canonicalize(dir).ok().as_deref() != Some(here.as_path()) {
            copy_run(&dir.join(run_folder(*k)), &out.join(run_folder(*k)))?;
        }
    }
    let mut table = header;
    table.push('\n');
    for (line, _) in rows.values() {
        table.push_str(line);
        table.push('\n');
    }
    manifest.shard = "1/1".to_string();
    write_manifest(out, &manifest)?;
    write_atomic(&out.join(TABLE), table.as_bytes())?;
    crate::say!("{} runs -> {}", rows.len(), out.join(TABLE).display())?;
    Ok(crate::Outcome::Ok)
}

/// Copies a run folder's files (its stream and scenario) to `to`.
fn copy_run(from: &Path, to: &Path) -> Result<()> {
    fs::create_dir_all(to).with_context(|| format!("cannot create {}", to.display()))?;
    for name in [RUN_STREAM, "scenario.toml"] {
        crate::atomic::copy(&from.join(name), &to.join(name))?;
    }
    Ok(())
}
