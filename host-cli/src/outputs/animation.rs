//! Animated PNG (APNG) files from a run's pictures: frames of one size,
//! each with its label ("day 12", "age 6.0 months") drawn into its
//! top-left corner, shown `delay_ms` apart and looped.
//!
//! [`AnimationWriter`] streams: it holds one frame at a time, so a writer
//! that draws frame after frame never keeps them all. [`Animation`] is the
//! same for frames already at hand. Every frame must have the animation's
//! size (its pixel buffer the exact length): a frame of another size is an
//! error, never padded or cropped, since a padded frame would silently
//! misplace what it shows.
//!
//! Frames are RGB or RGBA samples, or palette indices
//! ([`AnimationWriter::indexed`]: a third of RGB's bytes to compress, the
//! labels' colours added to the palette, their glyph edges in 16 shades).
//!
//! Labels are drawn with the embedded DejaVu Sans face of
//! [`super::chart::font`] (no system font is read): white text on a
//! darkened box, so it reads on light and dark pictures alike. A label
//! wider than the frame is cut at its right edge. The bytes depend only
//! on the frames, the labels and the delay.
//!
//! ```no_run
//! use morphogen_cli::outputs::animation::{AnimationWriter, Pixels};
//!
//! let mut apng = AnimationWriter::new(std::path::Path::new("days.png"), 64, 48, Pixels::Rgb, 3, 250)?;
//! for day in 0..3 {
//!     apng.frame(vec![255; 64 * 48 * 3], &format!("day {day}"))?;
//! }
//! apng.finish()?;
//! # Ok::<(), anyhow::Error>(())
//! ```

use std::fmt;
use std::io::{self, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use ab_glyph::{Font, PxScale, ScaleFont, point};
use anyhow::{Context, Result, anyhow, bail};

use super::chart::font;
use crate::atomic::OutputFile;

/// The largest width or height of an animation, in pixels.
pub const MAX_SIDE: u32 = 16_384;

/// The layout of a frame's pixels: 8-bit samples, row by row, no padding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pixels {
    /// Red, green, blue: 3 bytes a pixel.
    #[default]
    Rgb,
    /// Red, green, blue, alpha (straight, not premultiplied): 4 bytes a
    /// pixel. A label's box is drawn opaque.
    Rgba,
}

impl Pixels {
    /// Bytes a pixel.
    #[must_use]
    pub const fn channels(self) -> usize {
        match self {
            Pixels::Rgb => 3,
            Pixels::Rgba => 4,
        }
    }

    fn colour_type(self) -> png::ColorType {
        match self {
            Pixels::Rgb => png::ColorType::Rgb,
            Pixels::Rgba => png::ColorType::Rgba,
        }
    }
}

/// One picture of an animation and the label drawn into it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// `width × height` pixels in the animation's [`Pixels`] layout.
    pub pixels: Vec<u8>,
    /// Drawn top left, e.g. `day 12`; empty for none.
    pub label: String,
}

/// Frames at hand, to write as one APNG with [`Animation::write`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Animation {
    /// Width of every frame, in pixels.
    pub width: u32,
    /// Height of every frame, in pixels.
    pub height: u32,
    /// Layout of every frame's pixels.
    pub pixels: Pixels,
    /// Time each frame is shown, in milliseconds (0: as fast as the
    /// viewer goes).
    pub delay_ms: u16,
    /// The frames in the order shown; at least one.
    pub frames: Vec<Frame>,
}

impl Animation {
    /// Writes the animation as an APNG at `path`, whole or not at all.
    ///
    /// # Errors
    /// As [`AnimationWriter::new`] and [`AnimationWriter::frame`].
    pub fn write(&self, path: &Path) -> Result<()> {
        let count = u32::try_from(self.frames.len())
            .map_err(|_| anyhow!("an animation has at most {} frames", u32::MAX))?;
        let mut writer = AnimationWriter::new(
            path,
            self.width,
            self.height,
            self.pixels,
            count,
            self.delay_ms,
        )?;
        for frame in &self.frames {
            writer.frame(frame.pixels.as_slice(), &frame.label)?;
        }
        writer.finish()
    }
}

/// The output file, shared between the PNG encoder (which keeps its
/// writer to the end) and [`AnimationWriter::finish`] (which renames it
/// into place).
#[derive(Clone)]
struct SharedFile(Arc<Mutex<Option<OutputFile>>>);

