//! A surface mosaic's object as a picture: seen once from an elevation
//! (per pixel the nearest face's depth and shade, smooth between its
//! corners), then painted for every day in its cells' colours, a square
//! of pixels at a time.

use anyhow::Result;
use rayon::prelude::*;
use tiny_skia::{Pixmap, PremultipliedColorU8};

use super::Shell;
use super::nearest::{Along, Cell, Nearest, Reach, nearest_among};
use crate::outputs::mesh::Rgb;
use crate::outputs::normals;
use nalgebra::Vector3;

use crate::outputs::normals::unit;

/// The picture's longer side in pixels (drawn at twice the size, halved).
const PICTURE_SIDE: f64 = 700.0;
/// The side of the squares of pixels [`View::paint`] colours at once
/// (at twice the picture's size).
const TILE: usize = 16;
/// The light's direction (towards the light), normalised when used.
const LIGHT: [f64; 3] = [-0.4, -0.6, 0.7];
/// The shade level of a pixel that shows no face ([`View::level`]).
const NOTHING: u8 = 0;
/// The picture's background.
const BACKGROUND: Rgb = [246, 244, 238];

impl Shell {
    /// The shade at each corner of each face: 0.35 + 0.65 |n · l| for the
    /// light l and the normal n there ([`normals::corner_normals`]), so a
    /// picture shaded between the corners is smooth where the surface is
    /// and keeps its edges.
    fn corner_shades(&self) -> Vec<[f64; 3]> {
        let light = unit(Vector3::from(LIGHT));
        normals::corner_normals(&self.vertices, &self.faces)
            .into_iter()
            .map(|corners| corners.map(|n| 0.35 + 0.65 * Vector3::from(n).dot(&light).abs()))
            .collect()
    }
    /// The object seen from `elevation` radians above its equator
    /// (orthographic, z up) at twice the picture's size: per pixel the
    /// depth of the nearest face and its shade there, found once for all
    /// the days (the mesh does not move).
    pub(super) fn view(&self, elevation: f64) -> View {
        let [right, up, towards] = axes(elevation);
        let screen: Vec<[f64; 3]> = self
            .vertices
            .iter()
            .map(|&p| {
                let p = Vector3::from(p);
                [p.dot(&right), p.dot(&up), p.dot(&towards)]
            })
            .collect();
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for s in &screen {
            for k in 0..2 {
                lo[k] = lo[k].min(s[k]);
                hi[k] = hi[k].max(s[k]);
            }
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-9);
        let scale = 2.0 * PICTURE_SIDE / (span * 1.1);
        let margin = 0.05 * span;
        let w = (((hi[0] - lo[0]) + 2.0 * margin) * scale).ceil().max(1.0) as usize;
        let h = (((hi[1] - lo[1]) + 2.0 * margin) * scale).ceil().max(1.0) as usize;
        let to_px = |s: &[f64; 3]| {
            [
                (s[0] - lo[0] + margin) * scale,
                (hi[1] - s[1] + margin) * scale,
                s[2],
            ]
        };
        let corners = self.corner_shades();
        // Depth of the nearest triangle per pixel, and its shade there.
        let mut depth = vec![f64::MIN; w * h];
        let mut level = vec![NOTHING; w * h];
        for (f, shades) in self.faces.iter().zip(&corners) {
            let [a, b, c] = f.map(|i| to_px(&screen[i as usize]));
            depth_shade([a, b, c], shades, w, &mut depth, &mut level);
        }
        let mut view = View {
            w,
            h,
            scale,
            top: hi[1] + margin,
            axes: [right, up, towards].map(Into::into),
            columns: (0..w)
                .map(|x| {
                    let across = (x as f64 + 0.5) / scale + lo[0] - margin;
                    (right * across).into()
                })
                .collect(),
            depth,
            level,
            boxes: Vec::new(),
        };
        view.boxes = view.boxes();
        view
    }
}

