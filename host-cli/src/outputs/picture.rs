//! Pictures as PNG files: opaque RGB from a tiny-skia pixmap, or
//! palette-indexed, both with the `png` crate's fast deflate, written
//! atomically (each row predicted from the one above it, [`PICTURE`], or
//! for charts by Paeth, [`save_plot`]); and [`half`] (or [`half_rgb`], straight to the bytes
//! saved), the 2×2 average that turns a picture drawn at twice its size
//! into an anti-aliased one.

use std::path::Path;
use std::sync::Mutex;

use anyhow::{Context, Result, anyhow, bail};
use tiny_skia::{Color, IntSize, Pixmap};

use crate::atomic::OutputFile;

/// How the rows of a picture are filtered before deflate: each from the
/// row above. A drawing on a flat background repeats rows more than it
/// repeats pixels along a row, and the fast deflate turns the zeros of
/// repeated rows into runs: smaller files than the crate's default (each
/// pixel from its left neighbour) in less time (bones.png 113 → 65 KB,
/// a mosaic's day 17 → 13 KB).
pub const PICTURE: png::FilterType = png::FilterType::Up;

/// Writes `width × height` 8-bit `colour` samples (`channels` bytes a
/// pixel: RGB, or one index into `palette`) as a PNG at `path`, its rows
/// filtered by `filter`.
fn encode(
    path: &Path,
    (width, height): (u32, u32),
    (colour, filter): (png::ColorType, png::FilterType),
    palette: Option<Vec<u8>>,
    samples: &[u8],
) -> Result<()> {
    OutputFile::write_with(path, |file| {
        let mut encoder = png::Encoder::new(file, width, height);
        encoder.set_color(colour);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        encoder.set_filter(filter);
        if let Some(palette) = palette {
            encoder.set_palette(palette);
        }
        let mut writer = encoder.write_header()?;
        writer.write_image_data(samples)?;
        writer.finish()?;
        Ok(())
    })
    .context("cannot encode PNG")
}

/// Writes `pixmap`, every pixel of which is opaque, as an RGB PNG.
///
/// # Errors
/// When encoding or writing fails.
pub fn save(pixmap: &Pixmap, path: &Path) -> Result<()> {
    save_rgb(pixmap.width(), pixmap.height(), &rgb_bytes(pixmap), path)
}

/// Writes `width × height` RGB bytes, row by row, as a PNG.
///
/// # Errors
/// When encoding or writing fails.
pub fn save_rgb(width: u32, height: u32, rgb: &[u8], path: &Path) -> Result<()> {
    let format = (png::ColorType::Rgb, PICTURE);
    encode(path, (width, height), format, None, rgb)
}

/// [`save_rgb`] for a chart: rows filtered by Paeth, which predicts
/// thin grid lines and curves both along a row and across rows, where
/// [`PICTURE`]'s filter leaves every vertical grid line in every row
/// (a 900 × 500 chart: 315 → 125 KB, encoded in no more time).
///
/// # Errors
/// When encoding or writing fails.
pub fn save_plot(width: u32, height: u32, rgb: &[u8], path: &Path) -> Result<()> {
    let format = (png::ColorType::Rgb, png::FilterType::Paeth);
    encode(path, (width, height), format, None, rgb)
}

/// Writes a picture of palette indices (one byte a pixel, row by row) as
/// an indexed PNG.
///
/// # Errors
/// When encoding or writing fails.
pub fn save_indexed(
    width: u32,
    height: u32,
    palette: &[[u8; 3]],
    indices: &[u8],
    path: &Path,
) -> Result<()> {
    encode(
        path,
        (width, height),
        (png::ColorType::Indexed, PICTURE),
        Some(palette.concat()),
        indices,
    )
}

/// Blank canvases of one size and background for frames drawn one after
/// another, or by parallel workers: a canvas given back is handed out
/// again, cleared, so a run of frames draws on a few pictures instead of
/// allocating (and zeroing) one a frame.
#[derive(Debug)]
pub struct Canvases {
    width: u32,
    height: u32,
    background: Color,
    free: Mutex<Vec<Pixmap>>,
}

impl Canvases {
    /// Canvases of `width × height` pixels filled with `background`.
    #[must_use]
    pub fn new(width: u32, height: u32, background: Color) -> Canvases {
        Canvases {
            width,
            height,
            background,
            free: Mutex::new(Vec::new()),
        }
    }

