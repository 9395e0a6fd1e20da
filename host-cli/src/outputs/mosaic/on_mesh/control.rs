//! A surface mosaic's pattern unrolled onto its control map (thesis Sec.
//! 3.2.2: the turn around z and the height on the control cylinder, or x
//! and y on a plane), so that the figures of a pattern on a fruit are
//! measured as on a cylinder's side ([`Raster`]): every pixel takes the
//! type most of the surface's sample points that land on it have.

use morphogen::fx::Real as _;
use morphogen::mosaic::ControlMap;
use morphogen::mosaic::Params;

use super::Shell;
use super::nearest::{Along, Nearest};
use crate::outputs::mosaic::Raster;

/// The longest side of the unrolled picture, in pixels.
const LONG_SIDE: f64 = 400.0;

/// The most samples along a triangle's side.
const MAX_SAMPLES: usize = 96;

/// Palette indices as the Voronoi pictures number them: no sample, then
/// the types from 2.
const EMPTY: u8 = 0;

/// The pattern of a day unrolled onto the control map of `params`.
#[derive(Debug)]
pub(super) struct Unrolled {
    pixels: Vec<u8>,
    width: usize,
    unit: [f64; 2],
    periodic: [bool; 2],
}

impl Unrolled {
    /// Samples every triangle of `shell` densely enough that each pixel it
    /// covers gets points, and lets each pixel's points vote for its type.
    pub(super) fn new(shell: &Shell, near: &Nearest, params: &Params, types: usize) -> Unrolled {
        let size = params.domain.size.map(f64::from_fx);
        let scale = LONG_SIDE / size[0].max(size[1]);
        let (w, h) = (
            ((size[0] * scale).round() as usize).max(1),
            ((size[1] * scale).round() as usize).max(1),
        );
        let cylinder = params.surface.map(|s| s.control) != Some(ControlMap::Plane);
        let (lo, hi) = shell.bounds();
        let map = Map {
            lo,
            hi,
            size: [w as f64, h as f64],
            cylinder,
        };
        let kinds = types.min(usize::from(u8::MAX) - 2);
        let mut ballot = Ballot {
            votes: vec![0u32; w * h * kinds.max(1)],
            width: w,
            kinds,
        };
        // The points one after another, each near the one before: a
        // search only where the last one's type may not hold.
        let mut along = Along::new(near);
        let mut pixels = Pixels::new(&map);
        for f in &shell.faces {
            let corners = shell.corners(f);
            let face = Face {
                samples: map.samples(&corners),
                corners,
            };
            // Rows back and forth: each point next to the one before.
            for i in 0..face.samples {
                let row = face.samples - i;
                for n in 0..row {
                    let j = if i % 2 == 0 { n } else { row - 1 - n };
                    let p = face.point(i, j);
                    if let Some(kind) = along.kind_at(&p) {
                        ballot.vote(pixels.of(&p), kind);
                    }
                }
            }
        }
        Unrolled {
            pixels: ballot.count(),
            width: w,
            unit: [size[0] / w as f64, size[1] / h as f64],
            periodic: [cylinder, false],
        }
    }

    /// It as a [`Raster`], for the pattern's figures.
    pub(super) fn raster(&self) -> Raster<'_> {
        Raster {
            pixels: &self.pixels,
            width: self.width,
            unit: self.unit,
            periodic: self.periodic,
        }
    }
}

/// A triangle of the surface and its samples: (i, j) for i + j < s,
/// s = `samples`, at barycentric (i + 1/3, j + 1/3) / s.
struct Face {
    corners: [[f64; 3]; 3],
    samples: usize,
}

impl Face {
    /// The point of sample (i, j).
    fn point(&self, i: usize, j: usize) -> [f64; 3] {
        let [a, b, c] = self.corners;
        let s = self.samples as f64;
        let (x, y) = ((i as f64 + 1.0 / 3.0) / s, (j as f64 + 1.0 / 3.0) / s);
        [0, 1, 2].map(|k| a[k] + x * (b[k] - a[k]) + y * (c[k] - a[k]))
    }
}

/// Points of the surface to pixels of the unrolled picture.
struct Map {
    /// The surface's bounds.
    lo: [f64; 3],
    hi: [f64; 3],
    /// The picture's width and height, pixels.
    size: [f64; 2],
    /// Whether the control map is the cylinder (else the plane).
    cylinder: bool,
}

impl Map {
    /// How far `x` is along axis `c` of the bounds, from 0 to 1.
    fn frac(&self, x: f64, c: usize) -> f64 {
        (x - self.lo[c]) / (self.hi[c] - self.lo[c]).max(1e-12)
    }

    /// (u, v) in pixels of a point.
    fn uv(&self, p: &[f64; 3]) -> [f64; 2] {
        let [w, h] = self.size;
        if self.cylinder {
            // atan2 is within ±π: its remainder by τ is itself, and
            // rem_euclid(τ) only adds τ to a negative turn.
            let turn = p[1].atan2(p[0]);
            let turn = if turn < 0.0 {
                turn + std::f64::consts::TAU
            } else {
                turn
            };
            [turn / std::f64::consts::TAU * w, self.frac(p[2], 2) * h]
        } else {
            [self.frac(p[0], 0) * w, self.frac(p[1], 1) * h]
        }
    }

    /// The pixel (column, row) a point lands on.
    fn pixel(&self, p: &[f64; 3]) -> [usize; 2] {
        let q = self.uv(p);
        // `as` saturates below 0 and truncates above it: the floor's
        // pixel, without a call to floor.
        [0, 1].map(|k| (q[k] as usize).min(self.size[k] as usize - 1))
    }