/// Draws the triangle `[a, b, c]` (pixel x, y and depth) into a picture
/// `w` pixels wide: where it is nearer than `depth`, its depth and its
/// shade, interpolated between the corners' `shades`, as a `level`.
fn depth_shade(
    [a, b, c]: [[f64; 3]; 3],
    shades: &[f64; 3],
    w: usize,
    depth: &mut [f64],
    level: &mut [u8],
) {
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
    let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(w);
    let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
    let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(depth.len() / w.max(1));
    // The weights of a and b, linear in the pixel's centre (px, py):
    // k[0] + k[1]·px + k[2]·py; c's is what they leave of 1.
    let inv = 1.0 / area;
    let ka = [b[0] * c[1] - b[1] * c[0], b[1] - c[1], c[0] - b[0]].map(|k| k * inv);
    let kb = [c[0] * a[1] - c[1] * a[0], c[1] - a[1], a[0] - c[0]].map(|k| k * inv);
    for y in y0..y1 {
        let py = y as f64 + 0.5;
        let (ra, rb) = (ka[0] + ka[2] * py, kb[0] + kb[2] * py);
        let weights = [(ra, ka[1]), (rb, kb[1]), (1.0 - ra - rb, -ka[1] - kb[1])];
        for x in row_span(weights, x0, x1) {
            let px = x as f64 + 0.5;
            let wa = ra + ka[1] * px;
            let wb = rb + kb[1] * px;
            let wc = 1.0 - wa - wb;
            if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                continue;
            }
            let z = wa * a[2] + wb * b[2] + wc * c[2];
            let k = y * w + x;
            if z > depth[k] {
                depth[k] = z;
                // Within the corners' shades, all in [0.35, 1]:
                // a level of at least 89, never NOTHING.
                let shade = wa * shades[0] + wb * shades[1] + wc * shades[2];
                level[k] = (shade * 255.0 + 0.5) as u8;
            }
        }
    }
}

/// The pixels `x0..x1` of a row that a triangle may cover: where each of
/// its three weights, `r + k·px` at the pixel's centre px, may be ≥ 0 —
/// a pixel wider on each side than the weights say, so rounding cannot
/// leave out a pixel the exact test would take. A weight nearly constant
/// along the row (|k| ≤ 10⁻⁶ a pixel) bounds nothing unless it stays
/// below 0 all along.
fn row_span(weights: [(f64, f64); 3], x0: usize, x1: usize) -> std::ops::Range<usize> {
    let (mut from, mut to) = (x0 as f64, x1 as f64);
    for (r, k) in weights {
        // The centre where the weight is 0, as a pixel index.
        let zero = -r / k - 0.5;
        if k > 1e-6 {
            from = from.max(zero.floor() - 1.0);
        } else if k < -1e-6 {
            to = to.min(zero.ceil() + 2.0);
        } else if r + k.abs() * (to + 1.0) < -1e-9 {
            return x0..x0;
        }
    }
    // `as` saturates: a bound below 0 is 0.
    (from as usize).max(x0)..(to as usize).min(x1)
}

/// The screen's right, up and the direction towards the viewer, who sees
/// the object from `elevation` radians above its equator (z up).
pub(super) fn axes(elevation: f64) -> [Vector3<f64>; 3] {
    let (sin_e, cos_e) = elevation.sin_cos();
    let towards = Vector3::new(0.0, -cos_e, sin_e);
    let right = Vector3::x();
    [right, towards.cross(&right), towards]
}

/// A surface mosaic's object as [`Shell::view`] sees it.
pub(super) struct View {
    /// Width and height, pixels (twice the picture's).
    w: usize,
    h: usize,
    /// Pixels a unit.
    scale: f64,
    /// The screen's up at the picture's top edge (the mesh's highest and
    /// the margin above it), units.
    top: f64,
    /// Right, up and towards the viewer.
    axes: [[f64; 3]; 3],
    /// Per column, the part of its points that the column makes (`right`
    /// times the screen's right of the pixels' centres): [`View::point`].
    columns: Vec<[f64; 3]>,
    /// Per pixel: the depth towards the viewer of the nearest face, and
    /// its shade there in 255ths ([`NOTHING`]: no face).
    depth: Vec<f64>,
    level: Vec<u8>,
    /// Per [`TILE`]-square of pixels (row by row), the least and greatest
    /// corner of the box around the points it shows, then the same of its
    /// quarters and of theirs ([`SQUARES`] in all: [`View::square`]); an
    /// empty box where no pixel shows the object.
    boxes: Vec<[[f64; 3]; 2]>,
}

