//! The Voronoi picture of a day's cells: every pixel takes the colour of
//! the type of its nearest cell, distances periodic where the domain
//! wraps.
//!
//! The picture finds each pixel's nearest cell tile by tile: the cell
//! nearest the tile's centre bounds how far any pixel of the tile can be
//! from its own nearest cell, so only the cells (and their periodic images,
//! placed once per tile) within that reach of the tile are compared, in
//! plain arithmetic per pixel.

use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::mosaic::Domain;

use super::object::pattern_pixel;
use crate::outputs::driver::Still;
use crate::outputs::kinds::Pixels;

use super::pattern::Raster;

/// The longest side of the pictures, in pixels.
const LONG_SIDE: f64 = 900.0;

/// The tile side, in multiples of the pixels between neighbouring cells
/// (about a cell per tile: few cells within reach of it, and a tile of
/// several types is split further by [`Canvas::split`]), and its limits
/// in pixels. Of 0.5, 1 and 2 (4 to 16 pixels at least), 1 and 8 drew
/// croton's and croton-mcu's days in the fewest instructions.
const TILE: (f64, usize, usize) = (1.0, 8, 64);

/// A cell placed for one tile: position (a periodic image, in domain
/// units), its order in the day (ties go to the lower), palette index.
#[derive(Debug, Clone, Copy)]
struct Site {
    x: f64,
    y: f64,
    order: u32,
    colour: u8,
}

/// The cells of a day in a uniform grid of bins (about one cell a bin),
/// periodic where the domain wraps.
struct Bins {
    /// The sites bin by bin, each bin's in their order.
    sites: Vec<Site>,
    size: [f64; 2],
    periodic: [bool; 2],
    n: [i64; 2],
    side: [f64; 2],
    /// Per bin, the start of its sites in `sites`; one more at the end.
    starts: Vec<usize>,
}

impl Bins {
    fn new(domain: &Domain, sites: Vec<Site>) -> Bins {
        let size = domain.size.map(f64::from_fx);
        let spacing = (size[0] * size[1] / sites.len().max(1) as f64).sqrt();
        let n = size.map(|s| ((s / spacing) as i64).clamp(1, 4096));
        let side = [size[0] / n[0] as f64, size[1] / n[1] as f64];
        let bin_of = |s: &Site| {
            let bx = ((s.x / side[0]) as i64).clamp(0, n[0] - 1);
            let by = ((s.y / side[1]) as i64).clamp(0, n[1] - 1);
            (by * n[0] + bx) as usize
        };
        // Counting sort of the sites by bin.
        let mut starts = vec![0usize; (n[0] * n[1]) as usize + 1];
        for s in &sites {
            starts[bin_of(s) + 1] += 1;
        }
        for b in 1..starts.len() {
            starts[b] += starts[b - 1];
        }
        let mut fill = starts.clone();
        let mut binned = sites.clone();
        for s in sites {
            let b = bin_of(&s);
            binned[fill[b]] = s;
            fill[b] += 1;
        }
        Bins {
            sites: binned,
            size,
            periodic: domain.periodic,
            n,
            side,
            starts,
        }
    }

    /// Calls `each` with every site of bin `(bx, by)` — any integers: past
    /// the grid on a periodic axis it is a shifted image, else nothing.
    fn visit(&self, bx: i64, by: i64, mut each: impl FnMut(Site)) {
        let mut shift = [0.0; 2];
        let mut at = [bx, by];
        for k in 0..2 {
            if !(0..self.n[k]).contains(&at[k]) {
                if !self.periodic[k] {
                    return;
                }
                shift[k] = at[k].div_euclid(self.n[k]) as f64 * self.size[k];
                at[k] = at[k].rem_euclid(self.n[k]);
            }
        }
        let b = (at[1] * self.n[0] + at[0]) as usize;
        for &s in &self.sites[self.starts[b]..self.starts[b + 1]] {
            each(Site {
                x: s.x + shift[0],
                y: s.y + shift[1],
                ..s
            });
        }
    }

