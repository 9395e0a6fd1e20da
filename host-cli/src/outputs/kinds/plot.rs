//! `plot`: the last frame as pen strokes for a plotter (`plot.svg`); not
//! written unless asked for.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, Product};
use crate::outputs::plot::{Drawing, FILE};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "plot",
    about: "plot.svg: the last frame's strokes for a pen plotter, in mm on A4, a layer per pen",
    by_default: false,
    format: &Plot,
};

struct Plot;

impl Format for Plot {
    fn takes(&self, product: Product) -> bool {
        product == Product::Drawing
    }

    fn drawing(&self, drawing: &Drawing, dir: &Path) -> Result<Option<PathBuf>> {
        let path = dir.join(FILE);
        drawing.save(&path)?;
        Ok(Some(path))
    }
}