/// The squares of a [`TILE`]-square [`View::boxes`] keeps, down to
/// squares of side `TILE / 4`: 1 + 4 + 16.
const SQUARES: usize = 21;

/// A box around no point: the least corner past the greatest.
const NO_BOX: [[f64; 3]; 2] = [[f64::MAX; 3], [f64::MIN; 3]];

impl View {
    /// The part of the points of row `y` that its height makes (`up` times
    /// the screen's up of the pixels' centres), for [`View::point`].
    fn row(&self, y: usize) -> [f64; 3] {
        let up = self.top - (y as f64 + 0.5) / self.scale;
        self.axes[1].map(|k| k * up)
    }

    /// The point of the object pixel `(x, y)` shows (that of the plane of
    /// its face), `row` its row's part ([`View::row`]): right · s₀ + up ·
    /// s₁ + towards · depth, s₀ and s₁ the screen's right and up of the
    /// pixel's centre.
    fn point(&self, row: [f64; 3], x: usize, y: usize) -> [f64; 3] {
        let column = self.columns[x];
        let depth = self.depth[y * self.w + x];
        [0, 1, 2].map(|i| column[i] + row[i] + self.axes[2][i] * depth)
    }

    /// [`TILE`]-squares across the picture.
    fn tiles_across(&self) -> usize {
        self.w.div_ceil(TILE)
    }

    /// The place in a tile's [`View::boxes`] of its square at `level`
    /// (0: the tile; 1: a quarter; 2: a quarter's quarter) at column and
    /// row `at` of that level's squares.
    fn square(level: usize, at: [usize; 2]) -> usize {
        [0, 1, 5][level] + at[1] * (1 << level) + at[0]
    }

    /// The boxes around the points of every square of every tile (the
    /// mesh does not move: found once).
    fn boxes(&self) -> Vec<[[f64; 3]; 2]> {
        let across = self.tiles_across();
        let mut boxes = vec![NO_BOX; across * self.h.div_ceil(TILE) * SQUARES];
        boxes
            .par_chunks_mut(across * SQUARES)
            .enumerate()
            .for_each(|(band, boxes)| {
                for y in band * TILE..((band + 1) * TILE).min(self.h) {
                    let row = self.row(y);
                    for x in 0..self.w {
                        if self.level[y * self.w + x] == NOTHING {
                            continue;
                        }
                        let p = self.point(row, x, y);
                        let tile = &mut boxes[(x / TILE) * SQUARES..(x / TILE + 1) * SQUARES];
                        let side = TILE >> 2;
                        let [lo, hi] =
                            &mut tile[Self::square(2, [x % TILE / side, y % TILE / side])];
                        for k in 0..3 {
                            lo[k] = lo[k].min(p[k]);
                            hi[k] = hi[k].max(p[k]);
                        }
                    }
                }
                // A square's box is the union of its quarters' boxes.
                for tile in boxes.chunks_exact_mut(SQUARES) {
                    for level in [1, 0] {
                        for at in (0..1 << level).flat_map(|y| (0..1 << level).map(move |x| [x, y]))
                        {
                            let [mut lo, mut hi] = NO_BOX;
                            for [qx, qy] in [[0, 0], [1, 0], [0, 1], [1, 1]] {
                                let quarter =
                                    Self::square(level + 1, [2 * at[0] + qx, 2 * at[1] + qy]);
                                let [qlo, qhi] = tile[quarter];
                                for k in 0..3 {
                                    lo[k] = lo[k].min(qlo[k]);
                                    hi[k] = hi[k].max(qhi[k]);
                                }
                            }
                            tile[Self::square(level, at)] = [lo, hi];
                        }
                    }
                }
            });
        boxes
    }

