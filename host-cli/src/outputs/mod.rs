//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model's module states its products (`driver::Products`:
//! frame → mesh, frame → picture with its label, frames → montage, frame
//! → tables of its own, run → charts, tables, pictures and texts) and
//! one driver hands them to the kinds of file `--only` asks for (and to
//! those written with any: a summary, a mask), each kind a module of
//! [`kinds`] that writes the products it takes; [`write()`] picks the
//! model by the preset's. The driver reads the records in passes over a [`Records`]
//! source (the stream file, read back frame by frame), one frame or day
//! at a time, so its memory is that of the frames in hand and their
//! pictures, never that of the stream. The L-system's plant is the one
//! model with its own writer (`plant`): its last frame can be larger than
//! memory allows to hold, so it is streamed into its OBJ and drawn from
//! depth-sorted runs spilled to disk.

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::preset::{Model, Preset};
use morphogen_scenario::Scenario;

use crate::records::Records;

pub use self::kinds::{Kinds, Product};

pub mod animation;
pub mod body;
pub mod bones;
pub mod chart;
pub mod curve;
pub(crate) mod driver;
pub mod fill;
pub mod horn;
pub mod kinds;
pub mod mesh;
pub mod montage;
pub mod mosaic;
pub mod normals;
pub mod numbered;
pub mod picture;
pub(crate) mod pipeline;
pub mod plant;
pub mod plot;
pub mod raster;
pub(crate) mod slots;
pub mod tip_bend;

/// Writes the files natural to `scenario`'s model into `dir`, of the
/// `kinds` given; returns their paths.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    scenario: &Scenario,
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let names: Vec<&str> = scenario.file().mosaic.as_ref().map_or_else(Vec::new, |m| {
        m.types.iter().map(|t| t.name.as_str()).collect()
    });
    scenario.with_preset(|preset| write_preset(preset, &names, records, dir, kinds))
}

/// The inks of the main pictures, for a rig preview in their colours
/// (`--rig WxH`): a mosaic's type colours, an L-system's colour ramp;
/// `None` for the models whose pictures are shaded (the rig keeps its own
/// palette).
#[must_use]
pub fn rig_inks(scenario: &Scenario) -> Option<Vec<[u8; 3]>> {
    scenario.with_preset(|preset| match preset.model {
        Model::Mosaic(p) => Some(p.types.iter().map(|t| t.colour).collect()),
        Model::LSystem(_) => Some((0..=plant::LAST_COLOUR).map(plant::palette).collect()),
        Model::GrowthCurve(_) | Model::Horn(_) | Model::Body(_) | Model::Bones(_) => None,
    })
}

/// [`write`] for the run `preset`, its mosaic's types named `names`.
fn write_preset<R: Records + ?Sized>(
    preset: &Preset<'_>,
    names: &[&str],
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    match preset.model {
        Model::GrowthCurve(_) => curve::write(records, dir, kinds),
        Model::Horn(p) => horn::write(records, dir, p, kinds),
        Model::LSystem(_) => plant::write(records, dir, kinds),
        Model::Body(p) => {
            let binding = morphogen::body::binding_summary::<
                { morphogen_scenario::body_files::USER_CYLINDERS },
            >(p.model, p.table)
            .ok();
            body::write(preset.name, records, dir, binding, Some(p.table), kinds)
        }
        Model::Bones(p) => bones::write(preset.name, p, records, dir, kinds),
        Model::Mosaic(p) if p.surface.is_some() => {
            mosaic::on_mesh::write(p, names, records, dir, kinds)
        }
        Model::Mosaic(p) => mosaic::write(p, names, records, dir, kinds),
    }
}