    /// A blank canvas: one given back, or a new one.
    ///
    /// # Errors
    /// When a side is 0 or the picture does not fit in memory.
    pub fn take(&self) -> Result<Pixmap> {
        let reused = self
            .free
            .lock()
            .map_err(|_| anyhow!("a picture writer stopped"))?
            .pop();
        let mut canvas = match reused {
            Some(canvas) => canvas,
            None => {
                Pixmap::new(self.width, self.height).context("picture size must be positive")?
            }
        };
        canvas.fill(self.background);
        Ok(canvas)
    }

    /// Gives `canvas` back for a later [`Canvases::take`].
    pub fn give_back(&self, canvas: Pixmap) {
        if let Ok(mut free) = self.free.lock() {
            free.push(canvas);
        }
    }
}

/// `pixmap` at half its size, each pixel the average of its 2×2 block.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high.
pub fn half(pixmap: &Pixmap) -> Result<Pixmap> {
    let size = IntSize::from_wh(pixmap.width() / 2, pixmap.height() / 2)
        .context("picture too small to halve")?;
    let mut rgba = vec![0; 4 * size.width() as usize * size.height() as usize];
    halve::<4>(pixmap, &mut rgba);
    Pixmap::from_vec(rgba, size).context("picture too small to halve")
}

/// [`half`] as RGB bytes, row by row: a picture drawn at twice its size
/// ready to save ([`save_rgb`]) or animate, with no pixmap in between.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high.
pub fn half_rgb(pixmap: &Pixmap) -> Result<Vec<u8>> {
    let mut rgb = vec![0; 3 * (pixmap.width() / 2 * (pixmap.height() / 2)) as usize];
    half_rgb_into(pixmap, &mut rgb)?;
    Ok(rgb)
}

/// [`half_rgb`] into `rgb`: for a picture drawn band by band, each band
/// halved into its rows of the whole.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high, or `rgb` is not
/// the size of its half.
pub fn half_rgb_into(pixmap: &Pixmap, rgb: &mut [u8]) -> Result<()> {
    let (w, h) = (pixmap.width() / 2, pixmap.height() / 2);
    if w == 0 || h == 0 {
        bail!("picture too small to halve");
    }
    if rgb.len() != 3 * w as usize * h as usize {
        bail!("{} bytes cannot hold a {w}×{h} RGB picture", rgb.len());
    }
    halve::<3>(pixmap, rgb);
    Ok(())
}

/// The 2×2 block averages of `pixmap`, the first `C` bytes of each, row by
/// row, into `out` (that many bytes); an odd last row or column of
/// `pixmap` is left out.
///
/// A picture drawn at twice its size is mostly background, so the rows
/// are taken 16 pixels at a time and a run of one colour in both rows
/// (checked with a branch-free fold the compiler vectorises) is that
/// colour halved. Any other block is averaged by [`average`].
fn halve<const C: usize>(pixmap: &Pixmap, out: &mut [u8]) {
    /// Source pixels a uniform run covers (one 64-byte chunk a row).
    const RUN: usize = 16;
    let w = pixmap.width() as usize / 2;
    let stride = 4 * pixmap.width() as usize;
    if w == 0 {
        return;
    }
    // A uniform run's halved bytes, and its colour.
    let mut fill = [0; 4 * RUN / 2];
    let mut fill_colour = None;
    let rows = pixmap.data().chunks_exact(2 * stride);
    for (row, pair) in out.chunks_exact_mut(C * w).zip(rows) {
        let (top, bottom) = pair.split_at(stride);
        let (top, bottom) = (&top[..8 * w], &bottom[..8 * w]);
        let mut outs = row.chunks_exact_mut(C * RUN / 2);
        let runs = top.as_chunks::<{ 4 * RUN }>().0.iter();
        for ((out, t), b) in (&mut outs)
            .zip(runs)
            .zip(bottom.as_chunks::<{ 4 * RUN }>().0)
        {
            let first = [t[0], t[1], t[2], t[3]];
            let colour = u32::from_ne_bytes(first);
            let differ = t
                .as_chunks::<4>()
                .0
                .iter()
                .chain(b.as_chunks::<4>().0)
                .fold(0, |acc, p| acc | (u32::from_ne_bytes(*p) ^ colour));
            if differ == 0 {
                if fill_colour != Some(colour) {
                    for pixel in fill.chunks_exact_mut(C) {
                        pixel.copy_from_slice(&first[..C]);
                    }
                    fill_colour = Some(colour);
                }
                out.copy_from_slice(&fill[..C * RUN / 2]);
            } else {
                average::<C>(out, t, b);
            }
        }
        let done = C * w - outs.into_remainder().len();
        let from = 8 * (done / C);
        average::<C>(&mut row[done..], &top[from..], &bottom[from..]);
    }
}