    /// A canvas for [`View::paint`], its size.
    pub(super) fn canvas(&self) -> Result<Pixmap> {
        let (w, h) = (self.w, self.h);
        Pixmap::new(w as u32, h as u32)
            .ok_or_else(|| anyhow::anyhow!("a {w}×{h} picture is too large"))
    }

    /// The object shaded on `canvas` (from [`View::canvas`]), every point
    /// in its nearest cell's colour, a [`TILE`]-square of pixels at a time
    /// ([`View::colour_square`]): every pixel is painted, so one canvas
    /// serves every day.
    pub(super) fn paint(&self, near: &Nearest, colours: &[[u8; 3]], canvas: &mut Pixmap) {
        let w = self.w;
        let across = self.tiles_across();
        let shaded = Shaded::new(colours);
        canvas
            .pixels_mut()
            .par_chunks_mut(w * TILE)
            .enumerate()
            .for_each(|(band, rows)| {
                // The cells of a tile, of a quarter and of a quarter's quarter.
                let mut scratch = vec![Vec::new(); 3];
                for tile in 0..across {
                    let square = Square {
                        tile: band * across + tile,
                        level: 0,
                        at: [0, 0],
                        corner: [tile * TILE, band * TILE],
                    };
                    self.colour_square(near, &shaded, square, None, &mut scratch, rows);
                }
            });
    }

    /// Colours the pixels of `square` into `rows` (the band of [`TILE`]
    /// rows it is in), the cells `wider` holding the nearest of every
    /// point it shows (none: the tile, whose cells are gathered from the
    /// grid; [`Nearest::near_box`]): when the box around its points has
    /// one type, that type's colour; else quarter by quarter, each with
    /// the cells (in `scratch[0]`) that may be nearest to its points, down
    /// to the smallest squares [`View::boxes`] keeps, then each pixel by
    /// the nearest of those.
    fn colour_square(
        &self,
        near: &Nearest,
        shaded: &Shaded,
        square: Square,
        wider: Option<&[Cell]>,
        scratch: &mut [Vec<Cell>],
        rows: &mut [PremultipliedColorU8],
    ) {
        let [lo, hi] = self.boxes[square.tile * SQUARES + Self::square(square.level, square.at)];
        let Some((cells, deeper)) = scratch.split_first_mut() else {
            return;
        };
        let reach = if lo[0] > hi[0] {
            Reach::One(None) // nothing shown: all background
        } else if let Some(wider) = wider {
            near.narrow(wider, lo, hi, cells)
        } else {
            near.near_box(lo, hi, cells)
        };
        if reach == Reach::Among && square.level < 2 {
            for [qx, qy] in [[0, 0], [1, 0], [0, 1], [1, 1]] {
                let side = TILE >> (square.level + 1);
                let quarter = Square {
                    level: square.level + 1,
                    at: [square.at[0] * 2 + qx, square.at[1] * 2 + qy],
                    corner: [square.corner[0] + qx * side, square.corner[1] + qy * side],
                    ..square
                };
                self.colour_square(near, shaded, quarter, Some(cells), deeper, rows);
            }
            return;
        }
        let side = TILE >> square.level;
        let [x0, y0] = square.corner;
        // Only when the cells were too far to gather: searched, but for
        // the pixels near enough the last one searched.
        let mut along = Along::new(near);
        let x1 = (x0 + side).min(self.w);
        for y in y0..(y0 + side).min(self.h) {
            let part = self.row(y);
            let row = &mut rows[(y % TILE) * self.w..][x0..x1];
            let levels = &self.level[y * self.w..][x0..x1];
            if let Reach::One(kind) = reach {
                // One type for the whole square: its column of the table.
                let column = shaded.column(kind);
                for (px, &level) in row.iter_mut().zip(levels) {
                    *px = column[usize::from(level)];
                }
                continue;
            }
            for (x, (px, &level)) in (x0..x1).zip(row.iter_mut().zip(levels)) {
                let kind = match reach {
                    _ if level == NOTHING => None,
                    Reach::One(kind) => kind,
                    Reach::Among => nearest_among(cells, &self.point(part, x, y)).map(|(_, k)| k),
                    Reach::Far => along.kind_at(&self.point(part, x, y)),
                };
                *px = shaded.column(kind)[usize::from(level)];
            }
        }
    }
}