    fn bin(&self, x: f64, axis: usize) -> i64 {
        (x / self.side[axis]).floor() as i64
    }

    /// The site (image) nearest to `(x, y)`, searched ring by ring of bins.
    fn nearest(&self, x: f64, y: f64) -> Option<Site> {
        let (bx, by) = (self.bin(x, 0), self.bin(y, 1));
        let mut best: Option<(f64, Site)> = None;
        let rings = self.n[0].max(self.n[1]) + 1;
        for k in 0..=rings {
            for dy in -k..=k {
                let step = if dy.abs() == k { 1 } else { 2 * k.max(1) };
                let mut dx = -k;
                while dx <= k {
                    self.visit(bx + dx, by + dy, |s| {
                        let d2 = (s.x - x).powi(2) + (s.y - y).powi(2);
                        if best.is_none_or(|(b, _)| d2 < b) {
                            best = Some((d2, s));
                        }
                    });
                    dx += step;
                }
            }
            // Bins of ring k + 1 are at least k sides away.
            let reach = k as f64 * self.side[0].min(self.side[1]);
            if best.is_some_and(|(d2, _)| d2 <= reach * reach) {
                break;
            }
        }
        best.map(|(_, s)| s)
    }

    /// Every site image that can be nearest to a point of the box
    /// `lo`–`hi`, by order, into `out`, and the first of them: those
    /// within reach of the box, the reach being the distance from the
    /// site nearest the box's middle to the box's corner farthest from it
    /// (distance is convex, so no point of the box is farther from its
    /// own nearest site).
    fn near_tile<'a>(
        &self,
        lo: [f64; 2],
        hi: [f64; 2],
        out: &'a mut Vec<Site>,
    ) -> Option<&'a Site> {
        let s = self.nearest((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0)?;
        self.near_box(lo, hi, farthest_corner(&s, lo, hi), out);
        out.first()
    }

    /// Every site image within `reach` of the box `lo`–`hi`, by order.
    fn near_box(&self, lo: [f64; 2], hi: [f64; 2], reach: f64, out: &mut Vec<Site>) {
        out.clear();
        let (bx0, bx1) = (self.bin(lo[0] - reach, 0), self.bin(hi[0] + reach, 0));
        let (by0, by1) = (self.bin(lo[1] - reach, 1), self.bin(hi[1] + reach, 1));
        let limit = wider(reach).powi(2);
        for by in by0..=by1 {
            for bx in bx0..=bx1 {
                self.visit(bx, by, |s| out.push(s));
            }
        }
        keep_within(lo, hi, limit, out);
        out.sort_unstable_by_key(|s| s.order);
    }
}

/// The site of `sites` nearest to `p`, the first of equals.
fn nearest_to(sites: &[Site], p: [f64; 2]) -> Option<&Site> {
    let mut nearest = 0;
    let mut best = f64::INFINITY;
    for (i, s) in sites.iter().enumerate() {
        let d2 = (s.x - p[0]) * (s.x - p[0]) + (s.y - p[1]) * (s.y - p[1]);
        let closer = d2 < best;
        best = if closer { d2 } else { best };
        nearest = if closer { i } else { nearest };
    }
    sites.get(nearest)
}

/// The distance from `s` to the corner of the box `lo`–`hi` farthest
/// from it: the farther side along each axis.
fn farthest_corner(s: &Site, lo: [f64; 2], hi: [f64; 2]) -> f64 {
    let far_x = (s.x - lo[0]).abs().max((s.x - hi[0]).abs());
    let far_y = (s.y - lo[1]).abs().max((s.y - hi[1]).abs());
    (far_x * far_x + far_y * far_y).sqrt()
}

/// `reach` made slightly wider, so that rounding cannot drop a tie.
fn wider(reach: f64) -> f64 {
    reach * (1.0 + 1e-9) + 1e-9
}

