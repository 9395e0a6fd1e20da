//! Running a preset into an in-memory stream, with a progress bar on runs
//! longer than a second.

use std::time::{Duration, Instant};

use anyhow::{Result, anyhow};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use morphogen::preset::{self, Preset, Runner};
use morphogen::stream::{ByteSink, Encoder, SinkError};

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
pub fn run(preset: &Preset, seed: u64, progress: bool) -> Result<Run> {
    let mut encoder = Encoder::new(Bytes::default());
    let mut runner = Runner::new();
    let start = Instant::now();
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix} [{bar:40}] {pos}/{len} steps, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_prefix(preset.name);
    let mut shown = false;
    preset::run(preset, seed, &mut runner, &mut encoder, &mut |p| {
        bar.set_length(u64::from(p.total));
        bar.set_position(u64::from(p.done));
        if progress && !shown && start.elapsed() > Duration::from_secs(1) {
            bar.set_draw_target(ProgressDrawTarget::stderr());
            shown = true;
        }
    })
    .map_err(|e| anyhow!("preset {}: {e}", preset.name))?;
    bar.finish_and_clear();
    let digest = encoder.digest();
    let frames = encoder.frames();
    Ok(Run {
        stream: encoder.into_writer().0,
        digest,
        frames,
    })
}

/// The preset called `name`, or an error listing the known ones.
///
/// # Errors
/// When no preset has that name.
pub fn find(name: &str) -> Result<&'static Preset> {
    preset::find(name).ok_or_else(|| {
        let known: Vec<&str> = preset::PRESETS.iter().map(|p| p.name).collect();
        anyhow!("unknown preset '{name}' (known: {})", known.join(", "))
    })
}
