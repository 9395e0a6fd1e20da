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
        for f in &shell.faces {
            let corners = shell.corners(f);
            let face = Face {
                samples: map.samples(&corners),
                corners,
            };
            for i in 0..face.samples {
                for j in 0..face.samples - i {
                    let p = face.point(i, j);
                    if let Some(kind) = along.kind_at(&p) {
                        ballot.vote(map.pixel(&p), kind);
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
    /// (u, v) in pixels of a point.
    fn uv(&self, p: &[f64; 3]) -> [f64; 2] {
        let frac = |x: f64, c: usize| (x - self.lo[c]) / (self.hi[c] - self.lo[c]).max(1e-12);
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
            [turn / std::f64::consts::TAU * w, frac(p[2], 2) * h]
        } else {
            [frac(p[0], 0) * w, frac(p[1], 1) * h]
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
