//! `morphogen sweep`: the cartesian product of parameter values, run on all
//! cores, one folder per run and one table (`sweep.csv`) for them all. A
//! run's row depends only on its parameters, so the table is the same for
//! any thread count; `--shard I/N` runs every N-th combination (a batch
//! scheduler's array job) and `--merge` joins the shards' tables into the
//! table an unsharded sweep writes.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use morphogen::stream::{Decoder, Record};
use rayon::prelude::*;

use crate::atomic::write_atomic;
use crate::exec;

/// The table a sweep writes into its folder.
pub const TABLE: &str = "sweep.csv";

/// The most runs one sweep may have.
pub const MAX_RUNS: usize = 100_000;

/// Arguments of `morphogen sweep`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The preset or scenario file to sweep.
    #[arg(required_unless_present = "merge")]
    target: Option<String>,
    /// A key and its values: `--set mosaic.days=10,20,30`; `--set
    /// seed=1..8` for seeds 1 to 8. Repeatable: every combination runs,
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
#[derive(Debug, Clone)]
struct Axis {
    key: String,
    values: Vec<String>,
}

/// Splits `a,b,c` at commas outside brackets, braces and quotes;
/// `seed=1..8` style ranges of integers expand.
fn values(text: &str) -> Result<Vec<String>> {
    if let Some((a, b)) = text.split_once("..")
        && let (Ok(a), Ok(b)) = (a.trim().parse::<u64>(), b.trim().parse::<u64>())
    {
        if b < a || b - a >= MAX_RUNS as u64 {
            bail!("{text}: a range a..b needs a ≤ b and at most {MAX_RUNS} values");
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
        bail!("{text}: an empty value");
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
            let value = exec::set_value(k, v).map_err(|e| anyhow!("--set {k}={v}: {e}"))?;
            Ok((k.clone(), value))
        })
        .collect()
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
    let axes: Vec<Axis> = args
        .sets
        .iter()
        .map(|s| {
            let (key, v) = exec::split_set(s)?;
            Ok(Axis {
                key,
                values: values(&v)?,
            })
        })
        .collect::<Result<_>>()?;
    let total = axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
        .filter(|&n| n <= MAX_RUNS)
        .ok_or_else(|| anyhow!("more than {MAX_RUNS} combinations (sweep::MAX_RUNS)"))?;
    let (index, count) = args
        .shard
        .as_deref()
        .map(shard)
        .transpose()?
        .unwrap_or((1, 1));
    let base = exec::find(target, &[])?;
    let combos: Vec<(usize, Vec<(String, String)>)> = (0..total)
        .filter(|k| k % count == index - 1)
        .map(|k| {
            let mut rest = k;
            let mut chosen = vec![(String::new(), String::new()); axes.len()];
            for (slot, axis) in chosen.iter_mut().zip(&axes).rev() {
                let n = axis.values.len();
                *slot = (axis.key.clone(), axis.values[rest % n].clone());
                rest /= n;
            }
            (k, chosen)
        })
        .collect();
    // Check every combination before running any.
    for (_, chosen) in &combos {
        base.clone_with_sets(&scenario_sets(chosen)?)
            .with_context(|| {
                let sets: Vec<String> = chosen.iter().map(|(k, v)| format!("{k}={v}")).collect();
                format!("the combination {}", sets.join(" "))
            })?;
    }
    fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.map_or(0, usize::from))
        .build()
        .context("cannot start the worker threads")?;
    let rows: Vec<Result<String>> = pool.install(|| {
        combos
            .par_iter()
            .map(|(k, chosen)| one_run(&base, *k, chosen, &args.out))
            .collect()
    });
    let mut table = header(&axes);
    for row in rows {
        table.push_str(&row?);
    }
    write_atomic(&args.out.join(TABLE), table.as_bytes())?;
    let stale = remove_earlier_runs(&args.out, combos.iter().map(|(k, _)| *k))?;
    crate::say!(
        "{} of {total} runs (shard {index}/{count}) -> {}",
        combos.len(),
        args.out.join(TABLE).display()
    )?;
    if let (Some(first), Some(last)) = (stale.first(), stale.last()) {
        let folders = if stale.len() == 1 {
            first.clone()
        } else {
            format!("{first} … {last} ({} folders)", stale.len())
        };
        crate::say!("removed an earlier sweep's {folders}, not in {TABLE}")?;
    }
    Ok(crate::Outcome::Ok)
}