/// Keeps the sites of `sites` whose squared distance from the box
/// `lo`–`hi` is at most `limit`, in their order. Every site is written,
/// the next one over it unless it is kept: no branch on which are (one,
/// mispredicted for many sites, cost more than the test itself).
fn keep_within(lo: [f64; 2], hi: [f64; 2], limit: f64, sites: &mut Vec<Site>) {
    let mut kept = 0;
    for i in 0..sites.len() {
        let s = sites[i];
        let dx = (lo[0] - s.x).max(s.x - hi[0]).max(0.0);
        let dy = (lo[1] - s.y).max(s.y - hi[1]).max(0.0);
        sites[kept] = s;
        kept += usize::from(dx * dx + dy * dy <= limit);
    }
    sites.truncate(kept);
}

/// Palette index of pixels no cell reaches (an empty day): white.
const EMPTY: u8 = 0;
/// Palette index of cells of a type the parameters do not name: grey.
const UNKNOWN: u8 = 1;

/// The size of a mosaic's pictures, pixels: [`LONG_SIDE`] along the
/// domain's longer side.
pub(super) fn picture_size(domain: &Domain) -> (usize, usize) {
    let size = domain.size.map(f64::from_fx);
    let scale = LONG_SIDE / size[0].max(size[1]);
    let w = ((size[0] * scale).round() as usize).max(1);
    let h = ((size[1] * scale).round() as usize).max(1);
    (w, h)
}

/// A picture of palette indices, one byte a pixel.
#[derive(Debug)]
pub struct Indexed {
    width: usize,
    height: usize,
    palette: Vec<[u8; 3]>,
    pixels: Vec<u8>,
    /// The pixels of each palette index but [`EMPTY`], counted as they
    /// were coloured.
    counts: Box<[u64; 256]>,
}

impl Still for Indexed {
    fn pixels(&self) -> Pixels<'_> {
        Pixels::Indexed {
            size: (self.width as u32, self.height as u32),
            palette: &self.palette,
            indices: &self.pixels,
        }
    }
}

impl Indexed {
    /// The pixels of each of the first `types` types (the Voronoi area of
    /// its cells, in pixels).
    #[must_use]
    pub fn areas(&self, types: usize) -> Vec<u64> {
        self.counts[2..].iter().take(types).copied().collect()
    }

    /// The picture as a [`Raster`] of `domain`, for its pattern's figures.
    #[must_use]
    pub fn raster(&self, domain: &Domain) -> Raster<'_> {
        let size = domain.size.map(f64::from_fx);
        Raster {
            pixels: &self.pixels,
            width: self.width,
            unit: [size[0] / self.width as f64, size[1] / self.height as f64],
            periodic: domain.periodic,
        }
    }

    /// The colour at the fractions (`u`, `v`) of its width and height
    /// (clamped into the picture).
    #[must_use]
    pub fn at(&self, u: f64, v: f64) -> [u8; 3] {
        self.colour(pattern_pixel([self.width, self.height], u, v))
    }

    /// The colour of pixel `i` (row by row): its [`palette`](Self::palette)
    /// entry, black past the palette.
    #[must_use]
    pub fn colour(&self, i: usize) -> [u8; 3] {
        self.palette
            .get(usize::from(self.index(i)))
            .copied()
            .unwrap_or([0; 3])
    }

    /// The palette index of pixel `i` (row by row); past the picture, that
    /// of an empty day.
    #[must_use]
    pub fn index(&self, i: usize) -> u8 {
        self.pixels.get(i).copied().unwrap_or(EMPTY)
    }

    /// The colours its pixels index.
    #[must_use]
    pub fn palette(&self) -> &[[u8; 3]] {
        &self.palette
    }

    /// The palette index of every pixel, row by row.
    #[must_use]
    pub fn indices(&self) -> &[u8] {
        &self.pixels
    }
}

/// The pixels of a Voronoi picture being coloured.
struct Canvas<'a> {
    pixels: &'a mut [u8],
    /// The pixels coloured with each palette index so far.
    counts: &'a mut [u64; 256],
    width: usize,
    /// The domain coordinate of the centre of pixel `p` along either
    /// axis, `(p + 0.5) / scale` with `scale` pixels a domain unit.
    centres: &'a [f64],
}

/// A box of at most this many pixels is coloured pixel by pixel.
const LEAF_PIXELS: usize = 64;

