//! `morphogen run … --rig WxH`: the picture a display rig of that size
//! would show at the end of the run, drawn by the core's rig renderer
//! ([`morphogen::rig`]) — the same code a device runs — into an in-memory
//! `embedded-graphics` framebuffer, and saved as a PNG.

use std::path::Path;

use anyhow::{Context, Result, bail};
use morphogen::rig::embedded_graphics::Pixel;
use morphogen::rig::embedded_graphics::pixelcolor::Rgb888;
use morphogen::rig::embedded_graphics::prelude::*;
use morphogen::rig::{Bounds, CellSlot, PALETTE_RGB888, Rig, View};
use morphogen::stream::Record;

use crate::records::{Place, Records};

/// The largest rig accepted, per side (a 4096×4096 framebuffer is 48 MiB).
pub const MAX_RIG_SIDE: u32 = 4096;

/// An RGB framebuffer of any size, as an `embedded-graphics` draw target.
/// Pixels outside it are ignored, as on a real display driver.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    pixels: Vec<Rgb888>,
}

impl Framebuffer {
    /// A black `width`×`height` framebuffer.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Framebuffer {
        let len = width as usize * height as usize;
        Framebuffer {
            width,
            height,
            pixels: vec![Rgb888::BLACK; len],
        }
    }

    /// The colour at `(x, y)`, if inside.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Option<Rgb888> {
        if x < self.width && y < self.height {
            self.pixels
                .get(y as usize * self.width as usize + x as usize)
                .copied()
        } else {
            None
        }
    }

    /// Rows of RGB bytes, top to bottom.
    #[must_use]
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|c| [c.r(), c.g(), c.b()])
            .collect()
    }

    /// Saves the framebuffer as an 8-bit RGBA PNG (opaque), atomically
    /// (`fixture::write_atomic`: temporary file + rename).
    ///
    /// # Errors
    /// When the PNG cannot be encoded or written.
    pub fn save_png(&self, path: &Path) -> Result<()> {
        let mut pixmap = tiny_skia::Pixmap::new(self.width, self.height)
            .context("a rig of zero width or height")?;
        for (dst, c) in pixmap.pixels_mut().iter_mut().zip(&self.pixels) {
            *dst = tiny_skia::ColorU8::from_rgba(c.r(), c.g(), c.b(), 255).premultiply();
        }
        let png = pixmap.encode_png().context("encoding the rig PNG")?;
        crate::atomic::write_atomic(path, &png)
    }
}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        for Pixel(p, c) in pixels {
            if let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y))
                && x < self.width
                && y < self.height
            {
                self.pixels[y as usize * self.width as usize + x as usize] = c;
            }
        }
        Ok(())
    }
}

/// Parses a rig size `WxH` (e.g. `64x64`, `128x64`).
///
/// # Errors
/// When it is not two positive integers ≤ [`MAX_RIG_SIDE`] around an `x`.
pub fn parse_rig_size(text: &str) -> Result<(u32, u32)> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (1..=MAX_RIG_SIDE).contains(&w) && (1..=MAX_RIG_SIDE).contains(&h) => {
            Ok((w, h))
        }
        _ => bail!(
            "--rig {text:?}: expected WIDTHxHEIGHT in pixels, each 1..={MAX_RIG_SIDE} (e.g. 64x64)"
        ),
    }
}

/// The picture a `width`×`height` rig shows after `records`: the view is
/// fitted to the whole stream (1 px margin when there is room), each frame
/// clears the screen, so the last frame is what remains. Three passes:
/// the extent, then the last frame's cell count, then its drawing.
///
/// # Errors
/// A bad size, a record the renderer refuses, or unreadable records.
pub fn render_rig<R: Records + ?Sized>(
    records: &R,
    width: u32,
    height: u32,
) -> Result<Framebuffer> {
    if width == 0 || height == 0 || width > MAX_RIG_SIDE || height > MAX_RIG_SIDE {
        bail!("a rig must be 1..={MAX_RIG_SIDE} pixels per side, not {width}x{height}");
    }
    let mut bounds = Bounds::new();
    // Only the last frame survives the clears: draw from its start (its
    // place, and its index among the records).
    let (mut last_frame, mut last_index, mut count) = (Place::START, 0usize, 0usize);
    records.visit(Place::START, |place, r| {
        bounds.include(r);
        if matches!(r, Record::FrameStart { .. }) {
            (last_frame, last_index) = (place, count);
        }
        count += 1;
        Ok(())
    })?;
    let margin = u32::from(width.min(height) >= 16);
    let view = View::fit(&bounds, Size::new(width, height), margin);

    // Exactly as many cell slots as the largest frame needs.
    let mut most_cells = 0usize;
    let mut cells_in_frame = 0usize;
    records.visit(last_frame, |_, r| {
        match r {
            Record::FrameStart { .. } => cells_in_frame = 0,
            Record::Cell { .. } => {
                cells_in_frame += 1;
                most_cells = most_cells.max(cells_in_frame);
            }
            _ => {}
        }
        Ok(())
    })?;
    let mut cells = vec![CellSlot::EMPTY; most_cells];
    let mut screen = Framebuffer::new(width, height);
    let mut rig = Rig::new(view, &PALETTE_RGB888, &mut cells);
    let mut i = last_index;
    records.visit(last_frame, |_, r| {
        rig.draw(r, &mut screen)
            .map_err(|e| anyhow::anyhow!("record {i}: {e}"))?;
        i += 1;
        Ok(())
    })?;
    // A stream that does not end its frame still shows its cells.
    rig.draw(&Record::FrameEnd { frame: 0 }, &mut screen)
        .map_err(|e| anyhow::anyhow!("end of stream: {e}"))?;
    Ok(screen)
}