/// The folder of run `k`.
fn run_folder(k: usize) -> String {
    format!("run-{k:05}")
}

/// Removes the run folders in `out` that are not those of `runs` (an
/// earlier sweep's, which this one's table does not list); returns their
/// names, sorted.
fn remove_earlier_runs(out: &Path, runs: impl Iterator<Item = usize>) -> Result<Vec<String>> {
    let ours: std::collections::HashSet<String> = runs.map(run_folder).collect();
    let is_run = |name: &str| {
        name.strip_prefix("run-")
            .is_some_and(|k| k.len() == 5 && k.bytes().all(|b| b.is_ascii_digit()))
    };
    let mut stale = Vec::new();
    for entry in fs::read_dir(out).with_context(|| format!("cannot list {}", out.display()))? {
        let entry = entry.with_context(|| format!("cannot list {}", out.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_run(&name) && !ours.contains(&name) && entry.path().is_dir() {
            fs::remove_dir_all(entry.path())
                .with_context(|| format!("cannot remove {}", entry.path().display()))?;
            stale.push(name);
        }
    }
    stale.sort();
    Ok(stale)
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
    h.push_str(",last_frame_cells_by_type\n");
    h
}

fn csv(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

fn one_run(
    base: &morphogen_scenario::Scenario,
    k: usize,
    chosen: &[(String, String)],
    out: &Path,
) -> Result<String> {
    let scenario = base.clone_with_sets(&scenario_sets(chosen)?)?;
    let seed = match chosen.iter().find(|(k, _)| k == "seed") {
        Some((_, v)) => v
            .parse()
            .map_err(|_| anyhow!("--set seed={v}: a seed is a whole number"))?,
        None => scenario.seed(),
    };
    let run = exec::run(&scenario, seed, false)?;
    let dir = out.join(run_folder(k));
    fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    write_atomic(&dir.join("stream.bin"), &run.stream)?;
    write_atomic(
        &dir.join("scenario.toml"),
        scenario.self_contained().as_bytes(),
    )?;
    let mut counts: BTreeMap<&str, u64> = BTreeMap::new();
    let mut last_cells: BTreeMap<u8, u64> = BTreeMap::new();
    for d in Decoder::new(&run.stream) {
        if let Ok(r) = &d.result {
            *counts.entry(r.kind()).or_insert(0) += 1;
            match r {
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
        ",{seed},{},{},{:016x}",
        run.frames,
        run.stream.len(),
        run.digest
    );
    for kind in KINDS {
        let _ = write!(row, ",{}", counts.get(kind).copied().unwrap_or(0));
    }
    let cells: Vec<String> = last_cells.iter().map(|(t, n)| format!("{t}:{n}")).collect();
    let _ = writeln!(row, ",{}", cells.join(" "));
    Ok(row)
}

/// Joins shard tables: same header, rows by run number, none twice.
fn merge(dirs: &[PathBuf], out: &Path) -> Result<crate::Outcome> {
    let mut header: Option<String> = None;
    let mut rows: BTreeMap<usize, String> = BTreeMap::new();
    for dir in dirs {
        let path = dir.join(TABLE);
        let text =
            fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
        let mut lines = text.lines();
        let h = lines
            .next()
            .ok_or_else(|| anyhow!("{} is empty", path.display()))?;
        match &header {
            None => header = Some(h.to_string()),
            Some(first) if first != h => {
                bail!(
                    "{}: its columns differ from the first table's",
                    path.display()
                )
            }
            Some(_) => {}
        }
        for (n, line) in lines.enumerate() {
            let k: usize = line
                .split(',')
                .next()
                .and_then(|k| k.parse().ok())
                .ok_or_else(|| anyhow!("{}:{}: no run number", path.display(), n + 2))?;
            if rows.insert(k, line.to_string()).is_some() {
                bail!("{}: run {k} is in two tables", path.display());
            }
        }
    }
    let mut table = header.unwrap_or_default();
    table.push('\n');
    for row in rows.values() {
        table.push_str(row);
        table.push('\n');
    }
    if let Some(&last) = rows.keys().last()
        && last + 1 != rows.len()
    {
        bail!(
            "the tables hold {} runs but run numbers go to {last}: a shard is missing",
            rows.len()
        );
    }
    fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    write_atomic(&out.join(TABLE), table.as_bytes())?;
    crate::say!("{} runs -> {}", rows.len(), out.join(TABLE).display())?;
    Ok(crate::Outcome::Ok)
}
