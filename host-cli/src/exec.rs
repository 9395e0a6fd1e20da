//! Running a preset into an in-memory stream, with a progress bar on runs
//! longer than a second. The presets are the core's registry
//! ([`morphogen::preset::PRESETS`], also run by the firmware) followed by
//! the host-only ones ([`HOST_PRESETS`]); [`with_mask`] gives a mosaic
//! preset a user's mask.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use morphogen::mosaic::{Params, presets as mosaics};
use morphogen::preset::{self, Preset, Runner};
use morphogen::sim::Progress;
use morphogen::stream::{ByteSink, Decoder, Encoder, Record, SinkError};

use crate::host_presets::{HOST_PRESETS, HostPreset};

/// A preset of either registry.
#[derive(Debug, Clone, Copy)]
pub enum PresetRef {
    /// A core preset (`morphogen::preset::PRESETS`; runs on the firmware).
    Core(&'static Preset),
    /// A mosaic run on the host: a host-only preset ([`HOST_PRESETS`]), or
    /// any mosaic preset with a user's mask ([`with_mask`]).
    Host(&'static HostPreset),
}

impl PresetRef {
    /// The name used on the command line and in stream headers.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            PresetRef::Core(p) => p.name,
            PresetRef::Host(p) => p.name,
        }
    }

    /// One line for `morphogen list`.
    #[must_use]
    pub fn summary(self) -> &'static str {
        match self {
            PresetRef::Core(p) => p.summary,
            PresetRef::Host(p) => p.summary,
        }
    }

    /// The seed used when none is given.
    #[must_use]
    pub fn default_seed(self) -> u64 {
        match self {
            PresetRef::Core(p) => p.default_seed,
            PresetRef::Host(p) => p.default_seed,
        }
    }

    /// The host-only preset, if this is one.
    #[must_use]
    pub fn host(self) -> Option<&'static HostPreset> {
        match self {
            PresetRef::Core(_) => None,
            PresetRef::Host(p) => Some(p),
        }
    }

    /// The mosaic parameters, if this is a mosaic (MClone) preset.
    #[must_use]
    pub fn mosaic(self) -> Option<&'static Params> {
        match self {
            PresetRef::Core(p) => mosaics::by_name(p.name),
            PresetRef::Host(p) => Some(p.params),
        }
    }
}

/// The mosaic `preset` with its mask replaced by the mask file `file`
/// (PBM or PNG, [`read_mask`](crate::outputs::mosaic::read_mask)): a host
/// preset of the same name and seed whose header's parameter digest is that
/// of the changed parameters. Leaks the parameters: one per run.
///
/// # Errors
/// When `preset` is not a mosaic, or the file is not a usable mask.
pub fn with_mask(preset: PresetRef, file: &Path) -> Result<PresetRef> {
    let params = preset.mosaic().ok_or_else(|| {
        let mosaics: Vec<&str> = all()
            .filter(|p| p.mosaic().is_some())
            .map(PresetRef::name)
            .collect();
        anyhow!(
            "--mask needs a mosaic preset, and '{}' is not one (mosaics: {})",
            preset.name(),
            mosaics.join(", ")
        )
    })?;
    let mask = crate::outputs::mosaic::read_mask(file)?;
    let params = Box::leak(Box::new(Params {
        mask: Some(mask),
        ..*params
    }));
    Ok(PresetRef::Host(Box::leak(Box::new(HostPreset {
        name: preset.name(),
        summary: preset.summary(),
        default_seed: preset.default_seed(),
        params,
    }))))
}

/// Every preset: the core's, then the host-only ones.
pub fn all() -> impl Iterator<Item = PresetRef> + Clone {
    preset::PRESETS
        .iter()
        .map(PresetRef::Core)
        .chain(HOST_PRESETS.iter().map(PresetRef::Host))
}

/// A growable byte sink for the host.
#[derive(Debug, Default)]
pub struct Bytes(pub Vec<u8>);

impl ByteSink for Bytes {
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), SinkError> {
        self.0.extend_from_slice(bytes);
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

/// Runs `preset` with `seed`; shows a progress bar once the run has taken
/// more than a second and `progress` is set.
///
/// # Errors
/// The core's error, with the preset named.
pub fn run(preset: PresetRef, seed: u64, progress: bool) -> Result<Run> {
    let mut encoder = Encoder::new(Bytes::default());
    let start = Instant::now();
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix} [{bar:40}] {pos}/{len} steps, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_prefix(preset.name());
    let mut shown = false;
    let mut report = |p: Progress| {
        bar.set_length(u64::from(p.total));
        bar.set_position(u64::from(p.done));
        if progress && !shown && start.elapsed() > Duration::from_secs(1) {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
    };
    match preset {
        PresetRef::Core(p) => preset::run(p, seed, &mut Runner::new(), &mut encoder, &mut report),
        PresetRef::Host(p) => p.run(seed, &mut encoder, &mut report),
    }
    .map_err(|e| anyhow!("preset {}: {e}", preset.name()))?;
    bar.finish_and_clear();
    let digest = encoder.digest();
    let frames = encoder.frames();
    Ok(Run {
        stream: encoder.into_writer().0,
        digest,
        frames,
    })
}

/// The preset called `name` (core or host-only), or an error listing the
/// known ones.
///
/// # Errors
/// When no preset has that name.
pub fn find(name: &str) -> Result<PresetRef> {
    all().find(|p| p.name() == name).ok_or_else(|| {
        let known: Vec<&str> = all().map(PresetRef::name).collect();
        anyhow!("unknown preset '{name}' (known: {})", known.join(", "))
    })
}

/// Writes a finished run into `dir` (created if missing): `stream.bin`,
/// `records.jsonl`, then the files `model` draws from the decoded records.
/// Returns every path written, in order.
///
/// # Errors
/// When the folder cannot be created or a file cannot be written.
pub fn write_outputs(
    dir: &Path,
    run: &Run,
    model: impl FnOnce(&[Record], &Path) -> Result<Vec<PathBuf>>,
) -> Result<Vec<PathBuf>> {
    fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    let stream_path = dir.join("stream.bin");
    crate::fixture::write_atomic(&stream_path, &run.stream)?;
    let jsonl_path = dir.join("records.jsonl");
    crate::fixture::write_atomic(&jsonl_path, crate::jsonl::stream(&run.stream).as_bytes())?;
    let records: Vec<Record> = Decoder::new(&run.stream)
        .filter_map(|d| d.result.ok())
        .collect();
    let mut written = vec![stream_path, jsonl_path];
    written.extend(model(&records, dir)?);
    Ok(written)
}
