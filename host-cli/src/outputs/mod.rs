//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model has a module; [`write`] picks it by preset.

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::stream::Record;

pub mod curve;
pub mod plot;

/// Writes the files natural to `preset`'s model into `dir`; returns their
/// paths.
///
/// # Errors
/// When a file cannot be written.
pub fn write(preset: &str, records: &[Record], dir: &Path) -> Result<Vec<PathBuf>> {
    match preset {
        "growth-curve" => curve::write(records, dir),
        _ => Ok(Vec::new()),
    }
}
