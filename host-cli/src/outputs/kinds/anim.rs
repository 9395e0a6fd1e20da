//! `anim`: the frames' pictures as one animated PNG (`animation.png`),
//! indexed when the pictures are and their palette leaves room for the
//! labels' colours, RGB otherwise.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};

use super::{Format, Kind, PictureSeries, Pixels, Product, Sequence};
use crate::outputs::slots::OrderedAnimation;

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "anim",
    about: "animation.png",
    by_default: true,
    format: &Anim,
};

/// The animation's file name.
const ANIMATION: &str = "animation.png";

struct Anim;

impl Format for Anim {
    fn takes(&self, product: Product) -> bool {
        product == Product::Animation
    }

    fn animation(&self, dir: &Path, sequence: &Sequence) -> Result<Option<Box<dyn PictureSeries>>> {
        let path = dir.join(ANIMATION);
        let (size, frames) = (sequence.size, sequence.frames);
        let indexed = match &sequence.palette {
            Some(palette) => OrderedAnimation::indexed(&path, size, palette, frames)?,
            None => None,
        };
        let animation = match indexed {
            Some(indexed) => indexed,
            None => OrderedAnimation::new(&path, size.0, size.1, frames)?,
        };
        Ok(Some(Box::new(Animation { animation, path })))
    }
}

/// `animation.png` being written.
struct Animation {
    animation: OrderedAnimation,
    path: PathBuf,
}

impl PictureSeries for Animation {
    fn frame(&self, slot: usize, pixels: &Pixels<'_>, label: &str) -> Result<()> {
        let bytes = if self.animation.is_indexed() {
            match *pixels {
                Pixels::Indexed { indices, .. } => indices.to_vec(),
                Pixels::Rgb { .. } | Pixels::Bits { .. } => {
                    return Err(anyhow!("an indexed animation's frame has no palette"));
                }
            }
        } else {
            pixels.rgb().into_owned()
        };
        self.animation.frame(slot, bytes, label.to_string())
    }

    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>> {
        self.animation.finish()?;
        Ok(vec![self.path])
    }
}
