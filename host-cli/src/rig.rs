//! `morphogen run … --rig WxH[:grey4|:mono]`: the picture a display rig of
//! that size would show at the end of the run, drawn by the core's rig
//! renderer ([`morphogen::rig`]) — the same code a device runs — into an
//! in-memory `embedded-graphics` framebuffer, and saved as a PNG. `:grey4`
//! draws in the 16 greys of a 4-bit OLED ([`PALETTE_GRAY4`], saved as
//! 8-bit grey `17·level`, as QEMU shows its emulated SSD0323), the
//! firmware's picture pixel for pixel; `:mono` as firmware-rp2040 draws its
//! monochrome SSD1306 ([`PALETTE_MONO`]), and every frame's display RAM
//! beside it ([`render_ssd1306`]).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen::rig::embedded_graphics::Pixel;
use morphogen::rig::embedded_graphics::pixelcolor::{Gray4, GrayColor, Rgb888};
use morphogen::rig::embedded_graphics::prelude::*;
use morphogen::rig::{Bounds, PALETTE_GRAY4, PALETTE_RGB888, Receiver, Rig, View, plane_bytes};
use morphogen::stream::{FrameError, Header, Record};

use crate::atomic::OutputFile;
use crate::records::{Place, Records};
use crate::ws2812::{Chain, ChainFile};

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

    /// An enlarged picture of the rig as it looks lit: each pixel `scale`
    /// pixels wide, drawn as a round LED on a dark board for an LED matrix
    /// ([`RigPalette::Rgb`]), as a square with a thin gap for an OLED
    /// ([`RigPalette::Grey4`]).
    #[must_use]
    pub fn preview(&self, palette: RigPalette, scale: u32) -> Framebuffer {
        let board = Rgb888::new(18, 18, 18);
        let mut big = Framebuffer::new(self.width * scale, self.height * scale);
        // Twice the offset from a pixel's centre, in 1/2 px, per sub-pixel.
        let centre = i64::from(scale) - 1;
        let radius2 = (i64::from(scale) * 9 / 10).pow(2);
        let lit = |dx: u32, dy: u32| match palette {
            RigPalette::Rgb => {
                let (x, y) = (2 * i64::from(dx) - centre, 2 * i64::from(dy) - centre);
                x * x + y * y <= radius2
            }
            RigPalette::Grey4 | RigPalette::Mono => scale < 4 || (dx + 1 < scale && dy + 1 < scale),
        };
        for (i, c) in big.pixels.iter_mut().enumerate() {
            let (x, y) = (i as u32 % big.width, i as u32 / big.width);
            let colour = self.get(x / scale, y / scale).unwrap_or(board);
            *c = if lit(x % scale, y % scale) {
                colour
            } else {
                board
            };
        }
        big
    }

    /// The framebuffer as a monochrome SSD1306's display RAM: ⌈H/8⌉ pages
    /// of W bytes, bit `k` of a byte the pixel `k` rows below its page's
    /// top, set where the pixel is not black.
    #[must_use]
    pub fn ssd1306_pages(&self) -> Vec<u8> {
        let pages = self.height.div_ceil(8);
        let mut ram = vec![0u8; pages as usize * self.width as usize];
        for (i, byte) in ram.iter_mut().enumerate() {
            let (page, x) = (i as u32 / self.width, i as u32 % self.width);
            for bit in 0..8 {
                if self
                    .get(x, page * 8 + bit)
                    .is_some_and(|c| c != Rgb888::BLACK)
                {
                    *byte |= 1 << bit;
                }
            }
        }
        ram
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

/// The colours a rig draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RigPalette {
    /// [`PALETTE_RGB888`]: an RGB LED matrix or colour display.
    Rgb,
    /// [`PALETTE_GRAY4`]: a 4-bit grey OLED (the firmware's SSD0323).
    Grey4,
    /// [`PALETTE_MONO`]: a monochrome OLED (firmware-rp2040's SSD1306).
    Mono,
}

