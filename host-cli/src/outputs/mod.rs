//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model has a module; [`write`] picks it by preset.

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::horn::presets::{RAM_HORN, RAM_HORN_ANIMATION};
use morphogen::stream::Record;

pub mod body;
pub mod bones;
pub mod curve;
pub mod horn;
pub mod mosaic;
pub mod plant;
pub mod plot;

/// Writes the files natural to `preset`'s model into `dir`; returns their
/// paths.
///
/// # Errors
/// When a file cannot be written.
pub fn write(preset: &str, records: &[Record], dir: &Path) -> Result<Vec<PathBuf>> {
    match preset {
        "growth-curve" => curve::write(records, dir),
        "horse-growth" | "cow-growth" | "horse-trot" => body::write_preset(preset, records, dir),
        "ram-horn" => horn::write(records, dir, RAM_HORN.rings_per_module),
        "ram-horn-animation" => horn::write(records, dir, RAM_HORN_ANIMATION.rings_per_module),
        name if morphogen::lsys::presets::ALL
            .iter()
            .any(|(n, _)| *n == name) =>
        {
            plant::write(records, dir)
        }
        name => {
            if let Some(params) = morphogen::bones::presets::find(name) {
                bones::write(name, params, records, dir)
            } else if let Some(params) = morphogen::mosaic::presets::by_name(name) {
                mosaic::write(params, records, dir)
            } else {
                Ok(Vec::new())
            }
        }
    }
}