impl Canvas<'_> {
    /// Colours the pixels `x0..=x1` × `y0..=y1`, whose nearest cells are
    /// all in `near` (by order), quadrant by quadrant: a quadrant whose
    /// candidates within reach are of one type is filled, the others are
    /// split again down to [`LEAF_PIXELS`], then coloured by their nearest
    /// candidate. The same pixels as testing every candidate at every
    /// pixel: a quadrant's nearest cells are among its candidates, which
    /// keep their order (ties still go to the lower). `scratch` holds the
    /// candidates of each depth.
    fn split(
        &mut self,
        [x0, y0, x1, y1]: [usize; 4],
        near: &[Site],
        depth: usize,
        scratch: &mut Vec<Vec<Site>>,
    ) {
        let (mx, my) = ((x0 + x1) / 2, (y0 + y1) / 2);
        let xs = [(x0, mx), (mx + 1, x1)];
        let ys = [(y0, my), (my + 1, y1)];
        if scratch.len() <= depth {
            scratch.push(Vec::new());
        }
        for &(qy0, qy1) in ys.iter().filter(|(a, b)| a <= b) {
            for &(qx0, qx1) in xs.iter().filter(|(a, b)| a <= b) {
                let mut candidates = std::mem::take(&mut scratch[depth]);
                self.quadrant([qx0, qy0, qx1, qy1], near, &mut candidates);
                let pixels = (qx1 - qx0 + 1) * (qy1 - qy0 + 1);
                match candidates.first() {
                    Some(first) if candidates.iter().all(|c| c.colour == first.colour) => {
                        self.counts[usize::from(first.colour)] += pixels as u64;
                        for py in qy0..=qy1 {
                            self.pixels[py * self.width + qx0..=py * self.width + qx1]
                                .fill(first.colour);
                        }
                    }
                    _ if pixels <= LEAF_PIXELS => {
                        self.each_pixel([qx0, qy0, qx1, qy1], &candidates);
                    }
                    _ => self.split([qx0, qy0, qx1, qy1], &candidates, depth + 1, scratch),
                }
                scratch[depth] = candidates;
            }
        }
    }

    /// The sites of `near` within reach of the box `x0..=x1` × `y0..=y1`
    /// (by order) into `out`: as `Bins::near_box`, the reach being the
    /// distance from the candidate nearest the box's middle to the box's
    /// farthest corner, which no pixel's nearest cell is farther than.
    fn quadrant(&self, [x0, y0, x1, y1]: [usize; 4], near: &[Site], out: &mut Vec<Site>) {
        out.clear();
        let (lo, hi) = (
            [self.centres[x0], self.centres[y0]],
            [self.centres[x1], self.centres[y1]],
        );
        let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        // The candidate nearest the middle: any one would bound the reach,
        // the nearest bounds it tightest.
        let Some(s) = nearest_to(near, mid) else {
            return;
        };
        out.extend_from_slice(near);
        keep_within(lo, hi, wider(farthest_corner(s, lo, hi)).powi(2), out);
    }

    /// Colours each pixel of the box by its nearest site of `near`, the
    /// first of equals winning: [`ROW`] pixels of a row at a time, each
    /// site compared with all of them (independent lanes, no branch).
    fn each_pixel(&mut self, [x0, y0, x1, y1]: [usize; 4], near: &[Site]) {
        for py in y0..=y1 {
            let y = self.centres[py];
            let row = py * self.width;
            let xs = self.centres[x0..=x1].chunks(ROW);
            let pixels = self.pixels[row + x0..=row + x1].chunks_mut(ROW);
            for (xs, pixels) in xs.zip(pixels) {
                // Past the box's edge, pixels infinitely far: never nearer.
                let mut x = [f64::INFINITY; ROW];
                x[..xs.len()].copy_from_slice(xs);
                let mut best = [f64::INFINITY; ROW];
                let mut colour = [EMPTY; ROW];
                for s in near {
                    let dy2 = (y - s.y) * (y - s.y);
                    for ((x, best), colour) in x.iter().zip(&mut best).zip(&mut colour) {
                        let d2 = (x - s.x) * (x - s.x) + dy2;
                        // All ones where nearer (the first of equals stays).
                        let nearer = u8::from(d2 < *best).wrapping_neg();
                        *colour = (*colour & !nearer) | (s.colour & nearer);
                        *best = best.min(d2);
                    }
                }
                for (pixel, &c) in pixels.iter_mut().zip(&colour) {
                    *pixel = c;
                    self.counts[usize::from(c)] += 1;
                }
            }
        }
    }
}