/// A monochrome OLED's palette as firmware-rp2040 draws it
/// (`firmware-rp2040/src/screen.rs`): the background dark, ink `n` lit
/// when `n` is even and dark when odd, in white and black.
pub const PALETTE_MONO: [Rgb888; 3] = [Rgb888::BLACK, Rgb888::WHITE, Rgb888::BLACK];

impl RigPalette {
    /// The palette as RGB: greys as `17·level` on all three channels.
    #[must_use]
    pub fn colours(self) -> Vec<Rgb888> {
        match self {
            RigPalette::Rgb => PALETTE_RGB888.to_vec(),
            RigPalette::Grey4 => PALETTE_GRAY4
                .map(|g: Gray4| {
                    let v = g.luma() * 17;
                    Rgb888::new(v, v, v)
                })
                .to_vec(),
            RigPalette::Mono => PALETTE_MONO.to_vec(),
        }
    }
}

/// A rig: its size in pixels, its palette and, for a WS2812 matrix, its
/// chain (`--rig WxH[:grey4]`, `--rig WxH:ws2812[:LAYOUT][:B]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RigSpec {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// The colours.
    pub palette: RigPalette,
    /// The WS2812 chain whose bytes are written per frame, if any.
    pub chain: Option<Chain>,
}

impl RigSpec {
    /// The display's size and the margin a fitted view leaves (1 px when
    /// there is room, as the firmware's); refuses a size out of range.
    ///
    /// # Errors
    /// A side of 0 or more than [`MAX_RIG_SIDE`].
    pub fn checked(&self) -> Result<(Size, u32)> {
        let RigSpec { width, height, .. } = *self;
        if width == 0 || height == 0 || width > MAX_RIG_SIDE || height > MAX_RIG_SIDE {
            bail!("a rig must be 1..={MAX_RIG_SIDE} pixels per side, not {width}x{height}");
        }
        Ok((Size::new(width, height), u32::from(width.min(height) >= 16)))
    }

    /// The picture's file name: `rig-WxH.png`, `rig-WxH-grey4.png` or
    /// `rig-WxH-mono.png`.
    #[must_use]
    pub fn file_name(&self) -> String {
        format!("{}.png", self.stem())
    }

    /// The WS2812 chain's bytes' file name: `rig-WxH-ws2812.bin`.
    #[must_use]
    pub fn chain_name(&self) -> String {
        format!("rig-{}x{}-ws2812.bin", self.width, self.height)
    }

    /// The display RAM's file name: `rig-WxH-ssd1306.bin`.
    #[must_use]
    pub fn ssd1306_name(&self) -> String {
        format!("rig-{}x{}-ssd1306.bin", self.width, self.height)
    }

    /// The enlarged preview's file name: `rig-WxH[-grey4|-mono]-preview.png`.
    #[must_use]
    pub fn preview_name(&self) -> String {
        format!("{}-preview.png", self.stem())
    }

    fn stem(&self) -> String {
        let suffix = match self.palette {
            RigPalette::Rgb => "",
            RigPalette::Grey4 => "-grey4",
            RigPalette::Mono => "-mono",
        };
        format!("rig-{}x{}{suffix}", self.width, self.height)
    }

    /// How much the preview enlarges: about 1,024 px across, 2× to 8×.
    #[must_use]
    pub fn preview_scale(&self) -> u32 {
        (1024 / self.width.max(self.height)).clamp(2, 8)
    }
}

