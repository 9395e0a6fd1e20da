//! Mosaic presets (MClone): per streamed day a CSV of the cells
//! (`cells_dayNN.csv`: `id,type,x,y`) and a Voronoi picture
//! (`day_NN.png`: every pixel takes the colour of the type of its nearest
//! cell, distances periodic where the domain wraps, the cylinder unrolled
//! with u to the right and v down); `mosaic.png` is the last day; the
//! control mask, if any, as `mask.pbm`. [`read_mask`] reads a user's mask
//! (PBM or PNG).

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen::mosaic::{Mask, Params};
use morphogen::stream::Record;
use tiny_skia::{ColorU8, Pixmap};

use crate::fixture::write_atomic;

/// The longest side of the pictures, in pixels.
const LONG_SIDE: f64 = 900.0;

/// One streamed day.
#[derive(Debug, Default)]
pub struct Day {
    /// The day number.
    pub day: i32,
    /// `(id, type, u, v)` of each cell.
    pub cells: Vec<(u32, u8, f64, f64)>,
}

/// The days of a mosaic stream, in order.
#[must_use]
pub fn days(records: &[Record]) -> Vec<Day> {
    let mut out: Vec<Day> = Vec::new();
    for r in records {
        match r {
            Record::FrameStart { time, .. } => out.push(Day {
                day: time.floor_int(),
                cells: Vec::new(),
            }),
            Record::Cell { id, kind, p } => {
                if let Some(d) = out.last_mut() {
                    d.cells.push((
                        *id,
                        *kind,
                        f64::from(p[0].to_bits()) / 65_536.0,
                        f64::from(p[1].to_bits()) / 65_536.0,
                    ));
                }
            }
            _ => {}
        }
    }
    out
}

/// Writes the CSVs, the Voronoi PNGs and the mask of `params`' run.
///
/// # Errors
/// When a file cannot be written.
pub fn write(params: &Params, records: &[Record], dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let days = days(records);
    for d in &days {
        let mut csv = String::from("id,type,x,y\n");
        for (id, kind, x, y) in &d.cells {
            let _ = writeln!(csv, "{id},{kind},{x},{y}");
        }
        let path = dir.join(format!("cells_day{:02}.csv", d.day));
        write_atomic(&path, csv.as_bytes())?;
        written.push(path);
        let png = voronoi(params, &d.cells)?;
        let path = dir.join(format!("day_{:02}.png", d.day));
        write_atomic(&path, &png)?;
        written.push(path);
    }
    if let Some(last) = days.last() {
        let path = dir.join("mosaic.png");
        write_atomic(&path, &voronoi(params, &last.cells)?)?;
        written.push(path);
    }
    if let Some(mask) = &params.mask {
        let path = dir.join("mask.pbm");
        write_atomic(&path, write_pbm(mask).as_bytes())?;
        written.push(path);
    }
    Ok(written)
}

/// Nearest-cell lookup on a uniform grid, periodic where the domain wraps.
struct Nearest<'a> {
    cells: &'a [(u32, u8, f64, f64)],
    size: [f64; 2],
    periodic: [bool; 2],
    n: [usize; 2],
    side: [f64; 2],
    bins: Vec<Vec<u32>>,
}