impl SharedFile {
    fn with<T>(&self, f: impl FnOnce(&mut OutputFile) -> io::Result<T>) -> io::Result<T> {
        let mut file = self
            .0
            .lock()
            .map_err(|_| io::Error::other("an earlier write panicked"))?;
        f(file
            .as_mut()
            .ok_or_else(|| io::Error::other("the animation is finished"))?)
    }
}

impl Write for SharedFile {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.with(|f| f.write(bytes))
    }

    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.with(|f| f.write_all(bytes))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.with(Write::flush)
    }
}

/// An APNG being written frame by frame; dropped before
/// [`AnimationWriter::finish`], it leaves no file behind.
pub struct AnimationWriter {
    path: PathBuf,
    file: SharedFile,
    png: png::Writer<SharedFile>,
    width: u32,
    height: u32,
    layout: Layout,
    frames: u32,
    written: u32,
    /// Bytes a frame.
    frame_bytes: usize,
}

/// What a frame's bytes are, and so how its label is drawn.
#[derive(Debug, Clone, Copy)]
enum Layout {
    /// Samples ([`draw_label`]).
    Samples(Pixels),
    /// Palette indices ([`AnimationWriter::indexed`]).
    Indexed(LabelPalette),
}

impl fmt::Debug for AnimationWriter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("AnimationWriter")
            .field("path", &self.path)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("layout", &self.layout)
            .field("frames", &self.frames)
            .field("written", &self.written)
            .finish_non_exhaustive()
    }
}

impl AnimationWriter {
    /// Starts an APNG at `path` of `frames` frames of `width × height`
    /// `pixels`, each shown `delay_ms` milliseconds, looping forever.
    ///
    /// # Errors
    /// When `frames` is 0, a side is 0 or above [`MAX_SIDE`], or the
    /// folder is not writable.
    pub fn new(
        path: &Path,
        width: u32,
        height: u32,
        pixels: Pixels,
        frames: u32,
        delay_ms: u16,
    ) -> Result<AnimationWriter> {
        let layout = Layout::Samples(pixels);
        start(path, (width, height), layout, None, frames, delay_ms)
    }

    /// [`AnimationWriter::new`] for frames of palette indices, one byte a
    /// pixel, every index inside `palette`: a third of an RGB frame's
    /// bytes to deflate. The file's palette is `palette` followed by the
    /// colours the labels need ([`LabelPalette`]), so at most
    /// [`LabelPalette::MAX_COLOURS`] colours fit.
    ///
    /// # Errors
    /// As [`AnimationWriter::new`], or when `palette` is empty or has more
    /// colours than fit.
    pub fn indexed(
        path: &Path,
        width: u32,
        height: u32,
        palette: &[[u8; 3]],
        frames: u32,
        delay_ms: u16,
    ) -> Result<AnimationWriter> {
        let (labels, all) = LabelPalette::new(palette)?;
        let layout = Layout::Indexed(labels);
        start(
            path,
            (width, height),
            layout,
            Some(all.concat()),
            frames,
            delay_ms,
        )
    }

    /// Adds the next frame: `pixels` (`width × height` in the layout given
    /// to [`AnimationWriter::new`]) with `label` drawn in. Pixels handed
    /// over as a `Vec` are labelled in place; a slice is copied first.
    ///
    /// # Errors
    /// When `pixels` has another length than a frame's, all the frames
    /// announced are written already, or writing fails.
    pub fn frame(&mut self, pixels: impl Into<Vec<u8>>, label: &str) -> Result<()> {
        let mut pixels = pixels.into();
        if self.written == self.frames {
            bail!(
                "{}: all {} announced frames are written already",
                self.path.display(),
                self.frames
            );
        }
        let expected = self.frame_bytes;
        if pixels.len() != expected {
            bail!(
                "{}: frame {} has {} bytes, not the {expected} of {}×{} {:?} pixels",
                self.path.display(),
                self.written,
                pixels.len(),
                self.width,
                self.height,
                self.layout
            );
        }
        // The greatest index, in blocks that compile to vector maxima.
        let greatest = || {
            let blocks = pixels.chunks(64);
            blocks.fold(0, |m, b| b.iter().fold(m, |m, &i| m.max(i)))
        };
        if let Layout::Indexed(labels) = self.layout
            && let index = greatest()
            && usize::from(index) >= labels.n
        {
            bail!(
                "{}: frame {} has the index {index}, past its {} colours",
                self.path.display(),
                self.written,
                labels.n
            );
        }
        match self.layout {
            Layout::Samples(layout) => {
                draw_label(&mut pixels, self.width, self.height, layout, label)?;
            }
            Layout::Indexed(labels) => labels.draw(&mut pixels, self.width, self.height, label)?,
        }
        self.png
            .write_image_data(&pixels)
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        self.written += 1;
        Ok(())
    }