/// Parses a rig `WxH` (e.g. `64x64`, `128x64`), optionally followed by
/// `:grey4` for a 4-bit grey OLED, `:mono` for a monochrome one, or by
/// `:ws2812` for an RGB matrix of
/// WS2812 LEDs with its chain's options ([`Chain::parse`]).
///
/// # Errors
/// When it is not two positive integers ≤ [`MAX_RIG_SIDE`] around an `x`,
/// the kind is not `grey4`, `mono` or `ws2812`, or a chain option is wrong.
pub fn parse_rig(text: &str) -> Result<RigSpec> {
    let mut parts = text.split(':');
    let size = parts.next().unwrap_or_default();
    let options: Vec<&str> = parts.collect();
    let (palette, chain) = match options.split_first() {
        None => (RigPalette::Rgb, None),
        Some((kind, [])) if kind.trim().eq_ignore_ascii_case("grey4") => (RigPalette::Grey4, None),
        Some((kind, [])) if kind.trim().eq_ignore_ascii_case("mono") => (RigPalette::Mono, None),
        Some((kind, rest)) if kind.trim().eq_ignore_ascii_case("ws2812") => {
            (RigPalette::Rgb, Some(Chain::parse(rest)?))
        }
        Some((kind, _)) => bail!(
            "unknown rig {kind:?}: grey4 (a 4-bit grey OLED, e.g. 128x64:grey4), mono (a monochrome OLED, e.g. 128x64:mono) or ws2812 (an LED matrix, e.g. 16x16:ws2812)"
        ),
    };
    let parsed = size
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((width, height))
            if (1..=MAX_RIG_SIDE).contains(&width) && (1..=MAX_RIG_SIDE).contains(&height) =>
        {
            Ok(RigSpec {
                width,
                height,
                palette,
                chain,
            })
        }
        _ => bail!(
            "expected WIDTHxHEIGHT in pixels, each 1..={MAX_RIG_SIDE} (e.g. 64x64, or 128x64:grey4)"
        ),
    }
}

/// The picture `rig` shows after `records`: the view is fitted to the
/// whole stream (1 px margin when there is room), each frame clears the
/// screen, so the last frame is what remains. Two passes: the extent, then
/// the last frame's drawing. An RGB rig draws ink `n` in `inks[n]` when
/// given (the colours of the main pictures), else from
/// [`PALETTE_RGB888`]; a grey one always in [`PALETTE_GRAY4`], as the
/// firmware does.
///
/// # Errors
/// A bad size, a record the renderer refuses, or unreadable records.
pub fn render_rig<R: Records + ?Sized>(
    records: &R,
    rig: RigSpec,
    inks: Option<&[[u8; 3]]>,
) -> Result<Framebuffer> {
    let (fitted, (last_frame, last_index)) = Fitted::new(records, rig, inks)?;
    let mut screen = Framebuffer::new(rig.width, rig.height);
    fitted.draw(records, (last_frame, last_index), &mut screen, |_| Ok(()))?;
    Ok(screen)
}

/// Writes `chain`'s bytes of every frame of `records` on `rig` (as
/// [`render_rig`] draws them) into `dir`; returns the file's path.
///
/// # Errors
/// As [`render_rig`], or a failed write.
pub fn render_chain<R: Records + ?Sized>(
    records: &R,
    rig: RigSpec,
    chain: Chain,
    inks: Option<&[[u8; 3]]>,
    dir: &Path,
) -> Result<PathBuf> {
    let (fitted, _) = Fitted::new(records, rig, inks)?;
    let mut screen = Framebuffer::new(rig.width, rig.height);
    let mut file = ChainFile::create(dir, &rig.chain_name(), chain)?;
    fitted.draw(records, (Place::START, 0), &mut screen, |screen| {
        file.frame((screen.width, screen.height), |x, y| {
            let c = screen.get(x, y).unwrap_or(Rgb888::BLACK);
            [c.r(), c.g(), c.b()]
        })
    })?;
    file.finish()
}

