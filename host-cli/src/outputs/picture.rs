//! Pictures as PNG files: opaque RGB from a tiny-skia pixmap, or
//! palette-indexed, both with the `png` crate's fast deflate, written
//! atomically; and [`half`], the 2×2 average that turns a picture drawn at
//! twice its size into an anti-aliased one.

use std::path::Path;

use anyhow::{Context, Result};
use tiny_skia::Pixmap;

use crate::atomic::OutputFile;

/// Writes `width × height` 8-bit `colour` samples (`channels` bytes a
/// pixel: RGB, or one index into `palette`) as a PNG at `path`.
fn encode(
    path: &Path,
    (width, height): (u32, u32),
    colour: png::ColorType,
    palette: Option<Vec<u8>>,
    samples: &[u8],
) -> Result<()> {
    OutputFile::write_with(path, |file| {
        let mut encoder = png::Encoder::new(file, width, height);
        encoder.set_color(colour);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
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
    save_rgb(
        pixmap.width(),
        pixmap.height(),
        &super::rgb_bytes(pixmap),
        path,
    )
}

/// Writes `width × height` RGB bytes, row by row, as a PNG.
///
/// # Errors
/// When encoding or writing fails.
pub fn save_rgb(width: u32, height: u32, rgb: &[u8], path: &Path) -> Result<()> {
    encode(path, (width, height), png::ColorType::Rgb, None, rgb)
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
        png::ColorType::Indexed,
        Some(palette.concat()),
        indices,
    )
}

/// `pixmap` at half its size, each pixel the average of its 2×2 block.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high.
pub fn half(pixmap: &Pixmap) -> Result<Pixmap> {
    let (w, h) = (pixmap.width() / 2, pixmap.height() / 2);
    let mut out = Pixmap::new(w, h).context("picture too small to halve")?;
    let stride = 4 * pixmap.width() as usize;
    // Row pairs of the source beside rows of the picture; an odd last
    // row or column of the source is left out. Each pair is summed down
    // the columns, then pixel pairs across (two passes that vectorise).
    let mut column = vec![0u16; stride];
    let pairs = pixmap.data().chunks_exact(2 * stride);
    for (row, pair) in out.data_mut().chunks_exact_mut(4 * w as usize).zip(pairs) {
        let (top, bottom) = pair.split_at(stride);
        for ((sum, t), b) in column.iter_mut().zip(top).zip(bottom) {
            *sum = u16::from(*t) + u16::from(*b);
        }
        let blocks = column.as_chunks::<8>().0;
        for (pixel, block) in row.as_chunks_mut::<4>().0.iter_mut().zip(blocks) {
            // Averages of premultiplied RGBA bytes stay premultiplied; four
            // bytes sum below 1 024, +2 rounds to nearest.
            *pixel = std::array::from_fn(|c| ((block[c] + block[c + 4] + 2) / 4) as u8);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use tiny_skia::{Color, PremultipliedColorU8};

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
        assert_eq!(h.pixel(0, 0).unwrap().red(), 128);
        assert_eq!(h.pixel(1, 0).unwrap().red(), 255);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.png");
        save(&h, &path).unwrap();
        let back = Pixmap::load_png(&path).unwrap();
        assert_eq!(back.pixel(0, 0).unwrap().green(), 128);
        let path = dir.path().join("i.png");
        save_indexed(2, 1, &[[1, 2, 3], [9, 8, 7]], &[1, 0], &path).unwrap();
        let back = Pixmap::load_png(&path).unwrap();
        assert_eq!(back.pixel(0, 0).unwrap().red(), 9);
        assert_eq!(back.pixel(1, 0).unwrap().blue(), 3);
    }
}