    /// Ends the file and renames it into place.
    ///
    /// # Errors
    /// When fewer frames were written than announced (then no file is
    /// left), or writing fails.
    pub fn finish(self) -> Result<()> {
        let AnimationWriter {
            path,
            file,
            png,
            frames,
            written,
            ..
        } = self;
        if written != frames {
            bail!(
                "{}: {written} of the {frames} announced frames were written",
                path.display()
            );
        }
        png.finish()
            .with_context(|| format!("cannot write {}", path.display()))?;
        let output = file
            .0
            .lock()
            .map_err(|_| anyhow!("cannot write {}: an earlier write panicked", path.display()))?
            .take()
            .ok_or_else(|| anyhow!("cannot write {}: finished twice", path.display()))?;
        output.finish()
    }
}

/// Starts an APNG at `path` of `frames` frames of `width × height` pixels
/// laid out as `layout` says (with the file's `palette` when indexed).
fn start(
    path: &Path,
    (width, height): (u32, u32),
    layout: Layout,
    palette: Option<Vec<u8>>,
    frames: u32,
    delay_ms: u16,
) -> Result<AnimationWriter> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        bail!("an animation must be 1 to {MAX_SIDE} pixels a side, not {width}×{height}");
    }
    if frames == 0 {
        bail!("an animation needs at least one frame");
    }
    let (colour, channels) = match layout {
        Layout::Samples(pixels) => (pixels.colour_type(), pixels.channels()),
        Layout::Indexed(_) => (png::ColorType::Indexed, 1),
    };
    let bytes = u64::from(width) * u64::from(height) * channels as u64;
    let bytes = usize::try_from(bytes).context("an animation frame does not fit in memory")?;
    let file = SharedFile(Arc::new(Mutex::new(Some(OutputFile::create(path)?))));
    let mut encoder = png::Encoder::new(file.clone(), width, height);
    encoder.set_color(colour);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(super::picture::PICTURE);
    if let Some(palette) = palette {
        encoder.set_palette(palette);
    }
    encoder.validate_sequence(true);
    // Play count 0: loop forever.
    encoder.set_animated(frames, 0)?;
    encoder.set_frame_delay(delay_ms, 1000)?;
    let png = encoder
        .write_header()
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(AnimationWriter {
        path: path.to_path_buf(),
        file,
        png,
        width,
        height,
        layout,
        frames,
        written: 0,
        frame_bytes: bytes,
    })
}

/// The colours an indexed animation's labels need beyond the frames' own
/// `n` (indices below `n`): each colour darkened under a label's box
/// (indices `n..2n`), then each darkened colour under a glyph at the
/// coverages 17, 34, …, 255 (15 levels a colour, from `2n`). A glyph's
/// coverage is rounded to the nearest level, so its edges take 16 shades
/// instead of 256, a difference of at most 8 in a channel.
#[derive(Debug, Clone, Copy)]
pub struct LabelPalette {
    n: usize,
}

impl LabelPalette {
    /// Coverage levels of a glyph, 0 (none) included.
    const LEVELS: usize = 16;
    /// The weight of one level, of 255.
    const STEP: u32 = 255 / (Self::LEVELS as u32 - 1);
    /// The most colours of frames whose labels fit a palette of 256.
    pub const MAX_COLOURS: usize = 256 / (Self::LEVELS + 1);

    /// The labels' colours for frames in `palette`, and the whole palette.
    ///
    /// # Errors
    /// When `palette` is empty or has more than [`Self::MAX_COLOURS`].
    pub fn new(palette: &[[u8; 3]]) -> Result<(LabelPalette, Vec<[u8; 3]>)> {
        let n = palette.len();
        if n == 0 || n > Self::MAX_COLOURS {
            bail!(
                "an indexed animation takes 1 to {} colours, not {n}",
                Self::MAX_COLOURS
            );
        }
        let (towards, weight) = BOX;
        let dark: Vec<[u8; 3]> = palette
            .iter()
            .map(|c| c.map(|s| mix(s, towards, weight)))
            .collect();
        let mut all = [palette, &dark].concat();
        for d in &dark {
            for level in 1..Self::LEVELS as u32 {
                // ≤ 255: exact in u16.
                let weight = (level * Self::STEP) as u16;
                all.push(d.map(|s| mix(s, GLYPH, weight)));
            }
        }
        Ok((LabelPalette { n }, all))
    }