/// Writes into `dir` the display RAM of a monochrome SSD1306 on `rig` for
/// every frame of `records` (as [`render_rig`] draws them in
/// [`PALETTE_MONO`]): `rig-WxH-ssd1306.bin`, per frame ⌈H/8⌉ pages of W
/// bytes, a byte the 8 pixels of a column down its page, the lowest bit
/// on top, lit 1 — what the `ssd1306` crate sends the panel for a frame.
/// Returns the file's path.
///
/// # Errors
/// As [`render_rig`], or a failed write.
pub fn render_ssd1306<R: Records + ?Sized>(
    records: &R,
    rig: RigSpec,
    dir: &Path,
) -> Result<PathBuf> {
    let rig = RigSpec {
        palette: RigPalette::Mono,
        ..rig
    };
    let (fitted, _) = Fitted::new(records, rig, None)?;
    let mut screen = Framebuffer::new(rig.width, rig.height);
    let path = dir.join(rig.ssd1306_name());
    let mut file = OutputFile::create(&path)?;
    fitted.draw(records, (Place::START, 0), &mut screen, |screen| {
        file.write_all(&screen.ssd1306_pages())
            .with_context(|| format!("cannot write {}", path.display()))
    })?;
    file.finish()?;
    Ok(path)
}

/// A rig's view fitted to a whole stream, and its colours.
struct Fitted {
    view: View,
    palette: Vec<Rgb888>,
}

impl Fitted {
    /// The view of `rig` fitted to `records` (1 px margin when there is
    /// room) and the colours it draws with: an RGB rig's ink `n` is
    /// `inks[n]` when given, else from [`PALETTE_RGB888`]; a grey one's is
    /// from [`PALETTE_GRAY4`], as the firmware's. Also where the last
    /// frame starts, and its record's index.
    fn new<R: Records + ?Sized>(
        records: &R,
        rig: RigSpec,
        inks: Option<&[[u8; 3]]>,
    ) -> Result<(Fitted, (Place, usize))> {
        let (size, margin) = rig.checked()?;
        let mut bounds = Bounds::new();
        let (mut last_frame, mut last_index, mut count) = (Place::START, 0usize, 0usize);
        records.visit(Place::START, |place, r| {
            bounds.include(r);
            if matches!(r, Record::FrameStart { .. }) {
                (last_frame, last_index) = (place, count);
            }
            count += 1;
            Ok(())
        })?;
        let palette = match (rig.palette, inks) {
            (RigPalette::Rgb, Some(inks)) if !inks.is_empty() => std::iter::once(Rgb888::BLACK)
                .chain(inks.iter().map(|&[r, g, b]| Rgb888::new(r, g, b)))
                .collect(),
            (palette, _) => palette.colours(),
        };
        let view = View::fit(&bounds, size, margin);
        Ok((Fitted { view, palette }, (last_frame, last_index)))
    }

    /// Draws `records` from `start` (a place and its record's index) on
    /// `screen`, each frame clearing it, and hands `screen` to
    /// `frame_end` as each frame ends. A stream that does not end its
    /// last frame still shows it.
    fn draw<R: Records + ?Sized>(
        &self,
        records: &R,
        (start, index): (Place, usize),
        screen: &mut Framebuffer,
        mut frame_end: impl FnMut(&Framebuffer) -> Result<()>,
    ) -> Result<()> {
        let mut plane = vec![0; plane_bytes(screen.size())];
        let mut rig = Rig::new(self.view, &self.palette, &mut plane);
        let (mut i, mut open) = (index, false);
        records.visit(start, |_, r| {
            rig.draw(r, screen)
                .map_err(|e| anyhow::anyhow!("record {i}: {e}"))?;
            i += 1;
            match r {
                Record::FrameStart { .. } => open = true,
                Record::FrameEnd { .. } => {
                    open = false;
                    frame_end(screen)?;
                }
                _ => {}
            }
            Ok(())
        })?;
        if open {
            rig.draw(&Record::FrameEnd { frame: 0 }, screen)
                .map_err(|e| anyhow::anyhow!("end of stream: {e}"))?;
            frame_end(screen)?;
        }
        Ok(())
    }
}