/// Writes to `path` the PNG a `width`×`height` rig would show after
/// `records` (see [`render_rig`]).
///
/// # Errors
/// A bad size, a frame the renderer refuses, unreadable records or a
/// failed write.
pub fn render_rig_png<R: Records + ?Sized>(
    records: &R,
    width: u32,
    height: u32,
    path: &Path,
) -> Result<()> {
    render_rig(records, width, height)?.save_png(path)
}

#[cfg(test)]
mod tests {
    use morphogen::fx::Fx;

    use super::*;

    /// One character per pixel: `.` black, `#` white, `R`/`G`/`B` pure
    /// colours, `?` anything else.
    fn ascii(fb: &Framebuffer) -> Vec<String> {
        (0..fb.height)
            .map(|y| {
                (0..fb.width)
                    .map(|x| match fb.get(x, y).map(|c| (c.r(), c.g(), c.b())) {
                        Some((0, 0, 0)) => '.',
                        Some((255, 255, 255)) => '#',
                        Some((255, 0, 0)) => 'R',
                        Some((0, 255, 0)) => 'G',
                        Some((0, 0, 255)) => 'B',
                        _ => '?',
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn a_small_frame_matches_its_picture() {
        let fx = Fx::from_int;
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            // Cells of type 2 (red) at the bottom left, 3 (green) at the top
            // right: the Voronoi border is their perpendicular bisector.
            Record::Cell {
                id: 0,
                kind: 2,
                p: [fx(0), fx(0)],
            },
            Record::Cell {
                id: 1,
                kind: 3,
                p: [fx(9), fx(5)],
            },
            // Then a white line (colour 1) along the top.
            Record::Segment {
                a: [fx(0), fx(5), Fx::ZERO],
                b: [fx(9), fx(5), Fx::ZERO],
                width: Fx::DELTA,
                colour: 1,
            },
            Record::FrameEnd { frame: 0 },
        ];
        let picture = render_rig(&records, 10, 6).unwrap();
        assert_eq!(
            ascii(&picture),
            [
                "##########",
                "RRRRGGGGGG",
                "RRRRRGGGGG",
                "RRRRRGGGGG",
                "RRRRRRGGGG",
                "RRRRRRGGGG",
            ]
        );
    }

    #[test]
    fn only_the_last_frame_is_shown_and_saved() {
        let seg = |c| Record::Segment {
            a: [Fx::ZERO; 3],
            b: [Fx::from_int(3), Fx::ZERO, Fx::ZERO],
            width: Fx::DELTA,
            colour: c,
        };
        let records = [
            Record::FrameStart {
                frame: 0,
                time: Fx::ZERO,
            },
            seg(2),
            Record::FrameEnd { frame: 0 },
            Record::FrameStart {
                frame: 1,
                time: Fx::ONE,
            },
            seg(4),
            Record::FrameEnd { frame: 1 },
        ];
        let picture = render_rig(&records, 4, 1).unwrap();
        assert_eq!(ascii(&picture), ["BBBB"]);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rig.png");
        render_rig_png(&records, 4, 1, &path).unwrap();
        let back = tiny_skia::Pixmap::load_png(&path).unwrap();
        assert_eq!((back.width(), back.height()), (4, 1));
        assert_eq!(
            back.pixel(2, 0).map(|p| (p.red(), p.blue())),
            Some((0, 255))
        );
    }

    #[test]
    fn rig_sizes_parse_or_explain() {
        assert_eq!(parse_rig_size("64x64").unwrap(), (64, 64));
        assert_eq!(parse_rig_size("128X64").unwrap(), (128, 64));
        for bad in ["64", "0x8", "8x", "x8", "9999x1", "axb"] {
            let e = parse_rig_size(bad).unwrap_err().to_string();
            assert!(e.contains("WIDTHxHEIGHT"), "{bad}: {e}");
        }
    }
}
