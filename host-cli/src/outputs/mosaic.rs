//! Mosaic presets (MClone): per streamed day a CSV of the cells
//! (`cells_dayNN.csv`: `id,type,x,y`) and a Voronoi picture
//! (`day_NN.png`: every pixel takes the colour of the type of its nearest
//! cell, distances periodic where the domain wraps, the cylinder unrolled
//! with u to the right and v down); `mosaic.png` is the last day; the
//! control mask, if any, as `mask.pbm`. [`read_mask`] reads a user's mask
//! (PBM or PNG).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::mosaic::Params;
use morphogen::stream::Record;
use tiny_skia::{ColorU8, Pixmap};

use crate::atomic::write_atomic;

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
        write_atomic(&path, morphogen_scenario::mask::to_pbm(mask).as_bytes())?;
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