/// The picture a device that receives the stream of `header` would show
/// on `rig` ([`Receiver`]): its last frame that came whole — `frames` are
/// what a [`morphogen::stream::Reader`] gave after the header, bad frames
/// included — through the view of the stream's extent, or of its readable
/// records' when it was sent without one (a `stream.bin`).
///
/// # Errors
/// A bad size, or a record the renderer refuses.
pub fn render_received(
    header: &Header,
    frames: &[Result<Record, FrameError>],
    rig: RigSpec,
) -> Result<Framebuffer> {
    let (size, margin) = rig.checked()?;
    let (extent, frames) = match frames.split_first() {
        Some((Ok(extent @ Record::Extent { .. }), rest)) => (extent.clone(), rest),
        _ => {
            let mut bounds = Bounds::new();
            frames.iter().flatten().for_each(|r| bounds.include(r));
            (bounds.to_record(), frames)
        }
    };
    let palette = rig.palette.colours();
    let mut plane = vec![0; plane_bytes(size)];
    let mut receiver = Receiver::new(size, margin, &palette, &mut plane);
    let mut screen = Framebuffer::new(size.width, size.height);
    let mut shown = screen.clone();
    let start = [Ok(Record::Header(header.clone())), Ok(extent)];
    for (i, frame) in start.iter().chain(frames).enumerate() {
        let done = receiver
            .take(frame, &mut screen)
            .map_err(|e| anyhow::anyhow!("frame {i}: {e}"))?;
        if done.is_some_and(|d| d.shown) {
            shown.clone_from(&screen);
        }
    }
    Ok(shown)
}

/// Writes into `dir` the PNG `rig` would show after `records` (see
/// [`render_rig`]) and its enlarged preview ([`Framebuffer::preview`]);
/// returns their paths.
///
/// # Errors
/// A bad size, a frame the renderer refuses, unreadable records or a
/// failed write.
pub fn render_rig_png<R: Records + ?Sized>(
    records: &R,
    rig: RigSpec,
    inks: Option<&[[u8; 3]]>,
    dir: &Path,
) -> Result<[PathBuf; 2]> {
    save_rig_png(&render_rig(records, rig, inks)?, rig, dir)
}

/// Writes `picture` of `rig` into `dir` with its enlarged preview; returns
/// their paths.
///
/// # Errors
/// A failed write.
pub fn save_rig_png(picture: &Framebuffer, rig: RigSpec, dir: &Path) -> Result<[PathBuf; 2]> {
    let (path, preview) = (dir.join(rig.file_name()), dir.join(rig.preview_name()));
    picture.save_png(&path)?;
    picture
        .preview(rig.palette, rig.preview_scale())
        .save_png(&preview)?;
    Ok([path, preview])
}

#[cfg(test)]
mod tests {
    use morphogen::fx::Fx;

    use super::*;

