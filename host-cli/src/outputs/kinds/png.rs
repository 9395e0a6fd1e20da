//! `png`: still pictures — a frame's, a montage of frames, the run's —
//! and charts as bitmaps (every `*.png` but `animation.png`), each
//! encoded here: RGB or indexed as its pixels are (a bit a pixel as
//! RGB).

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, Pixels, Product};
use crate::outputs::chart::{Chart, write_png};
use crate::outputs::picture::{save_indexed, save_rgb};

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

    fn picture(&self, pixels: &Pixels<'_>, dir: &Path, stem: &str) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{stem}.png"));
        let (w, h) = pixels.size();
        match *pixels {
            Pixels::Rgb { rgb, .. } => save_rgb(w, h, rgb, &path)?,
            Pixels::Indexed {
                palette, indices, ..
            } => save_indexed(w, h, palette, indices, &path)?,
            Pixels::Bits { .. } => save_rgb(w, h, &pixels.rgb(), &path)?,
        }
        Ok(Some(path))
    }
}