/// The 2×2 block averages of the pixel pairs of `top` and `bottom`, the
/// first `C` bytes of each, into `out`. Each block is two 8-byte words (a
/// pixel pair from each row) whose bytes are summed in 16-bit lanes — red
/// and blue in one word, green and alpha in the other — so one addition
/// sums a channel of two pixels, and the rounded average `(sum + 2) / 4`
/// of each channel (at most 1 022 before the shift, so no lane carries
/// into the next) is a shift away.
fn average<const C: usize>(out: &mut [u8], top: &[u8], bottom: &[u8]) {
    /// The low byte of each 16-bit lane.
    const LOW: u64 = 0x00ff_00ff_00ff_00ff;
    /// Two added to both 16-bit lanes of a 32-bit word: the rounding.
    const HALF: u64 = 0x0002_0002;
    let blocks = top.as_chunks::<8>().0.iter().zip(bottom.as_chunks::<8>().0);
    for (pixel, (t, b)) in out.as_chunks_mut::<C>().0.iter_mut().zip(blocks) {
        let (t, b) = (u64::from_le_bytes(*t), u64::from_le_bytes(*b));
        // Lanes r₀ b₀ r₁ b₁ and g₀ a₀ g₁ a₁, top plus bottom.
        let rb = (t & LOW) + (b & LOW);
        let ga = ((t >> 8) & LOW) + ((b >> 8) & LOW);
        // The two pixels of the pair added, rounded: the low 32 bits.
        let rb = rb + (rb >> 32) + HALF;
        let ga = ga + (ga >> 32) + HALF;
        let average = [rb >> 2, ga >> 2, rb >> 18, ga >> 18].map(|v| v as u8);
        *pixel = std::array::from_fn(|c| average[c]);
    }
}

/// A picture's pixels as RGB bytes (every pixel opaque).
#[must_use]
pub fn rgb_bytes(pixmap: &Pixmap) -> Vec<u8> {
    // Opaque premultiplied pixels are their own RGB.
    let mut rgb = vec![0; 3 * pixmap.pixels().len()];
    let (fours, rest) = pixmap.data().as_chunks::<16>();
    let (out, out_rest) = rgb.as_chunks_mut::<12>();
    for (out, four) in out.iter_mut().zip(fours) {
        let words: [u32; 4] = std::array::from_fn(|k| {
            u32::from_le_bytes([
                four[4 * k],
                four[4 * k + 1],
                four[4 * k + 2],
                four[4 * k + 3],
            ])
        });
        *out = pack_rgb(words);
    }
    let pixels = rest.as_chunks::<4>().0;
    for (out, rgba) in out_rest.as_chunks_mut::<3>().0.iter_mut().zip(pixels) {
        *out = [rgba[0], rgba[1], rgba[2]];
    }
    rgb
}

/// The low three bytes of each of four little-endian words (a pixel's
/// red, green, blue; the high byte is dropped), packed into 12 bytes with
/// three word stores instead of twelve byte stores.
#[must_use]
pub(crate) fn pack_rgb([a, b, c, d]: [u32; 4]) -> [u8; 12] {
    let words = [
        (a & 0x00ff_ffff) | b << 24,
        (b >> 8 & 0xffff) | c << 16,
        (c >> 16 & 0xff) | d << 8,
    ];
    let mut out = [0; 12];
    for (bytes, word) in out.as_chunks_mut::<4>().0.iter_mut().zip(words) {
        *bytes = word.to_le_bytes();
    }
    out
}

#[cfg(test)]
mod tests {
    use tiny_skia::{Color, PremultipliedColorU8};

