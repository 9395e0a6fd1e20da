//! Which frames an `animation.png` shows (its slots), and the animation
//! those frames fill in order while parallel workers draw them.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;

use anyhow::{Result, anyhow, bail};

use super::animation::{self, AnimationWriter, Pixels};

/// The most frames an `animation.png` shows: a run with more frames is
/// subsampled evenly (first and last kept), each frame labelled with its
/// own time.
pub const MAX_ANIMATION_FRAMES: usize = 60;

/// Milliseconds each animation frame is shown.
pub const ANIMATION_DELAY_MS: u16 = 200;

/// Which of `count` frames (by position) an animation shows, rising: all
/// of them, or [`MAX_ANIMATION_FRAMES`] spread evenly from the first to
/// the last.
#[must_use]
pub fn animation_frames(count: usize) -> Vec<usize> {
    if count <= MAX_ANIMATION_FRAMES {
        return (0..count).collect();
    }
    let slots = MAX_ANIMATION_FRAMES - 1;
    (0..=slots).map(|i| i * (count - 1) / slots).collect()
}

/// An `animation.png` fed by parallel workers: frame `k` may arrive
/// before frame `k − 1` and waits (as its RGB bytes) until the frames
/// before it are written, so only the frames in flight are held.
pub(crate) struct OrderedAnimation {
    state: Mutex<OrderedState>,
    /// Whether its frames are indices into a palette.
    indexed: bool,
}

struct OrderedState {
    writer: Option<AnimationWriter>,
    next: usize,
    waiting: BTreeMap<usize, (Vec<u8>, String)>,
}

impl OrderedAnimation {
    /// An animation of `frames` frames of `width × height` RGB pixels at
    /// `path`.
    pub(crate) fn new(path: &Path, width: u32, height: u32, frames: usize) -> Result<Self> {
        let frames = u32::try_from(frames)?;
        let writer =
            AnimationWriter::new(path, width, height, Pixels::Rgb, frames, ANIMATION_DELAY_MS)?;
        Ok(Self::writing(writer, false))
    }

    fn writing(writer: AnimationWriter, indexed: bool) -> Self {
        OrderedAnimation {
            indexed,
            state: Mutex::new(OrderedState {
                writer: Some(writer),
                next: 0,
                waiting: BTreeMap::new(),
            }),
        }
    }

    /// [`OrderedAnimation::new`] for frames of indices into `palette`
    /// ([`AnimationWriter::indexed`]); `None` when `palette` has more
    /// colours than an indexed animation's labels leave room for.
    pub(crate) fn indexed(
        path: &Path,
        (width, height): (u32, u32),
        palette: &[[u8; 3]],
        frames: usize,
    ) -> Result<Option<Self>> {
        if palette.len() > animation::LabelPalette::MAX_COLOURS {
            return Ok(None);
        }
        let frames = u32::try_from(frames)?;
        let writer =
            AnimationWriter::indexed(path, width, height, palette, frames, ANIMATION_DELAY_MS)?;
        Ok(Some(Self::writing(writer, true)))
    }

    /// Whether its frames are indices ([`OrderedAnimation::indexed`]).
    pub(crate) fn is_indexed(&self) -> bool {
        self.indexed
    }

    /// Hands over frame `slot` (0-based among the animation's frames):
    /// its RGB bytes, or its indices for [`OrderedAnimation::indexed`].
    pub(crate) fn frame(&self, slot: usize, rgb: Vec<u8>, label: String) -> Result<()> {
        let mut state = self
            .state
            .lock()
            .map_err(|_| anyhow!("an animation writer stopped"))?;
        state.waiting.insert(slot, (rgb, label));
        loop {
            let next = state.next;
            let Some((rgb, label)) = state.waiting.remove(&next) else {
                return Ok(());
            };
            let writer = state
                .writer
                .as_mut()
                .ok_or_else(|| anyhow!("the animation is finished"))?;
            writer.frame(rgb, &label)?;
            state.next += 1;
        }
    }

    /// Ends the file.
    pub(crate) fn finish(self) -> Result<()> {
        let state = self
            .state
            .into_inner()
            .map_err(|_| anyhow!("an animation writer stopped"))?;
        if !state.waiting.is_empty() {
            bail!("animation frames are missing");
        }
        state
            .writer
            .ok_or_else(|| anyhow!("the animation is finished"))?
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn animations_keep_at_most_sixty_frames_first_and_last() {
        assert_eq!(animation_frames(3), vec![0, 1, 2]);
        let many = animation_frames(97);
        assert_eq!(many.len(), MAX_ANIMATION_FRAMES);
        assert_eq!((many[0], many[59]), (0, 96));
        assert!(many.windows(2).all(|w| w[0] < w[1]));
    }
}