    /// The index pixel `i` takes under a label's box: its frame colour
    /// darkened (a pixel already darkened or under a glyph stays).
    fn shade(self, i: u8) -> u8 {
        let (n, i) = (self.n, usize::from(i));
        let index = if i < n { n + i } else { i };
        // < 2n ≤ 256.
        u8::try_from(index).unwrap_or(u8::MAX)
    }

    /// The index pixel `i` takes under a glyph of coverage `weight` (of
    /// 255): the glyph adds its coverage to the coverage the pixel has (as
    /// two blends towards white would), rounded to a level. A glyph over a
    /// pixel outside the box is drawn as over the box.
    fn ink(self, i: u8, weight: u16) -> u8 {
        let (n, i, top) = (self.n, usize::from(i), Self::LEVELS - 1);
        // The frame colour under the pixel, and the glyph level on it.
        let (k, level) = match i.checked_sub(2 * n) {
            Some(g) => (g / top, g % top + 1),
            None => (i % n, 0),
        };
        let before = level as u32 * Self::STEP;
        let left = (255 - before) * (255 - u32::from(weight).min(255));
        let cover = 255 - (left + 127) / 255;
        let index = match ((cover + Self::STEP / 2) / Self::STEP) as usize {
            0 => i,
            level => 2 * n + k * top + level - 1,
        };
        // < n · (LEVELS + 1) ≤ 256.
        u8::try_from(index).unwrap_or(u8::MAX)
    }

    /// Draws `label` into `indices` (`width × height`, one byte a pixel)
    /// as [`draw_label`] draws it into samples.
    fn draw(self, indices: &mut [u8], width: u32, height: u32, label: &str) -> Result<()> {
        let label = Label::new(width, height, label)?;
        let w = width as usize;
        let shaded: [u8; 256] = std::array::from_fn(|i| self.shade(i as u8));
        for row in indices
            .chunks_exact_mut(w)
            .take(label.ys.end)
            .skip(label.ys.start)
        {
            for p in &mut row[label.xs.clone()] {
                *p = shaded[usize::from(*p)];
            }
        }
        for &(x, y, weight) in &label.glyphs {
            let p = &mut indices[y * w + x];
            *p = self.ink(*p, weight);
        }
        Ok(())
    }
}

/// The height of a label's text for a frame `height` pixels high: a
/// fourteenth of it, 10 to 32 px.
fn label_px(height: u32) -> f32 {
    // ≤ 32, exact in f32.
    (height / 14).clamp(10, 32) as f32
}

/// Draws `label` into the top-left corner of `pixels` (a `width ×
/// height` picture in the `layout` given): white text on the picture
/// darkened to 37 %, cut at the picture's edges. An empty label draws
/// nothing.
///
/// # Errors
/// When `pixels` is not `width × height` pixels long.
pub fn draw_label(
    pixels: &mut [u8],
    width: u32,
    height: u32,
    layout: Pixels,
    label: &str,
) -> Result<()> {
    let w = width as usize;
    if w.checked_mul(height as usize)
        .and_then(|n| n.checked_mul(layout.channels()))
        != Some(pixels.len())
    {
        bail!(
            "a {width}×{height} {layout:?} picture has not {} bytes",
            pixels.len()
        );
    }
    Label::new(width, height, label)?.draw(pixels, w, [0, 0], layout);
    Ok(())
}

/// A label's box: the picture moved towards black by 160 of 255.
const BOX: (u8, u16) = (0, 160);
/// A label's glyphs: white, by their coverage.
const GLYPH: u8 = 255;

/// `sample` moved towards `towards` by `weight` of 255, rounded.
pub(crate) fn mix(sample: u8, towards: u8, weight: u16) -> u8 {
    // weight ≤ 255 and samples ≤ 255: the sum ≤ 65025 + 127.
    let mixed = (u32::from(sample) * u32::from(255 - weight)
        + u32::from(towards) * u32::from(weight)
        + 127)
        / 255;
    u8::try_from(mixed).unwrap_or(u8::MAX)
}