    /// The samples along a side of the triangle `corners`: two a pixel
    /// along its longest side in the picture, at least 2.
    fn samples(&self, corners: &[[f64; 3]; 3]) -> usize {
        let mut uv = corners.map(|c| self.uv(&c));
        let w = self.size[0];
        if self.cylinder {
            // A triangle across the seam: its corners on one side.
            let (min, max) = uv
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
            if max - min > w / 2.0 {
                for p in &mut uv {
                    if p[0] < w / 2.0 {
                        p[0] += w;
                    }
                }
            }
        }
        let extent = (0..3)
            .map(|i| {
                let (a, b) = (uv[i], uv[(i + 1) % 3]);
                (a[0] - b[0]).abs().max((a[1] - b[1]).abs())
            })
            .fold(0.0, f64::max);
        ((extent * 2.0).ceil() as usize).clamp(2, MAX_SAMPLES)
    }
}

/// The pixels of points one after another, each near the one before: on
/// the cylinder, a point's column is the last one's or its neighbour's
/// when its turn lies inside that column by a margin (two cross products
/// with the column's edges, far cheaper than `atan2`); else, and on the
/// plane, [`Map::pixel`]. Inside by the margin, `atan2` would give that
/// column too: its rounding is some 10⁻¹⁶ of a turn, the margin 10⁻⁹.
struct Pixels<'m> {
    map: &'m Map,
    /// The direction of each column's first edge, and the last's end.
    edges: Vec<[f64; 2]>,
    /// The last point's column.
    column: usize,
}

impl<'m> Pixels<'m> {
    fn new(map: &'m Map) -> Pixels<'m> {
        let w = map.size[0] as usize;
        let edges = if map.cylinder {
            (0..=w)
                .map(|k| {
                    let turn = k as f64 / w as f64 * std::f64::consts::TAU;
                    [turn.cos(), turn.sin()]
                })
                .collect()
        } else {
            Vec::new()
        };
        Pixels {
            map,
            edges,
            column: 0,
        }
    }

    /// The pixel (column, row) the point `p` lands on.
    fn of(&mut self, p: &[f64; 3]) -> [usize; 2] {
        if let Some(column) = self.near_column(p[0], p[1]) {
            // The row as `Map::pixel` finds it on the cylinder.
            let h = self.map.size[1];
            let v = self.map.frac(p[2], 2) * h;
            return [column, (v as usize).min(h as usize - 1)];
        }
        let pixel = self.map.pixel(p);
        self.column = pixel[0];
        pixel
    }

    /// The column of (x, y) if it is the last point's or a neighbour of
    /// it, inside by the margin.
    fn near_column(&mut self, x: f64, y: f64) -> Option<usize> {
        let w = self.edges.len().checked_sub(1)?;
        let margin = 1e-9 * (x.abs() + y.abs());
        let inside = |k: usize| {
            let (a, b) = (self.edges[k], self.edges[k + 1]);
            a[0] * y - a[1] * x > margin && x * b[1] - y * b[0] > margin
        };
        let last = self.column;
        let next = if last + 1 == w { 0 } else { last + 1 };
        let before = if last == 0 { w - 1 } else { last - 1 };
        let column = [last, next, before].into_iter().find(|&k| inside(k))?;
        self.column = column;
        Some(column)
    }
}

/// Each pixel's votes, type by type.
struct Ballot {
    votes: Vec<u32>,
    width: usize,
    /// The types that vote (the others' points are not counted).
    kinds: usize,
}

impl Ballot {
    /// A point of type `kind` at `pixel`.
    fn vote(&mut self, [x, y]: [usize; 2], kind: u8) {
        if usize::from(kind) < self.kinds {
            self.votes[(y * self.width + x) * self.kinds + usize::from(kind)] += 1;
        }
    }

    /// Each pixel's type: the one with most votes, the lowest of equal
    /// ones ([`EMPTY`] without votes), numbered as the palette's.
    fn count(self) -> Vec<u8> {
        self.votes
            .chunks(self.kinds.max(1))
            .map(|v| {
                let (best, n) = v
                    .iter()
                    .enumerate()
                    .max_by_key(|&(k, n)| (*n, usize::MAX - k))
                    .unwrap_or((0, &0));
                if *n == 0 { EMPTY } else { best as u8 + 2 }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A walk around and along a cylinder of 400 columns, in steps of a
    /// fraction of a column, some points on the columns' edges and on the
    /// seam: every pixel as `atan2` would place it.
    #[test]
    fn pixels_of_a_walk_are_those_of_atan2() {
        let map = Map {
            lo: [-3.0, -3.0, -1.0],
            hi: [3.0, 3.0, 5.0],
            size: [400.0, 160.0],
            cylinder: true,
        };
        let mut pixels = Pixels::new(&map);
        let tau = std::f64::consts::TAU;
        let mut turn = 0.0f64;
        for step in 0..200_000u32 {
            let t = f64::from(step);
            // Mostly small steps either way; now and then exactly an edge.
            turn += (t * 0.618).sin() * 0.006;
            let on_edge = step % 97 == 0;
            let at = if on_edge {
                (turn / tau * 400.0).round() / 400.0 * tau
            } else {
                turn
            };
            let r = 0.5 + 2.0 * (t * 0.013).sin().abs();
            let p = [r * at.cos(), r * at.sin(), 2.0 + 2.5 * (t * 0.001).sin()];
            assert_eq!(pixels.of(&p), map.pixel(&p), "step {step}, turn {at}");
        }
        // Points on the axis, where no column holds them.
        for p in [[0.0, 0.0, 1.0], [-0.0, 0.0, 1.0], [1e-300, -0.0, 1.0]] {
            assert_eq!(pixels.of(&p), map.pixel(&p), "{p:?}");
        }
    }
}