/// Each type's colour at each shade ([`View::paint`]).
struct Shaded {
    /// Type by type, the last for a type the parameters do not name
    /// (grey), the colour at each level of [`View::level`]: at
    /// [`NOTHING`] the background.
    colours: Vec<[PremultipliedColorU8; 256]>,
}

impl Shaded {
    fn new(colours: &[[u8; 3]]) -> Shaded {
        let opaque = |[r, g, b]: Rgb| {
            PremultipliedColorU8::from_rgba(r, g, b, 255)
                .unwrap_or(PremultipliedColorU8::TRANSPARENT)
        };
        let colours = colours
            .iter()
            .chain([&[128; 3]])
            .map(|c| {
                std::array::from_fn(|level| match level {
                    0 => opaque(BACKGROUND),
                    // level ≤ 255: rounded, in 0..=255.
                    _ => opaque(c.map(|c| ((u32::from(c) * level as u32 + 127) / 255) as u8)),
                })
            })
            .collect();
        Shaded { colours }
    }

    /// The colours of type `kind` (none: the last, grey).
    fn column(&self, kind: Option<u8>) -> &[PremultipliedColorU8; 256] {
        let last = self.colours.len() - 1;
        &self.colours[kind.map_or(last, |k| usize::from(k).min(last))]
    }
}