/// A label laid out in the top-left corner of a `width × height`
/// picture ([`draw_label`]): the box that darkens the picture and the
/// coverage of its glyphs, both cut at the picture's edges.
#[derive(Debug)]
pub(crate) struct Label {
    /// The box: columns `xs` of rows `ys`.
    xs: Range<usize>,
    ys: Range<usize>,
    /// The glyphs' pixels `(x, y, weight)`, white at `weight` of 255, in
    /// the order they are drawn (glyphs may overlap).
    glyphs: Vec<(usize, usize, u16)>,
}

impl Label {
    /// Lays `label` out (an empty one covers nothing).
    ///
    /// # Errors
    /// When the label's font cannot be read.
    pub(crate) fn new(width: u32, height: u32, label: &str) -> Result<Label> {
        let mut laid = Label {
            xs: 0..0,
            ys: 0..0,
            glyphs: Vec::new(),
        };
        if label.is_empty() {
            return Ok(laid);
        }
        let (w, h) = (width as usize, height as usize);
        let face = font()?;
        let size = label_px(height);
        let scaled = face.as_scaled(PxScale::from(size));
        let pad = (size / 4.0).max(2.0).round();
        let mut caret = 0.0f32;
        let mut previous = None;
        let mut glyphs = Vec::with_capacity(label.len());
        for c in label.chars() {
            let id = scaled.glyph_id(c);
            if let Some(previous) = previous {
                caret += scaled.kern(previous, id);
            }
            glyphs.push((id, caret));
            caret += scaled.h_advance(id);
            previous = Some(id);
        }
        let ascent = scaled.ascent();
        let text_height = ascent - scaled.descent();
        // The box: `pad` from the corner, `pad` around the text; its
        // corners are whole pixels (rounded above).
        let box_right = (3.0 * pad + caret).ceil() as usize;
        let box_bottom = (3.0 * pad + text_height).ceil() as usize;
        // `lo..hi` cut at `n`.
        let cut = |lo: usize, hi: usize, n: usize| lo.min(n)..hi.min(n).max(lo.min(n));
        laid.xs = cut(pad as usize, box_right, w);
        laid.ys = cut(pad as usize, box_bottom, h);
        let origin = point(2.0 * pad, 2.0 * pad + ascent);
        for (id, x) in glyphs {
            let glyph = id.with_scale_and_position(size, point(origin.x + x, origin.y));
            let Some(outline) = face.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            let (left, top) = (bounds.min.x as i64, bounds.min.y as i64);
            outline.draw(|gx, gy, coverage| {
                let (x, y) = (left + i64::from(gx), top + i64::from(gy));
                if let (Ok(x), Ok(y)) = (usize::try_from(x), usize::try_from(y))
                    && x < w
                    && y < h
                {
                    // coverage ∈ [0, 1]: the weight ∈ [0, 255].
                    let weight = (coverage.clamp(0.0, 1.0) * 255.0).round() as u16;
                    laid.glyphs.push((x, y, weight));
                }
            });
        }
        Ok(laid)
    }