impl<'a> Nearest<'a> {
    fn new(params: &Params, cells: &'a [(u32, u8, f64, f64)]) -> Nearest<'a> {
        let size = params
            .domain
            .size
            .map(|s| f64::from(s.to_bits()) / 65_536.0);
        let spacing = (size[0] * size[1] / cells.len().max(1) as f64).sqrt();
        let n = size.map(|s| ((s / spacing) as usize).clamp(1, 4096));
        let side = [size[0] / n[0] as f64, size[1] / n[1] as f64];
        let mut bins = vec![Vec::new(); n[0] * n[1]];
        for (i, c) in cells.iter().enumerate() {
            let bx = ((c.2 / side[0]) as usize).min(n[0] - 1);
            let by = ((c.3 / side[1]) as usize).min(n[1] - 1);
            bins[by * n[0] + bx].push(i as u32);
        }
        Nearest {
            cells,
            size,
            periodic: params.domain.periodic,
            n,
            side,
            bins,
        }
    }

    fn delta(&self, axis: usize, a: f64, b: f64) -> f64 {
        let d = a - b;
        if self.periodic[axis] {
            let s = self.size[axis];
            d - s * (d / s).round()
        } else {
            d
        }
    }

    /// The index of the cell nearest to `(x, y)` (ties: lowest index).
    fn find(&self, x: f64, y: f64) -> Option<usize> {
        let bx = ((x / self.side[0]) as isize).clamp(0, self.n[0] as isize - 1);
        let by = ((y / self.side[1]) as isize).clamp(0, self.n[1] as isize - 1);
        let mut best: Option<(f64, usize)> = None;
        let rings = self.n[0].max(self.n[1]) as isize;
        for k in 0..=rings {
            // Cells in ring k are at least (k − 1)·side away.
            let reach = (k - 1).max(0) as f64 * self.side[0].min(self.side[1]);
            if best.is_some_and(|(d2, _)| d2 < reach * reach) {
                break;
            }
            for dy in -k..=k {
                for dx in -k..=k {
                    if dx.abs() != k && dy.abs() != k {
                        continue;
                    }
                    let Some(b) = self.bin(bx + dx, by + dy) else {
                        continue;
                    };
                    for &i in &self.bins[b] {
                        let c = &self.cells[i as usize];
                        let ddx = self.delta(0, x, c.2);
                        let ddy = self.delta(1, y, c.3);
                        let d2 = ddx * ddx + ddy * ddy;
                        if best.is_none_or(|(bd, bi)| d2 < bd || (d2 == bd && (i as usize) < bi)) {
                            best = Some((d2, i as usize));
                        }
                    }
                }
            }
        }
        best.map(|(_, i)| i)
    }

    fn bin(&self, x: isize, y: isize) -> Option<usize> {
        let wrap = |v: isize, n: usize, periodic: bool| {
            if (0..n as isize).contains(&v) {
                Some(v as usize)
            } else if periodic && n >= 3 {
                Some(v.rem_euclid(n as isize) as usize)
            } else {
                None
            }
        };
        Some(
            wrap(y, self.n[1], self.periodic[1])? * self.n[0]
                + wrap(x, self.n[0], self.periodic[0])?,
        )
    }
}

/// The Voronoi picture of `cells` as PNG bytes.
///
/// # Errors
/// An empty domain or a failed encoding.
pub fn voronoi(params: &Params, cells: &[(u32, u8, f64, f64)]) -> Result<Vec<u8>> {
    let near = Nearest::new(params, cells);
    let scale = LONG_SIDE / near.size[0].max(near.size[1]);
    let w = ((near.size[0] * scale).round() as u32).max(1);
    let h = ((near.size[1] * scale).round() as u32).max(1);
    let mut pixmap = Pixmap::new(w, h).context("picture size must be positive")?;
    let colour = |kind: u8| {
        params
            .types
            .get(kind as usize)
            .map_or([128, 128, 128], |t| t.colour)
    };
    let pixels = pixmap.pixels_mut();
    for py in 0..h {
        for px in 0..w {
            let x = (f64::from(px) + 0.5) / scale;
            let y = (f64::from(py) + 0.5) / scale;
            let c = near
                .find(x, y)
                .map_or([255, 255, 255], |i| colour(cells[i].1));
            pixels[(py * w + px) as usize] =
                ColorU8::from_rgba(c[0], c[1], c[2], 255).premultiply();
        }
    }
    pixmap.encode_png().context("cannot encode PNG")
}

/// A mask as a plain PBM (P1): PBM's 1 is black, i.e. *not* allowed.
#[must_use]
pub fn write_pbm(mask: &Mask) -> String {
    let mut s = format!(
        "P1\n# morphogen mosaic mask: white (0) allows foreground cells\n{} {}\n",
        mask.width, mask.height
    );
    for y in 0..u32::from(mask.height) {
        let row: Vec<&str> = (0..u32::from(mask.width))
            .map(|x| if mask.pixel(x, y) { "0" } else { "1" })
            .collect();
        s.push_str(&row.join(" "));
        s.push('\n');
    }
    s
}

/// Reads the mask file `path`, a PNG (by its signature; see [`read_png`])
/// or else a PBM ([`read_pbm`]), into a [`Mask`] whose bits are leaked:
/// one mask per run.
///
/// # Errors
/// An unreadable or malformed file, or a side beyond the [`Mask`] limit.
pub fn read_mask(path: &Path) -> Result<Mask> {
    let bytes = fs::read(path).with_context(|| format!("cannot read mask {}", path.display()))?;
    let (width, height, bits) = if bytes.starts_with(PNG_SIGNATURE) {
        read_png(&bytes)
    } else {
        read_pbm(&bytes)
    }
    .with_context(|| format!("mask {}", path.display()))?;
    Ok(Mask {
        width,
        height,
        bits: bits.leak(),
    })
}

/// The first bytes of every PNG file.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// The core [`Mask`]'s limit, named in errors.
const SIDE_LIMIT: &str = "a mask side is at most 65535 pixels (the core Mask's u16)";

/// Reads a PNG mask into the core's packed rows, like [`read_pbm`]: a pixel
/// is white (allowed) when its alpha and its luminance (Rec. 709 weights of
/// the stored R, G, B) are both at least 50 %.
///
/// # Errors
/// An undecodable PNG, or a side beyond 65 535 pixels (the [`Mask`]'s `u16`).
pub fn read_png(bytes: &[u8]) -> Result<(u16, u16, Vec<u8>)> {
    let be32 = |at: usize| {
        bytes
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_be_bytes)
    };
    // The sizes in IHDR (the first chunk), checked before decoding
    // allocates the whole image.
    if let (Some(b"IHDR"), Some(w), Some(h)) = (bytes.get(12..16), be32(16), be32(20))
        && w.max(h) > u32::from(u16::MAX)
    {
        bail!("PNG: {w}×{h} pixels: {SIDE_LIMIT}");
    }
    let pixmap = Pixmap::decode_png(bytes).context("PNG: cannot decode")?;
    let side = |v: u32| u16::try_from(v).with_context(|| format!("PNG: {v} pixels: {SIDE_LIMIT}"));
    let (width, height) = (side(pixmap.width())?, side(pixmap.height())?);
    let stride = Mask::stride(width);
    let mut bits = vec![0u8; stride * usize::from(height)];
    for (i, p) in pixmap.pixels().iter().enumerate() {
        let c = p.demultiply();
        // 10 000·Y, Y = 0.2126 R + 0.7152 G + 0.0722 B; 50 % of 255 is 127.5.
        let luma =
            2126 * u32::from(c.red()) + 7152 * u32::from(c.green()) + 722 * u32::from(c.blue());
        if 2 * luma >= 2_550_000 && 2 * u32::from(c.alpha()) >= 255 {
            let (x, y) = (i % usize::from(width), i / usize::from(width));
            bits[y * stride + x / 8] |= 0x80 >> (x % 8);
        }
    }
    Ok((width, height, bits))
}

