//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model has a module; [`write()`] picks it by the preset's
//! model.

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::preset::{Model, Preset};
use morphogen::stream::Record;

pub mod body;
pub mod bones;
pub mod curve;
pub mod horn;
pub mod mosaic;
pub mod picture;
pub mod plant;
pub mod plot;
pub mod raster;
pub mod text;

/// Writes the files natural to `preset`'s model into `dir`; returns their
/// paths.
///
/// # Errors
/// When a file cannot be written.
pub fn write(preset: &Preset<'_>, records: &[Record], dir: &Path) -> Result<Vec<PathBuf>> {
    match preset.model {
        Model::GrowthCurve(_) => curve::write(records, dir),
        Model::Horn(p) => horn::write(records, dir, p.rings_per_module),
        Model::LSystem(_) => plant::write(records, dir),
        Model::Body(p) => {
            let binding = morphogen::body::binding_summary::<
                { morphogen_scenario::body_files::USER_CYLINDERS },
            >(p.model, p.table)
            .ok();
            body::write(preset.name, records, dir, binding)
        }
        Model::Bones(p) => bones::write(preset.name, p, records, dir),
        Model::Mosaic(p) => mosaic::write(p, records, dir),
        _ => Ok(Vec::new()),
    }
}