    /// Draws it into `pixels`, samples in `layout`, its pixel (x, y) at
    /// (`origin[0]` + x, `origin[1]` + y) of a picture `stride` pixels
    /// wide: the box darkened, then each glyph pixel moved towards white
    /// (an RGBA pixel drawn on is made opaque).
    ///
    /// # Panics
    /// When the label's box or glyphs, so placed, fall outside `pixels`.
    pub(crate) fn draw(
        &self,
        pixels: &mut [u8],
        stride: usize,
        origin: [usize; 2],
        layout: Pixels,
    ) {
        let channels = layout.channels();
        let at = |x: usize, y: usize| ((origin[1] + y) * stride + origin[0] + x) * channels;
        let shaded: [u8; 256] = std::array::from_fn(|s| mix(s as u8, BOX.0, BOX.1));
        for y in self.ys.clone() {
            let row = &mut pixels[at(self.xs.start, y)..at(self.xs.end, y)];
            for pixel in row.chunks_exact_mut(channels) {
                for sample in &mut pixel[..3] {
                    *sample = shaded[usize::from(*sample)];
                }
                if layout == Pixels::Rgba {
                    pixel[3] = 255;
                }
            }
        }
        for &(x, y, weight) in &self.glyphs {
            let pixel = &mut pixels[at(x, y)..at(x, y) + channels];
            for sample in &mut pixel[..3] {
                *sample = mix(*sample, GLYPH, weight);
            }
            if layout == Pixels::Rgba {
                pixel[3] = 255;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 160;
    const H: u32 = 120;

    /// Frame `i` of a red dot of radius 6 crossing a white picture.
    fn dot(i: u32) -> (Vec<u8>, (u32, u32)) {
        let centre = (20 + i * 13, 90);
        let mut rgb = vec![255u8; (W * H * 3) as usize];
        for y in 0..H {
            for x in 0..W {
                let (dx, dy) = (x.abs_diff(centre.0), y.abs_diff(centre.1));
                if dx * dx + dy * dy <= 36 {
                    let at = ((y * W + x) * 3) as usize;
                    rgb[at..at + 3].copy_from_slice(&[220, 30, 30]);
                }
            }
        }
        (rgb, centre)
    }

    fn write_dots(path: &Path) {
        let mut apng = AnimationWriter::new(path, W, H, Pixels::Rgb, 10, 150).unwrap();
        for i in 0..10 {
            apng.frame(dot(i).0, &format!("step {i}")).unwrap();
        }
        apng.finish().unwrap();
    }

    struct Decoded {
        size: (u32, u32),
        colour: png::ColorType,
        frames: u32,
        plays: u32,
        /// Each frame's pixels and delay (numerator, denominator).
        shown: Vec<(Vec<u8>, (u16, u16))>,
    }

    fn decode(path: &Path) -> Decoded {
        let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let info = reader.info();
        let actl = info.animation_control.expect("an acTL chunk");
        let (size, colour) = ((info.width, info.height), info.color_type);
        let mut shown = Vec::new();
        let mut buf = vec![0; reader.output_buffer_size()];
        while let Ok(out) = reader.next_frame(&mut buf) {
            let fctl = reader.info().frame_control.expect("an fcTL chunk");
            assert_eq!(
                (fctl.width, fctl.height, fctl.x_offset, fctl.y_offset),
                (W, H, 0, 0)
            );
            shown.push((
                buf[..out.buffer_size()].to_vec(),
                (fctl.delay_num, fctl.delay_den),
            ));
        }
        Decoded {
            size,
            colour,
            frames: actl.num_frames,
            plays: actl.num_plays,
            shown,
        }
    }

    /// The label's area of a `W`-wide RGB picture: its top-left corner.
    fn label_area(rgb: &[u8]) -> Vec<[u8; 3]> {
        rgb.chunks_exact(3)
            .enumerate()
            .filter(|(i, _)| (*i as u32 % W) < 60 && (*i as u32 / W) < 20)
            .map(|(_, p)| [p[0], p[1], p[2]])
            .collect()
    }

    /// Every frame of the APNG at `path` as RGB (indices looked up).
    fn decode_rgb(path: &Path) -> Vec<Vec<u8>> {
        let mut decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let mut frames = Vec::new();
        while let Ok(out) = reader.next_frame(&mut buf) {
            frames.push(buf[..out.buffer_size()].to_vec());
        }
        frames
    }

    #[test]
    fn indexed_frames_show_their_colours_and_labels_within_a_level() {
        let palette = [
            [255, 255, 255],
            [128, 128, 128],
            [30, 160, 40],
            [200, 40, 170],
        ];
        // Stripes of every colour, across the label too.
        let frame = |shift: u32| -> Vec<u8> {
            (0..W * H)
                .map(|i| ((i % W / 3 + i / W / 5 + shift) % 4) as u8)
                .collect()
        };
        let rgb = |indices: &[u8]| -> Vec<u8> {
            indices
                .iter()
                .flat_map(|&i| palette[usize::from(i)])
                .collect()
        };
        let labels = ["day 0", "day 12", "age 6.0 months", ""];
        let dir = tempfile::tempdir().unwrap();
        let (indexed, direct) = (dir.path().join("i.png"), dir.path().join("d.png"));
        let mut a = AnimationWriter::indexed(&indexed, W, H, &palette, 4, 100).unwrap();
        let mut b = AnimationWriter::new(&direct, W, H, Pixels::Rgb, 4, 100).unwrap();
        for (k, label) in labels.iter().enumerate() {
            a.frame(frame(k as u32), label).unwrap();
            b.frame(rgb(&frame(k as u32)), label).unwrap();
        }
        a.finish().unwrap();
        b.finish().unwrap();
        let (shown, wanted) = (decode_rgb(&indexed), decode_rgb(&direct));
        assert_eq!(shown.len(), 4);
        for (k, (shown, wanted)) in shown.iter().zip(&wanted).enumerate() {
            let plain = rgb(&frame(k as u32));
            let mut under = vec![false; (W * H) as usize];
            let label = Label::new(W, H, labels[k]).unwrap();
            for y in label.ys.clone() {
                for x in label.xs.clone() {
                    under[y * W as usize + x] = true;
                }
            }
            for &(x, y, _) in &label.glyphs {
                under[y * W as usize + x] = true;
            }
            let pixels = |b: &[u8]| b.chunks_exact(3).map(<[u8]>::to_vec).collect::<Vec<_>>();
            for ((s, w), under) in pixels(shown).iter().zip(pixels(wanted)).zip(&under) {
                // Outside the label: the same; under it, a glyph's
                // coverage is within half a level (8 of 255).
                if *under {
                    let near = s.iter().zip(&w).all(|(s, w)| s.abs_diff(*w) <= 8);
                    assert!(near, "frame {k}: {s:?} for {w:?}");
                } else {
                    assert_eq!(s, &w, "frame {k}");
                }
            }
            assert_eq!(shown != &plain, !labels[k].is_empty(), "frame {k}");
        }
        // The indexed file is a third of the bytes to deflate, and smaller.
        let size = |p: &Path| std::fs::metadata(p).unwrap().len();
        assert!(size(&indexed) < size(&direct));
    }

    #[test]
    fn indexed_frames_refuse_indices_past_their_colours_and_too_many_colours() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("i.png");
        let colours = [[9, 9, 9]; LabelPalette::MAX_COLOURS + 1];
        assert!(AnimationWriter::indexed(&path, W, H, &colours, 1, 100).is_err());
        assert!(AnimationWriter::indexed(&path, W, H, &[], 1, 100).is_err());
        let mut apng = AnimationWriter::indexed(&path, W, H, &colours[1..], 1, 100).unwrap();
        let mut pixels = vec![0; (W * H) as usize];
        pixels[7] = LabelPalette::MAX_COLOURS as u8;
        let e = apng.frame(pixels, "x").unwrap_err().to_string();
        assert!(e.contains("the index 15, past its 15 colours"), "{e}");
        drop(apng);
        assert!(!path.exists());
    }

    #[test]
    fn an_apng_has_its_frames_delays_labels_and_the_same_bytes_twice() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        write_dots(&a);
        write_dots(&b);
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);

        let apng = decode(&a);
        assert_eq!(apng.size, (W, H));
        assert_eq!(apng.colour, png::ColorType::Rgb);
        assert_eq!((apng.frames, apng.plays), (10, 0));
        assert_eq!(apng.shown.len(), 10);
        for (i, (rgb, delay)) in apng.shown.iter().enumerate() {
            assert_eq!(*delay, (150, 1000));
            // The dot of frame i, where frame i put it, and the rest of
            // its row white away from the dot.
            let (source, (cx, cy)) = dot(i as u32);
            let at = ((cy * W + cx) * 3) as usize;
            assert_eq!(rgb[at..at + 3], [220, 30, 30], "frame {i}");
            let far = ((cy * W + (cx + 40) % W) * 3) as usize;
            assert_eq!(rgb[far..far + 3], [255, 255, 255], "frame {i}");
            // Outside the label's box the frame is as given.
            let below = (40 * W * 3) as usize;
            assert_eq!(rgb[below..], source[below..], "frame {i}");
            // The label: a box darker than the white picture, with
            // near-white ink on it.
            let area = label_area(rgb);
            let dark = area.iter().filter(|p| p.iter().all(|&c| c < 110)).count();
            let ink = area.iter().filter(|p| p.iter().all(|&c| c > 200)).count();
            assert!(dark > 300, "frame {i}: {dark} box pixels");
            assert!(ink > 20, "frame {i}: {ink} ink pixels");
        }
        // "step 0" and "step 1" differ in their last glyph only.
        let (zero, one) = (label_area(&apng.shown[0].0), label_area(&apng.shown[1].0));
        let differing = zero.iter().zip(&one).filter(|(p, q)| p != q).count();
        assert!(differing > 10, "{differing} pixels differ");
    }