/// A square of pixels [`View::colour_square`] colours.
#[derive(Debug, Clone, Copy)]
struct Square {
    /// Its tile, row by row.
    tile: usize,
    /// 0: the tile; 1: a quarter; 2: a quarter's quarter.
    level: usize,
    /// Its column and row among its level's squares of the tile.
    at: [usize; 2],
    /// Its first pixel's column and row in the picture.
    corner: [usize; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A globe of radius `r`: `rings` bands from pole to pole of
    /// `segments` facets each.
    fn globe(r: f64, rings: u32, segments: u32) -> Shell {
        let (vertices, faces) = normals::tests::globe(r, rings, segments);
        Shell { vertices, faces }
    }

    /// The largest step in shade between neighbouring pixels of the
    /// middle of the picture (half its width and height) that both show
    /// the object.
    fn largest_step(view: &View) -> u8 {
        let mut step = 0;
        for y in view.h / 4..view.h * 3 / 4 {
            for x in view.w / 4..view.w * 3 / 4 {
                let here = view.level[y * view.w + x];
                let (right, down) = (x + 1 < view.w, y + 1 < view.h);
                for there in [
                    right.then(|| view.level[y * view.w + x + 1]),
                    down.then(|| view.level[(y + 1) * view.w + x]),
                ]
                .into_iter()
                .flatten()
                {
                    if here != NOTHING && there != NOTHING {
                        step = step.max(here.abs_diff(there));
                    }
                }
            }
        }
        step
    }

    #[test]
    fn a_smooth_surface_shades_smoothly_and_an_edge_stays_an_edge() {
        // A globe of facets 15° apart: one shade a facet steps by up to
        // 0.65 · sin 15° (43 levels) from facet to facet. (At the limb the
        // shade turns fast even on a true sphere: the middle of the
        // picture shows its side that faces the viewer.)
        let globe = globe(40.0, 12, 24);
        let view = globe.view(0.35);
        let smooth = largest_step(&view);
        assert!(smooth <= 4, "a step of {smooth} levels");
        // Wound either way, the same shades.
        let mut mixed = globe.clone();
        for f in mixed.faces.iter_mut().step_by(2) {
            f.swap(1, 2);
        }
        assert!(mixed.view(0.35).level == view.level);
        // A cube's faces meet at 90°: edges. It shows its top and front,
        // each in one shade (to rounding).
        let (vertices, faces) = normals::tests::cube(40.0);
        let view = Shell { vertices, faces }.view(0.35);
        let levels: std::collections::BTreeSet<u8> = view
            .level
            .iter()
            .copied()
            .filter(|&l| l != NOTHING)
            .collect();
        assert!(levels.len() <= 4, "{levels:?}");
    }

    #[test]
    fn a_squares_box_is_the_box_of_the_points_its_pixels_show() {
        // An octahedron: six vertices on the axes, eight faces.
        let r = 40.0;
        let shell = Shell {
            vertices: vec![
                [r, 0.0, 0.0],
                [-r, 0.0, 0.0],
                [0.0, r, 0.0],
                [0.0, -r, 0.0],
                [0.0, 0.0, r],
                [0.0, 0.0, -r],
            ],
            faces: vec![
                [0, 2, 4],
                [2, 1, 4],
                [1, 3, 4],
                [3, 0, 4],
                [2, 0, 5],
                [1, 2, 5],
                [3, 1, 5],
                [0, 3, 5],
            ],
        };
        let view = shell.view(0.35);
        let mut want = vec![NO_BOX; view.boxes.len()];
        let mut shown = 0;
        for y in 0..view.h {
            for x in 0..view.w {
                if view.level[y * view.w + x] == NOTHING {
                    continue;
                }
                shown += 1;
                let p = view.point(view.row(y), x, y);
                let tile = (y / TILE) * view.tiles_across() + x / TILE;
                for level in 0..3 {
                    let side = TILE >> level;
                    let at = [x % TILE / side, y % TILE / side];
                    let [lo, hi] = &mut want[tile * SQUARES + View::square(level, at)];
                    for k in 0..3 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
            }
        }
        assert!(shown > 100_000, "{shown} pixels show the octahedron");
        assert!(view.boxes == want);
    }

    #[test]
    fn a_row_span_keeps_every_pixel_the_triangle_covers() {
        // Triangles of every shape and size, some slivers, some nearly
        // flat along a row; the pixels each row's span leaves out are
        // ones the weights' test refuses.
        let (mut kept, mut spanned, mut rows) = (0, 0, 0);
        for i in 0..2_000u32 {
            let t = f64::from(i);
            let at = |k: f64| {
                let r = [3.0, 40.0, 400.0][i as usize % 3] * (1.0 + (t * k).sin());
                [
                    200.0 + r * (t * k * 1.7).cos(),
                    200.0 + r * (t * k * 2.3).sin(),
                ]
            };
            let (a, b) = (at(0.37), at(0.91));
            // Every fifth: c on a's row, so an edge is along the rows.
            let c = if i % 5 == 0 {
                [at(1.31)[0], a[1]]
            } else {
                at(1.31)
            };
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area.abs() < 1e-12 {
                continue;
            }
            let inv = 1.0 / area;
            let ka = [b[0] * c[1] - b[1] * c[0], b[1] - c[1], c[0] - b[0]].map(|k| k * inv);
            let kb = [c[0] * a[1] - c[1] * a[0], c[1] - a[1], a[0] - c[0]].map(|k| k * inv);
            let (x0, x1) = (0, 900);
            for y in 0..900 {
                let py = f64::from(y) + 0.5;
                let (ra, rb) = (ka[0] + ka[2] * py, kb[0] + kb[2] * py);
                let span = row_span(
                    [(ra, ka[1]), (rb, kb[1]), (1.0 - ra - rb, -ka[1] - kb[1])],
                    x0,
                    x1,
                );
                for x in x0..x1 {
                    let px = x as f64 + 0.5;
                    let wa = ra + ka[1] * px;
                    let wb = rb + kb[1] * px;
                    let wc = 1.0 - wa - wb;
                    if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
                        assert!(span.contains(&x), "{x} out of {span:?}, row {y}");
                        kept += 1;
                    }
                }
                spanned += span.len();
                rows += usize::from(!span.is_empty());
            }
        }
        assert!(kept > 1_000_000, "{kept}");
        // Spans are a pixel or two wider on each side than the triangle.
        assert!(
            spanned <= kept + 5 * rows,
            "{spanned} for {kept} in {rows} rows"
        );
    }
}
