//! `svg`: charts as vector drawings (`*.svg` but `plot.svg`).

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, Product};
use crate::outputs::chart::{Chart, write_svg};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "svg",
    about: "charts",
    by_default: true,
    format: &Svg,
};

struct Svg;

impl Format for Svg {
    fn takes(&self, product: Product) -> bool {
        product == Product::Chart
    }

    fn chart(
        &self,
        chart: &Chart,
        dir: &Path,
        stem: &str,
        (w, h): (u32, u32),
    ) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.svg"));
        write_svg(chart, &path, w, h)?;
        Ok(Some(path))
    }
}