    #[test]
    fn rgb_bytes_drop_alpha_four_pixels_at_a_time_and_after() {
        // 7 pixels: one packed group of four, three left over.
        let mut pixmap = Pixmap::new(7, 1).unwrap();
        let rgba: Vec<u8> = (0..28u8).map(|b| b.wrapping_mul(37)).collect();
        pixmap.data_mut().copy_from_slice(&rgba);
        let want: Vec<u8> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(rgb_bytes(&pixmap), want);
        assert_eq!(
            pack_rgb([0xff03_0201, 0xee06_0504, 0xdd09_0807, 0xcc0c_0b0a]),
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]
        );
    }

    use super::*;

    #[test]
    fn halving_averages_blocks_and_saving_reads_back() {
        let mut p = Pixmap::new(4, 2).unwrap();
        p.fill(Color::WHITE);
        let black = PremultipliedColorU8::from_rgba(0, 0, 0, 255).unwrap();
        p.pixels_mut()[0] = black;
        p.pixels_mut()[1] = black;
        let h = half(&p).unwrap();
        assert_eq!((h.width(), h.height()), (2, 1));
        assert_eq!(half_rgb(&p).unwrap(), [128, 128, 128, 255, 255, 255]);
        assert!(half_rgb(&Pixmap::new(1, 9).unwrap()).is_err());
        assert_eq!(h.pixel(0, 0).unwrap().red(), 128);
        assert_eq!(h.pixel(1, 0).unwrap().red(), 255);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.png");
        save(&h, &path).unwrap();
        let back = Pixmap::load_png(&path).unwrap();
        assert_eq!(back.pixel(0, 0).unwrap().green(), 128);
        let canvases = Canvases::new(3, 2, Color::BLACK);
        let mut first = canvases.take().unwrap();
        first.fill(Color::WHITE);
        canvases.give_back(first);
        let again = canvases.take().unwrap();
        assert_eq!((again.width(), again.height()), (3, 2));
        assert!(
            again
                .pixels()
                .iter()
                .all(|p| p.red() == 0 && p.alpha() == 255)
        );
        // A grid of thin lines, as a chart's: the same pixels back from
        // either filter, and smaller by Paeth.
        let grid: Vec<u8> = (0..64 * 48)
            .flat_map(|k| {
                let v = if k % 64 % 8 == 0 || k / 64 % 8 == 0 {
                    200
                } else {
                    255
                };
                [v, v, 255]
            })
            .collect();
        let (plot, rows) = (dir.path().join("plot.png"), dir.path().join("rows.png"));
        save_plot(64, 48, &grid, &plot).unwrap();
        save_rgb(64, 48, &grid, &rows).unwrap();
        for path in [&plot, &rows] {
            let back = Pixmap::load_png(path).unwrap();
            let rgb: Vec<u8> = back
                .pixels()
                .iter()
                .flat_map(|p| [p.red(), p.green(), p.blue()])
                .collect();
            assert_eq!(rgb, grid);
        }
        let size = |path: &Path| std::fs::metadata(path).unwrap().len();
        assert!(size(&plot) < size(&rows), "{} {}", size(&plot), size(&rows));
        let path = dir.path().join("i.png");
        save_indexed(2, 1, &[[1, 2, 3], [9, 8, 7]], &[1, 0], &path).unwrap();
        let back = Pixmap::load_png(&path).unwrap();
        assert_eq!(back.pixel(0, 0).unwrap().red(), 9);
        assert_eq!(back.pixel(1, 0).unwrap().blue(), 3);
    }

    #[test]
    fn halving_rounds_every_channel_of_every_block_as_the_plain_sum() {
        // Odd sides (the last row and column are left out) and every byte
        // value, premultiplied (each channel at most the alpha), in runs of
        // 16 pixels (as `halve` takes them) that are noise, one colour,
        // or one colour but for a pixel of the top or of the bottom row
        // (its place moving from row pair to row pair).
        let (w, h) = (77u32, 9u32);
        let mut bytes = Vec::new();
        let mut x = 0x9e37_79b9u32;
        let mut noise = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let alpha = [0, 1, 254, 255][(x & 3) as usize].max((x >> 24) as u8);
            let c = |shift: u32| ((x >> shift) as u8).min(alpha);
            [c(2), c(10), c(18), alpha]
        };
        for y in 0..h {
            for x in 0..w {
                let (run, pair) = (x / 16, y / 2);
                let odd = (run + pair) % 4 == 2 && y % 2 == pair % 2 && x % 16 == (pair * 5) % 16;
                let pixel = match (run + pair) % 4 {
                    0 => noise(),
                    _ if odd => noise(),
                    k => [10 * k as u8, 200, 3, 255],
                };
                bytes.extend(pixel);
            }
        }
        let p = Pixmap::from_vec(bytes, IntSize::from_wh(w, h).unwrap()).unwrap();
        let data = p.data();
        let at = |x: u32, y: u32, c: usize| u32::from(data[(4 * (y * w + x)) as usize + c]);
        let mut want = Vec::new();
        for y in 0..h / 2 {
            for x in 0..w / 2 {
                for c in 0..4 {
                    let (x, y) = (2 * x, 2 * y);
                    let sum = at(x, y, c) + at(x + 1, y, c) + at(x, y + 1, c) + at(x + 1, y + 1, c);
                    want.push(((sum + 2) / 4) as u8);
                }
            }
        }
        assert_eq!(half(&p).unwrap().data(), want.as_slice());
        let rgb: Vec<u8> = want.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(half_rgb(&p).unwrap(), rgb);
    }
}