    #[test]
    fn frames_at_hand_give_the_bytes_of_the_streaming_writer() {
        let dir = tempfile::tempdir().unwrap();
        let (streamed, at_hand) = (dir.path().join("s.png"), dir.path().join("h.png"));
        write_dots(&streamed);
        Animation {
            width: W,
            height: H,
            pixels: Pixels::Rgb,
            delay_ms: 150,
            frames: (0..10)
                .map(|i| Frame {
                    pixels: dot(i).0,
                    label: format!("step {i}"),
                })
                .collect(),
        }
        .write(&at_hand)
        .unwrap();
        assert_eq!(
            std::fs::read(&streamed).unwrap(),
            std::fs::read(&at_hand).unwrap()
        );
    }

    #[test]
    fn rgba_frames_keep_their_alpha_outside_the_label() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rgba.png");
        let clear = vec![0u8; (W * H * 4) as usize];
        let mut apng = AnimationWriter::new(&path, W, H, Pixels::Rgba, 2, 40).unwrap();
        apng.frame(clear.as_slice(), "age 6.0 months").unwrap();
        apng.frame(clear.as_slice(), "").unwrap();
        apng.finish().unwrap();
        let decoded = decode(&path);
        assert_eq!(decoded.colour, png::ColorType::Rgba);
        assert_eq!(decoded.shown.len(), 2);
        let opaque = |rgba: &[u8]| rgba.chunks_exact(4).filter(|p| p[3] == 255).count();
        let labelled = &decoded.shown[0].0;
        assert!(opaque(labelled) > 500, "{} opaque pixels", opaque(labelled));
        assert_eq!(
            labelled[(50 * W * 4) as usize..],
            clear[(50 * W * 4) as usize..]
        );
        assert_eq!(decoded.shown[1].0, clear);
        assert_eq!(decoded.shown[1].1, (40, 1000));
    }

    #[test]
    fn wrong_frames_are_refused_and_leave_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.png");
        let (good, _) = dot(0);

        let mut apng = AnimationWriter::new(&path, W, H, Pixels::Rgb, 2, 100).unwrap();
        let e = apng.frame(&good[3..], "short").unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("{} bytes, not the {}", good.len() - 3, good.len())),
            "{e}"
        );
        apng.frame(good.as_slice(), "one").unwrap();
        let e = apng.finish().unwrap_err();
        assert!(e.to_string().contains("1 of the 2 announced frames"), "{e}");

        let mut apng = AnimationWriter::new(&path, W, H, Pixels::Rgb, 1, 100).unwrap();
        apng.frame(good.as_slice(), "one").unwrap();
        let e = apng.frame(good.as_slice(), "two").unwrap_err();
        assert!(e.to_string().contains("all 1 announced frames"), "{e}");
        drop(apng);

        assert!(AnimationWriter::new(&path, W, H, Pixels::Rgb, 0, 100).is_err());
        assert!(AnimationWriter::new(&path, 0, H, Pixels::Rgb, 1, 100).is_err());
        assert!(draw_label(&mut [0; 5], 2, 1, Pixels::Rgb, "x").is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// Writes example pictures into the temporary folder, to look at:
    /// `cargo test -p morphogen-cli --lib outputs -- --ignored`.
    #[test]
    #[ignore = "writes examples to look at"]
    fn write_examples_to_tmp() {
        let tmp = std::env::temp_dir();
        let path = &tmp.join("animation-dots.png");
        write_dots(path);
        // All ten decoded frames side by side, as a still picture.
        let apng = decode(path);
        let mut strip = Vec::new();
        for y in 0..H as usize {
            for (rgb, _) in &apng.shown {
                strip.extend_from_slice(&rgb[y * W as usize * 3..(y + 1) * W as usize * 3]);
            }
        }
        // Labels on a dark-to-light gradient, 320×240.
        let gradient: Vec<u8> = (0..240u32 * 320)
            .flat_map(|i| {
                let v = (i % 320 * 255 / 319) as u8;
                [v, v / 2, 255 - v]
            })
            .collect();
        let labels = Animation {
            width: 320,
            height: 240,
            pixels: Pixels::Rgb,
            delay_ms: 500,
            frames: ["day 12", "age 6.0 months"]
                .map(|label| Frame {
                    pixels: gradient.clone(),
                    label: label.to_string(),
                })
                .to_vec(),
        };
        labels.write(&tmp.join("animation-labels.png")).unwrap();
        let mut second = gradient.clone();
        draw_label(&mut second, 320, 240, Pixels::Rgb, "age 6.0 months").unwrap();
        let file = std::fs::File::create(tmp.join("animation-label-months.png")).unwrap();
        let mut encoder = png::Encoder::new(file, 320, 240);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&second).unwrap();
        writer.finish().unwrap();
        let file = std::fs::File::create(tmp.join("animation-dots-frames.png")).unwrap();
        let mut encoder = png::Encoder::new(file, W * 10, H);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&strip).unwrap();
        writer.finish().unwrap();
    }
}
