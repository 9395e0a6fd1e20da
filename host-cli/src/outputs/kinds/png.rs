//! `png`: still pictures — a frame's, a montage of frames, the run's —
//! and charts as bitmaps (every `*.png` but `animation.png`).

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, Product};
use crate::outputs::chart::{Chart, write_png};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "png",
    about: "pictures and chart bitmaps",
    by_default: true,
    format: &Png,
};

struct Png;

impl Format for Png {
    fn takes(&self, product: Product) -> bool {
        matches!(
            product,
            Product::FramePicture | Product::Picture | Product::Chart
        )
    }

    fn chart(
        &self,
        chart: &Chart,
        dir: &Path,
        stem: &str,
        (w, h): (u32, u32),
    ) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.png"));
        write_png(chart, &path, w, h)?;
        Ok(Some(path))
    }

    fn picture(
        &self,
        dir: &Path,
        stem: &str,
        save: &mut dyn FnMut(&Path) -> Result<()>,
    ) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.png"));
        save(&path)?;
        Ok(Some(path))
    }
}