    fn rgb(width: u32, height: u32) -> RigSpec {
        RigSpec {
            width,
            height,
            palette: RigPalette::Rgb,
            chain: None,
        }
    }

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
            // Cells of type 1 (ink 1: red) at the bottom left, 2 (green) at the top
            // right: the Voronoi border is their perpendicular bisector.
            Record::Cell {
                id: 0,
                kind: 1,
                p: [fx(0), fx(0)],
            },
            Record::Cell {
                id: 1,
                kind: 2,
                p: [fx(9), fx(5)],
            },
            // Then a white line (ink 0) along the top.
            Record::Segment {
                a: [fx(0), fx(5), Fx::ZERO],
                b: [fx(9), fx(5), Fx::ZERO],
                width: Fx::DELTA,
                colour: 0,
            },
            Record::FrameEnd { frame: 0 },
        ];
        let picture = render_rig(&records, rgb(10, 6), None).unwrap();
        assert_eq!(
            ascii(&picture),
            [
                "##########",
                "RRRRGGGGGG",
                "RRRRRGGGGG",
                // On the bisector to ½ px: the earlier cell keeps it.
                "RRRRRRGGGG",
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
            seg(1),
            Record::FrameEnd { frame: 0 },
            Record::FrameStart {
                frame: 1,
                time: Fx::ONE,
            },
            seg(3),
            Record::FrameEnd { frame: 1 },
        ];
        let picture = render_rig(&records, rgb(4, 1), None).unwrap();
        assert_eq!(ascii(&picture), ["BBBB"]);
        let dir = tempfile::tempdir().unwrap();
        let [path, preview] = render_rig_png(&records, rgb(4, 1), None, dir.path()).unwrap();
        let big = tiny_skia::Pixmap::load_png(&preview).unwrap();
        assert_eq!((big.width(), big.height()), (32, 8));
        let back = tiny_skia::Pixmap::load_png(&path).unwrap();
        assert_eq!((back.width(), back.height()), (4, 1));
        assert_eq!(
            back.pixel(2, 0).map(|p| (p.red(), p.blue())),
            Some((0, 255))
        );
    }

    #[test]
    fn rig_sizes_parse_or_explain() {
        assert_eq!(parse_rig("64x64").unwrap(), rgb(64, 64));
        assert_eq!(parse_rig("128X64").unwrap(), rgb(128, 64));
        let grey = parse_rig("128x64:grey4").unwrap();
        assert_eq!(
            (grey.palette, grey.file_name()),
            (RigPalette::Grey4, "rig-128x64-grey4.png".into())
        );
        for bad in ["64", "0x8", "8x", "x8", "9999x1", "axb"] {
            let e = parse_rig(bad).unwrap_err().to_string();
            assert!(e.contains("WIDTHxHEIGHT"), "{bad}: {e}");
        }
        let e = parse_rig("8x8:sepia").unwrap_err().to_string();
        assert!(e.contains("grey4"), "{e}");
    }

    #[test]
    fn grey4_rigs_draw_seventeen_times_the_level() {
        let picture = render_rig(
            &[
                Record::FrameStart {
                    frame: 0,
                    time: Fx::ZERO,
                },
                Record::Cell {
                    id: 0,
                    kind: 1,
                    p: [Fx::ZERO; 2],
                },
                Record::FrameEnd { frame: 0 },
            ],
            RigSpec {
                palette: RigPalette::Grey4,
                ..rgb(1, 1)
            },
            None,
        )
        .unwrap();
        let level = PALETTE_GRAY4[2].luma() * 17; // ink 1
        assert_eq!(picture.get(0, 0), Some(Rgb888::new(level, level, level)));
    }

    #[test]
    fn mono_rigs_light_even_inks_and_write_each_frame_as_display_ram() {
        // A line in ink 0 (lit) along row 0, then one in ink 7 (dark: an
        // odd ink) over its right half, in each of two frames; the second
        // frame also draws ink 2 (lit) along row 9 of a 4×10 panel.
        let line = |y, x0, colour| Record::Segment {
            a: [Fx::from_int(x0), Fx::from_int(y), Fx::ZERO],
            b: [Fx::from_int(3), Fx::from_int(y), Fx::ZERO],
            width: Fx::DELTA,
            colour,
        };
        let frame = |n, extra: &[Record]| {
            let mut records = vec![
                Record::FrameStart {
                    frame: n,
                    time: Fx::ZERO,
                },
                line(9, 0, 0),
                line(9, 2, 7),
            ];
            records.extend_from_slice(extra);
            records.push(Record::FrameEnd { frame: n });
            records
        };
        let mut records = frame(0, &[]);
        records.extend(frame(1, &[line(0, 0, 2)]));
        let mono = parse_rig("4x10:mono").unwrap();
        assert_eq!(mono.file_name(), "rig-4x10-mono.png");
        assert_eq!(
            ascii(&render_rig(&records, mono, None).unwrap())[..1],
            ["##.."]
        );
        let dir = tempfile::tempdir().unwrap();
        let ram = std::fs::read(render_ssd1306(&records, mono, dir.path()).unwrap()).unwrap();
        // Two frames of two pages of 4 columns; v up is y down: v 9 is the
        // top row (bit 0 of page 0), v 0 the bottom one (bit 1 of page 1).
        assert_eq!(ram, [1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0, 2, 2, 2, 2]);
    }
}
