//! `morphogen run`: a preset, a scenario file or a grammar into its
//! folder: the stream, its records as JSON Lines, the model's own files
//! ([`crate::outputs`]) and, with `--rig`, the picture a display rig shows.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use morphogen_scenario::Scenario;

use crate::folder_lock::FolderLock;
use crate::outputs::{self, Kinds, Product};
use crate::rig::{self, RigPalette, RigSpec};
use crate::{Outcome, body_input, exec, say, written};

/// `morphogen run`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A preset's name (see `morphogen list`) or a scenario file
    /// (`*.toml`); may be omitted with --grammar.
    #[arg(required_unless_present = "grammar")]
    pub target: Option<String>,
    /// Change a parameter: a dotted key of the scenario file and a value
    /// (`--set mosaic.days=20`, `--set horn.modules[0].bend=80`, a
    /// grammar's setting or constant `--set lsystem.delta=30`);
    /// repeatable. A file (`--set bones.grammar=my.lsys`) is relative
    /// to the current folder.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// An L-system grammar file (format: docs/lsystems.md). Alone, it
    /// runs as a plant (plant.png, plant.obj, segments.csv); with an
    /// L-system or bone preset or scenario, it replaces that one's
    /// grammar (a bone preset wraps your skeleton).
    #[arg(long, value_name = "FILE")]
    pub grammar: Option<PathBuf>,
    /// The seed (default: the scenario's own, the one fixtures use).
    #[arg(long)]
    pub seed: Option<u64>,
    /// The output folder (default: `out/NAME`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// With a body scenario: grow this OBJ mesh instead of the built-in
    /// body (needs --cylinders; format: docs/body.md).
    #[arg(
        long,
        value_name = "FILE",
        requires = "cylinders",
        conflicts_with = "grammar"
    )]
    pub mesh: Option<PathBuf>,
    /// The cylinder file for --mesh (docs/body.md).
    #[arg(long, value_name = "FILE", requires = "mesh")]
    pub cylinders: Option<PathBuf>,
    /// Also write rig-WxH.png: the last frame as a W×H display rig
    /// (LED matrix, OLED) shows it, drawn by the core's rig renderer;
    /// `WxH:grey4` draws the 16 greys of a 4-bit OLED, as the firmware
    /// draws its SSD0323 (rig-WxH-grey4.png); `WxH:mono` a monochrome
    /// OLED as firmware-rp2040 draws its SSD1306 (rig-WxH-mono.png), and
    /// every frame's display RAM in rig-WxH-ssd1306.bin. In colour,
    /// mosaics and plants take the colours of their main pictures. Also
    /// writes rig-WxH[-grey4|-mono]-preview.png, enlarged as the LEDs or
    /// the OLED look lit. `WxH:ws2812` also writes rig-WxH-ws2812.bin, the bytes a
    /// chain of WS2812 LEDs wired as that matrix receives for each frame
    /// (green, red, blue; gamma and brightness as smart-leds applies
    /// them): `:serpentine` (the default) or `:progressive` rows, and a
    /// brightness 0 to 255 (default 255), e.g. 16x16:ws2812:64
    /// (docs/stream-format.md, "LED matrices").
    #[arg(long, value_name = "WxH[:grey4|:mono|:ws2812[:LAYOUT][:B]]", value_parser = rig::parse_rig)]
    pub rig: Option<RigSpec>,
    /// With a mosaic: where F cells may start instead of the scenario's
    /// mask, a PBM (P1/P4) or PNG stretched over the whole domain; white
    /// allows F (in a PNG: luminance and alpha both ≥ 50 %).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["grammar", "mesh"])]
    pub mask: Option<PathBuf>,
    /// Stop a run whose stream grows past this many MiB (a runaway
    /// grammar, a huge mosaic).
    #[arg(
        long,
        value_name = "MB",
        default_value_t = exec::DEFAULT_MAX_STREAM_MB,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub max_stream_mb: u32,
    /// Write only these kinds of file (a comma list; `--help` lists them).
    #[arg(long, value_name = "KINDS", value_parser = Kinds::parse, long_help = Kinds::help())]
    pub only: Option<Kinds>,
    /// Print nothing on standard output (no summary, no "wrote"
    /// lines) and show no progress bar; errors still go to standard
    /// error.
    #[arg(long, short)]
    pub quiet: bool,
}

/// What `run` writes and says: the kinds of file, and whether it is quiet.
#[derive(Debug, Clone, Copy)]
struct Writing {
    kinds: Kinds,
    quiet: bool,
}

/// Runs what `args` names, writes its files and says what it wrote.
///
/// # Errors
/// A target that is not one, a bad input file, a run that fails or a
/// file that cannot be written.
pub fn run(args: Args) -> Result<Outcome> {
    let writing = Writing {
        kinds: args.only.unwrap_or(Kinds::DEFAULT),
        quiet: args.quiet,
    };
    match (&args.target, &args.grammar) {
        (target, Some(file)) if target.as_deref().is_none_or(|t| t == "custom") => {
            if let Some(set) = args.sets.first() {
                bail!(
                    "--set {set}: a grammar run on its own has no scenario to change (name a preset or a scenario file, whose grammar --grammar then replaces)"
                );
            }
            run_grammar(
                file,
                args.seed,
                args.out.clone(),
                args.max_stream_mb,
                writing,
            )
        }
        (Some(target), _) => run_target(target, &args, writing),
        (None, _) => {
            bail!("give a preset name (see `morphogen list`), a scenario file, or --grammar FILE")
        }
    }
}