/// The pixels of a row that [`Canvas::each_pixel`] colours side by side.
const ROW: usize = 4;

/// The palette of a Voronoi picture: [`EMPTY`] white, [`UNKNOWN`] grey,
/// then the types' `colours` (at most 254 of them).
pub(super) fn palette(colours: &[[u8; 3]]) -> Vec<[u8; 3]> {
    let mut palette = vec![[255, 255, 255], [128, 128, 128]];
    palette.extend(colours.iter().take(254));
    palette
}

/// The Voronoi picture of `cells` on `domain`, type `k` in `colours[k]`.
#[must_use]
pub fn voronoi(domain: &Domain, colours: &[[u8; 3]], cells: &[(u32, u8, Fx, Fx)]) -> Indexed {
    let palette = palette(colours);
    let sites = cells
        .iter()
        .enumerate()
        .map(|(i, &(_, kind, x, y))| Site {
            x: f64::from_fx(x),
            y: f64::from_fx(y),
            order: i as u32,
            colour: if usize::from(kind) + 2 < palette.len() {
                kind + 2
            } else {
                UNKNOWN
            },
        })
        .collect();
    let bins = Bins::new(domain, sites);
    let scale = LONG_SIDE / bins.size[0].max(bins.size[1]);
    let (w, h) = picture_size(domain);
    let spacing = (w * h) as f64 / bins.sites.len().max(1) as f64;
    let tile = ((spacing.sqrt() * TILE.0) as usize).clamp(TILE.1, TILE.2);
    let mut pixels = vec![EMPTY; w * h];
    let mut counts = Box::new([0; 256]);
    let centres: Vec<f64> = (0..w.max(h)).map(|p| (p as f64 + 0.5) / scale).collect();
    let centre = |p: usize| centres[p];
    let mut near = Vec::new();
    let mut scratch = Vec::new();
    for ty in (0..h).step_by(tile) {
        for tx in (0..w).step_by(tile) {
            let (px1, py1) = ((tx + tile).min(w) - 1, (ty + tile).min(h) - 1);
            let (lo, hi) = ([centre(tx), centre(ty)], [centre(px1), centre(py1)]);
            let Some(&s) = bins.near_tile(lo, hi, &mut near) else {
                continue;
            };
            if near.iter().all(|n| n.colour == s.colour) {
                // One type within reach: the whole tile has its colour.
                counts[usize::from(s.colour)] += ((px1 + 1 - tx) * (py1 + 1 - ty)) as u64;
                for py in ty..=py1 {
                    pixels[py * w + tx..=py * w + px1].fill(s.colour);
                }
                continue;
            }
            let mut canvas = Canvas {
                pixels: &mut pixels,
                counts: &mut counts,
                width: w,
                centres: &centres,
            };
            canvas.split([tx, ty, px1, py1], &near, 0, &mut scratch);
        }
    }
    Indexed {
        width: w,
        height: h,
        palette,
        pixels,
        counts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outputs::picture::save_indexed;

    /// The nearest cell by brute force, ties to the first, periodic
    /// distances where the domain wraps.
    fn brute(domain: &Domain, sites: &[Site], x: f64, y: f64) -> u8 {
        let size = domain.size.map(f64::from_fx);
        let delta = |axis: usize, d: f64| {
            if domain.periodic[axis] {
                d - size[axis] * (d / size[axis]).round()
            } else {
                d
            }
        };
        let mut best = (f64::INFINITY, EMPTY);
        for s in sites {
            let d2 = delta(0, x - s.x).powi(2) + delta(1, y - s.y).powi(2);
            if d2 < best.0 {
                best = (d2, s.colour);
            }
        }
        best.1
    }

    #[test]
    fn of_cells_in_one_place_the_first_colours_its_pixels() {
        // A child can be placed on its parent: the picture must not depend
        // on which of two equally near cells a pixel's search meets last.
        let types = [[200, 0, 0], [0, 200, 0]];
        let domain = Domain {
            size: [Fx::from_int(90), Fx::from_int(30)],
            periodic: [true, false],
        };
        let at = |x: i32, y: i32| (Fx::from_int(x), Fx::from_int(y));
        for first in [0u8, 1] {
            let mut cells = vec![(0, 1 - first, at(10, 5).0, at(10, 5).1)];
            for (i, kind) in [first, 1 - first].into_iter().enumerate() {
                let (x, y) = at(45, 15);
                cells.push((i as u32 + 1, kind, x, y));
            }
            cells.push((3, 1 - first, at(80, 25).0, at(80, 25).1));
            let drawn = voronoi(&domain, &types, &cells);
            // Pixels around (45, 15), 10 pixels a unit: all the first's.
            for (px, py) in [(450, 150), (449, 149), (430, 160), (470, 140)] {
                assert_eq!(drawn.colour(py * 900 + px), types[usize::from(first)]);
            }
        }
    }

    #[test]
    fn tiles_find_the_same_nearest_cells_as_brute_force() {
        let types = [[200, 0, 0], [0, 200, 0]];
        let mut seed = 7u64;
        let mut random = |n: i32| {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((seed >> 33) % n as u64) as i32
        };
        for periodic in [[false, false], [true, false], [true, true]] {
            for count in [1usize, 3, 40, 700] {
                let domain = Domain {
                    size: [Fx::from_int(90), Fx::from_int(30)],
                    periodic,
                };
                let cells: Vec<(u32, u8, Fx, Fx)> = (0..count)
                    .map(|i| {
                        let x = Fx::from_bits(random(90 << 16));
                        let y = Fx::from_bits(random(30 << 16));
                        (i as u32, (random(3)) as u8, x, y)
                    })
                    .collect();
                let dir = tempfile::tempdir().unwrap();
                let path = dir.path().join("v.png");
                let drawn = voronoi(&domain, &types, &cells);
                // The areas counted while colouring are the pixels' own.
                let mut counted = vec![0u64; types.len()];
                for &i in &drawn.pixels {
                    if let Some(n) = counted.get_mut(usize::from(i).wrapping_sub(2)) {
                        *n += 1;
                    }
                }
                assert_eq!(drawn.areas(types.len()), counted);
                let size = (drawn.width as u32, drawn.height as u32);
                let (palette, indices) = (drawn.palette(), drawn.indices());
                save_indexed(size.0, size.1, palette, indices, &path).unwrap();
                let picture = tiny_skia::Pixmap::load_png(&path).unwrap();
                let bins = Bins::new(&domain, Vec::new());
                let scale = LONG_SIDE / bins.size[0];
                let colours = [[255, 255, 255], [128, 128, 128], [200, 0, 0], [0, 200, 0]];
                let sites: Vec<Site> = cells
                    .iter()
                    .enumerate()
                    .map(|(i, c)| Site {
                        x: f64::from_fx(c.2),
                        y: f64::from_fx(c.3),
                        order: i as u32,
                        colour: if c.1 < 2 { c.1 + 2 } else { UNKNOWN },
                    })
                    .collect();
                for py in (0..picture.height()).step_by(7) {
                    for px in (0..picture.width()).step_by(3) {
                        let x = (f64::from(px) + 0.5) / scale;
                        let y = (f64::from(py) + 0.5) / scale;
                        let want = colours[usize::from(brute(&domain, &sites, x, y))];
                        let got = picture.pixel(px, py).unwrap();
                        assert_eq!(
                            [got.red(), got.green(), got.blue()],
                            want,
                            "{periodic:?} {count} cells, pixel ({px}, {py})"
                        );
                    }
                }
            }
        }
    }
}