/// Reads a PBM mask (plain P1 or raw P4) into the core's packed rows
/// (1 = white = allowed): `(width, height, bits)`.
///
/// # Errors
/// A malformed file, with what is wrong and where.
pub fn read_pbm(bytes: &[u8]) -> Result<(u16, u16, Vec<u8>)> {
    let mut pos = 0;
    let mut token = |bytes: &[u8]| -> Result<String> {
        loop {
            while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
                pos += 1;
            }
            if pos < bytes.len() && bytes[pos] == b'#' {
                while pos < bytes.len() && bytes[pos] != b'\n' {
                    pos += 1;
                }
                continue;
            }
            break;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && bytes[pos] != b'#' {
            pos += 1;
        }
        if start == pos {
            bail!("PBM: unexpected end of header at byte {start}");
        }
        Ok(String::from_utf8_lossy(&bytes[start..pos]).into_owned())
    };
    let magic = token(bytes)?;
    let dim = |t: String, what: &str| -> Result<u16> {
        match t.parse::<u16>() {
            Ok(v) if v > 0 => Ok(v),
            _ => bail!("PBM: {what} '{t}' is not a number in 1..=65535: {SIDE_LIMIT}"),
        }
    };
    let width = dim(token(bytes)?, "width")?;
    let height = dim(token(bytes)?, "height")?;
    let stride = Mask::stride(width);
    let mut bits = vec![0u8; stride * usize::from(height)];
    match magic.as_str() {
        "P1" => {
            let mut i = 0usize;
            let total = usize::from(width) * usize::from(height);
            while i < total {
                while pos < bytes.len() && (bytes[pos].is_ascii_whitespace()) {
                    pos += 1;
                }
                match bytes.get(pos) {
                    Some(b'0') => {
                        let (x, y) = (i % usize::from(width), i / usize::from(width));
                        bits[y * stride + x / 8] |= 0x80 >> (x % 8);
                    }
                    Some(b'1') => {}
                    Some(b'#') => {
                        while pos < bytes.len() && bytes[pos] != b'\n' {
                            pos += 1;
                        }
                        continue;
                    }
                    Some(c) => bail!(
                        "PBM: pixel {i}: '{}' is not 0 or 1 (byte {pos})",
                        *c as char
                    ),
                    None => bail!("PBM: {i} of {total} pixels, then the file ends"),
                }
                pos += 1;
                i += 1;
            }
        }
        "P4" => {
            pos += 1; // the single whitespace after the height
            let data = bytes.get(pos..pos + bits.len()).with_context(|| {
                format!(
                    "PBM: raster needs {} bytes after byte {pos}, file has {}",
                    bits.len(),
                    bytes.len().saturating_sub(pos)
                )
            })?;
            for (b, d) in bits.iter_mut().zip(data) {
                *b = !d;
            }
            // Clear the padding bits of each row.
            let pad = (stride * 8 - usize::from(width)) as u32;
            if pad > 0 {
                for y in 0..usize::from(height) {
                    bits[y * stride + stride - 1] &= 0xFFu8 << pad;
                }
            }
        }
        other => bail!("PBM: magic '{other}' is neither P1 nor P4"),
    }
    Ok((width, height, bits))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbm_round_trips_and_rejects_garbage() {
        // Rows of 9 bits take 2 bytes each; the 7 padding bits stay clear.
        static BITS: [u8; 4] = [0b1010_0000, 0b1000_0000, 0, 0b1000_0000];
        let mask = Mask {
            width: 9,
            height: 2,
            bits: &BITS,
        };
        let text = write_pbm(&mask);
        let (w, h, bits) = read_pbm(text.as_bytes()).unwrap();
        assert_eq!((w, h, bits.as_slice()), (9, 2, &BITS[..]));
        let mut raw = b"P4\n9 2\n".to_vec();
        raw.extend(BITS.iter().map(|b| !b));
        assert_eq!(read_pbm(&raw).unwrap().2, BITS.to_vec());
        assert!(
            read_pbm(b"P1\n2 2\n0 1 2 0")
                .unwrap_err()
                .to_string()
                .contains("not 0 or 1")
        );
        assert!(
            read_pbm(b"P4\n9 2\n\x00")
                .unwrap_err()
                .to_string()
                .contains("raster needs 4 bytes")
        );
        assert!(read_pbm(b"P3\n1 1\n").is_err());
    }

    #[test]
    fn png_pixels_are_white_from_half_luminance_and_half_alpha() {
        // One row of 9 pixels: (R, G, B, A) and whether it allows F.
        let row: [([u8; 4], bool); 9] = [
            ([255, 255, 255, 255], true),
            ([0, 0, 0, 255], false),
            ([128, 128, 128, 255], true),  // Y = 50.2 %
            ([127, 127, 127, 255], false), // Y = 49.8 %
            ([0, 255, 0, 255], true),      // Y = 71.5 %
            ([255, 0, 0, 255], false),     // Y = 21.3 %
            ([255, 255, 255, 128], true),  // A = 50.2 %
            ([255, 255, 255, 127], false), // A = 49.8 %
            ([255, 255, 255, 0], false),
        ];
        let mut pixmap = Pixmap::new(9, 2).unwrap();
        for (p, ([r, g, b, a], _)) in pixmap.pixels_mut().iter_mut().zip(&row) {
            *p = ColorU8::from_rgba(*r, *g, *b, *a).premultiply();
        }
        let (width, height, bits) = read_png(&pixmap.encode_png().unwrap()).unwrap();
        assert_eq!((width, height), (9, 2));
        let mask = Mask {
            width,
            height,
            bits: bits.leak(),
        };
        assert!(mask.is_valid());
        let allowed: Vec<bool> = (0..9).map(|x| mask.pixel(x, 0)).collect();
        let expected: Vec<bool> = row.iter().map(|(_, white)| *white).collect();
        assert_eq!(allowed, expected);
        // Row 1 is transparent black: nothing allowed, padding clear.
        assert_eq!(&mask.bits[2..], &[0, 0]);
        assert!(
            read_png(b"\x89PNG\r\n\x1a\nnot really")
                .unwrap_err()
                .to_string()
                .contains("PNG: cannot decode")
        );
        let wide = Pixmap::new(70_000, 1).unwrap().encode_png().unwrap();
        assert!(
            read_png(&wide)
                .unwrap_err()
                .to_string()
                .contains("at most 65535")
        );
        // A huge size is refused from the header, before any decoding.
        let mut huge = wide[..16].to_vec();
        huge.extend(100_000u32.to_be_bytes().repeat(2));
        assert_eq!(
            read_png(&huge).unwrap_err().to_string(),
            format!("PNG: 100000×100000 pixels: {SIDE_LIMIT}")
        );
    }
}