/// `target` with the mask, grammar or body files of `args` in place of
/// its own.
fn run_target(target: &str, args: &Args, writing: Writing) -> Result<Outcome> {
    let scenario = exec::find(target, &exec::parse_sets(&args.sets)?)?;
    let scenario = match &args.mask {
        Some(file) => exec::with_mask(&scenario, file)?,
        None => scenario,
    };
    // What a run's errors name: the user's files too, and its folder is
    // named after them.
    let mut what = scenario.name().to_string();
    let mut out = args.out.clone();
    let name = scenario.name().to_string();
    let beside = |file: &Path, default: &str| {
        let stem = file
            .file_stem()
            .map_or_else(|| default.into(), |s| s.to_string_lossy().into_owned());
        Path::new("out").join(format!("{name}-{stem}"))
    };
    let scenario = match &args.grammar {
        Some(file) => {
            out = out.or_else(|| Some(beside(file, "grammar")));
            what = format!("{what} with the grammar {}", file.display());
            exec::with_grammar(&scenario, file)?
        }
        None => scenario,
    };
    let scenario = match (&args.mesh, &args.cylinders) {
        (Some(mesh), Some(cylinders)) => {
            out = out.or_else(|| Some(beside(mesh, "mesh")));
            what = format!("{what} on {} and {}", mesh.display(), cylinders.display());
            body_input::with_body_files(&scenario, mesh, cylinders)?
        }
        _ => scenario,
    };
    let rig = args.rig;
    run_scenario(
        &scenario,
        &what,
        args.seed,
        out,
        rig,
        args.max_stream_mb,
        writing,
    )
}

/// `scenario` into its folder; its errors name `what`.
fn run_scenario(
    scenario: &Scenario,
    what: &str,
    seed: Option<u64>,
    out: Option<PathBuf>,
    rig: Option<RigSpec>,
    max_stream_mb: u32,
    writing: Writing,
) -> Result<Outcome> {
    exec::warn_unused_seed(scenario, seed);
    let seed = seed.unwrap_or(scenario.seed());
    let folder = Folder::take(
        out.unwrap_or_else(|| Path::new("out").join(scenario.name())),
        writing,
    )?;
    let dir = &folder.dir;
    let run = exec::run_to_file(
        scenario,
        what,
        seed,
        !writing.quiet,
        max_stream_mb,
        folder.paths(writing),
    )?;
    let written = exec::write_outputs(dir, &run, !writing.quiet, |records, dir| {
        let mut files = outputs::write(scenario, records, dir, writing.kinds)?;
        if let Some(rig) = rig {
            let inks = outputs::rig_inks(scenario);
            files.extend(rig::render_rig_png(records, rig, inks.as_deref(), dir)?);
            if let Some(chain) = rig.chain {
                let path = rig::render_chain(records, rig, chain, inks.as_deref(), dir)?;
                files.push(path);
            }
            if rig.palette == RigPalette::Mono {
                files.push(rig::render_ssd1306(records, rig, dir)?);
            }
        }
        Ok(files)
    })?;
    // An earlier run's files of the series this run wrote anew, as they
    // were (their sizes), then gone.
    let stale = outputs::numbered::stale(dir, &written)?;
    let stale_lines = written::lines(&stale);
    outputs::numbered::remove(&stale)?;
    if writing.quiet {
        return Ok(Outcome::Ok);
    }
    say_made(scenario.name(), seed, &run, &written)?;
    for line in stale_lines {
        say!("  removed an earlier run's {line}")?;
    }
    Ok(Outcome::Ok)
}

/// A run's output folder, locked for the run, and where its stream and
/// records go.
struct Folder {
    dir: PathBuf,
    stream: PathBuf,
    jsonl: PathBuf,
    _lock: FolderLock,
}

impl Folder {
    /// Locks `dir` (creating it) and says which files of a stopped run the
    /// lock removed.
    fn take(dir: PathBuf, writing: Writing) -> Result<Folder> {
        let lock = FolderLock::take(&dir)?;
        let (count, bytes) = lock.removed;
        if count > 0 && !writing.quiet {
            say!(
                "removed {count} temporary file(s) ({}) that a stopped run left in {}",
                indicatif::DecimalBytes(bytes),
                dir.display()
            )?;
        }
        Ok(Folder {
            stream: dir.join(exec::STREAM_FILE),
            jsonl: dir.join(exec::JSONL_FILE),
            dir,
            _lock: lock,
        })
    }

    /// The stream file, and the records' file if `writing` asks for it.
    fn paths(&self, writing: Writing) -> exec::RunPaths<'_> {
        exec::RunPaths {
            stream: &self.stream,
            jsonl: writing
                .kinds
                .wants(Product::Records)
                .then_some(self.jsonl.as_path()),
        }
    }
}

/// Says what a run of `name` made: its frames, bytes and digest, and the
/// files written.
fn say_made(
    name: impl std::fmt::Display,
    seed: u64,
    run: &exec::RunFile,
    written: &[PathBuf],
) -> Result<()> {
    say!(
        "{name} seed {seed}: {} frames, {} bytes, digest {:016x}",
        run.frames,
        run.bytes,
        run.digest
    )?;
    written::say_wrote(written)
}

/// A grammar file run on its own, as a plant.
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
    let folder = Folder::take(out.unwrap_or_else(|| Path::new("out").join(&stem)), writing)?;
    let paths = folder.paths(writing);
    let run = exec::run_grammar(file, &text, seed, max_stream_mb, paths, !writing.quiet)?;
    let written = exec::write_outputs(&folder.dir, &run, !writing.quiet, |records, dir| {
        outputs::plant::write(records, dir, writing.kinds)
    })?;
    if !writing.quiet {
        say_made(file.display(), seed, &run, &written)?;
    }
    Ok(Outcome::Ok)
}
