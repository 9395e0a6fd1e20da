//! Mosaics grown on a mesh (MClone thesis Secs. 3.2, 4.1; the core's
//! `mosaic::surface`): per streamed day `cells_dayNN.csv` (`id,type,x,y,z`)
//! and a shaded picture of the object with every point coloured by its
//! nearest cell (`surface_dayNN.png`; `surface.png` the last day);
//! `surface.obj` the mesh the cells live on, `mosaic.obj` the last day
//! coloured on it (a colour per vertex, on the mesh split twice);
//! `types.csv` each type's share of the cells and of the area (the area
//! by sampling every triangle); the cell counts chart and the mask as for
//! the plane.

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::mosaic::Params;
use morphogen::mosaic::surface::ControlMap;
use morphogen::stream::Record;
use rayon::prelude::*;
use tiny_skia::{Pixmap, PremultipliedColorU8};

use super::mesh::{Mesh, ObjStyle, Rgb, write_obj};
use super::mosaic::{write_counts_and_mask, write_csv, write_shares};
use super::normals;
use super::picture;
use super::vector::{cross, dot, sub, unit};
use super::{Kind, Kinds};
use crate::atomic;
use crate::records::{Place, Records};

/// The picture's longer side in pixels (drawn at twice the size, halved).
const PICTURE_SIDE: f64 = 700.0;
/// The most cubes [`Nearest::near_box`] gathers cells from.
const BOX_CUBES: i64 = 4_096;
/// The side of the squares of pixels [`View::paint`] colours at once
/// (at twice the picture's size).
const TILE: usize = 16;
/// The most cubes of the nearest-cell search per cell ([`Nearest`]).
const CUBES_PER_CELL: i64 = 8;
/// The light's direction (towards the light), normalised when used.
const LIGHT: [f64; 3] = [-0.4, -0.6, 0.7];
/// The shade level of a pixel that shows no face ([`View::level`]).
const NOTHING: u8 = 0;
/// The picture's background.
const BACKGROUND: Rgb = [246, 244, 238];
/// Sample points per triangle side for the area shares (s(s+1)/2 each).
const AREA_SAMPLES: usize = 6;

/// The mesh of a surface mosaic's stream, in units.
#[derive(Debug, Default, Clone)]
pub struct Shell {
    /// Vertices.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles.
    pub faces: Vec<[u32; 3]>,
}

/// One streamed day: `(id, type, point)` of each cell.
#[derive(Debug, Default)]
pub struct Day {
    /// The day number.
    pub day: i32,
    /// The cells.
    pub cells: Vec<(u32, u8, [f64; 3])>,
}

/// The mesh and the days of a surface mosaic's stream.
///
/// # Errors
/// When the records cannot be read.
pub fn read<R: Records + ?Sized>(records: &R) -> Result<(Shell, Vec<Day>)> {
    let mut shell = Shell::default();
    let mut days: Vec<Day> = Vec::new();
    let units = |p: &[morphogen::fx::Fx; 3]| p.map(|x| f64::from(x.to_bits()) / 65_536.0);
    records.visit(Place::START, |_, r| {
        match r {
            Record::FrameStart { time, .. } => days.push(Day {
                day: time.floor_int(),
                cells: Vec::new(),
            }),
            Record::MeshVertex { p, .. } => shell.vertices.push(units(p)),
            Record::Triangle { v } => shell.faces.push(*v),
            Record::SurfaceCell { id, kind, p } => {
                if let Some(d) = days.last_mut() {
                    d.cells.push((*id, *kind, units(p)));
                }
            }
            _ => {}
        }
        Ok(())
    })?;
    Ok((shell, days))
}

/// The nearest cell of any point, through a uniform grid of cubes.
struct Nearest {
    lo: [f64; 3],
    side: f64,
    dims: [i64; 3],
    /// `(index in the day's list, type, point)` of the cells, cube by cube
    /// (x fastest), and each cube's start in it.
    sorted: Vec<(u32, u8, [f64; 3])>,
    starts: Vec<u32>,
}

impl Nearest {
    fn new(cells: &[(u32, u8, [f64; 3])], shell: &Shell) -> Nearest {
        let mut lo = [f64::MAX; 3];
        let mut hi = [f64::MIN; 3];
        for p in shell.vertices.iter().chain(cells.iter().map(|c| &c.2)) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let extent: f64 = (0..3).map(|k| (hi[k] - lo[k]).max(1e-9)).product::<f64>();
        // About one cell per cube the surface crosses: cubes of the cells'
        // spacing, the surface's area guessed from the extent; but no more
        // than [`CUBES_PER_CELL`] cubes a cell (a surface crosses few of
        // them, and many cells make many empty ones).
        let area_guess = extent.powf(2.0 / 3.0) * 3.0;
        let mut side = (area_guess / cells.len().max(1) as f64).sqrt().max(1e-6);
        let most = CUBES_PER_CELL * cells.len() as i64 + 4_096;
        let dims = loop {
            let dims =
                [0, 1, 2].map(|k| (((hi[k] - lo[k]) / side).floor() as i64 + 1).clamp(1, 1 << 10));
            let count = dims[0] * dims[1] * dims[2];
            if count <= most {
                break dims;
            }
            side *= (count as f64 / most as f64).cbrt().max(1.01);
        };
        let count = (dims[0] * dims[1] * dims[2]) as usize;
        let mut starts = vec![0u32; count + 1];
        let cube = |p: &[f64; 3]| Self::cube_of(lo, side, dims, p);
        for c in cells {
            starts[cube(&c.2) + 1] += 1;
        }
        for k in 1..=count {
            starts[k] += starts[k - 1];
        }
        let mut fill = starts.clone();
        let mut sorted = vec![(0, 0, [0.0; 3]); cells.len()];
        for (i, c) in cells.iter().enumerate() {
            let k = cube(&c.2);
            sorted[fill[k] as usize] = (i as u32, c.1, c.2);
            fill[k] += 1;
        }
        Nearest {
            lo,
            side,
            dims,
            sorted,
            starts,
        }
    }

    fn index(lo: [f64; 3], side: f64, dims: [i64; 3], p: &[f64; 3]) -> [i64; 3] {
        // `as` rounds towards 0: the floor, for all that is not clamped to 0.
        [0, 1, 2].map(|k| (((p[k] - lo[k]) / side) as i64).clamp(0, dims[k] - 1))
    }

    fn cube_of(lo: [f64; 3], side: f64, dims: [i64; 3], p: &[f64; 3]) -> usize {
        let [x, y, z] = Self::index(lo, side, dims, p);
        ((z * dims[1] + y) * dims[0] + x) as usize
    }

    /// The type of the cell nearest `p`, the lowest-numbered of equally
    /// near ones (so the answer does not depend on the cubes): the cubes
    /// next to `p`'s first, then one shell of cubes further out at a time,
    /// until the nearest cell found is nearer than any cube not yet
    /// searched.
    fn kind_at(&self, p: &[f64; 3]) -> Option<u8> {
        self.kind_near(p).map(|n| n.kind)
    }

    /// [`Nearest::kind_at`], and how far from `p` the nearest cell stays
    /// of that type: half the difference between the nearest distance d₁
    /// and a bound d₂ below the distance of every cell of another type,
    /// since a point q with 2·|q − p| < d₂ − d₁ is nearer to this cell
    /// (d₁ + |q − p|) than to any of those (d₂ − |q − p|). Across a patch
    /// of one type that is far more than the distance the cell itself
    /// stays the nearest. 0 when cells of two types are equally near.
    fn kind_near(&self, p: &[f64; 3]) -> Option<Nearby> {
        let at = Self::index(self.lo, self.side, self.dims, p);
        let mut found = Found {
            best: (f64::INFINITY, u32::MAX, 0),
            other: f64::INFINITY,
        };
        let mut gap = f64::MAX;
        for reach in 1..=self.dims.iter().copied().max().unwrap_or(1) {
            let [x0, y0, z0] = [0, 1, 2].map(|k| (at[k] - reach).max(0));
            let [x1, y1, z1] = [0, 1, 2].map(|k| (at[k] + reach).min(self.dims[k] - 1));
            for z in z0..=z1 {
                for y in y0..=y1 {
                    if reach == 1 || (z - at[2]).abs() == reach || (y - at[1]).abs() == reach {
                        // The whole first box, or a face of a shell.
                        found.scan(self.run(x0, x1, y, z), p);
                    } else {
                        // Inside the shell's faces: its two ends, the cubes
                        // between them searched before.
                        if at[0] - reach >= 0 {
                            found.scan(self.run(x0, x0, y, z), p);
                        }
                        if at[0] + reach < self.dims[0] {
                            found.scan(self.run(x1, x1, y, z), p);
                        }
                    }
                }
            }
            // Every cell not yet seen lies in a cube beyond the box searched,
            // at least `gap` from p (less a margin for rounding): done when
            // the nearest found is nearer.
            gap = f64::MAX;
            for k in 0..3 {
                if at[k] - reach > 0 {
                    gap = gap.min(p[k] - (self.lo[k] + (at[k] - reach) as f64 * self.side));
                }
                if at[k] + reach + 1 < self.dims[k] {
                    gap = gap.min(self.lo[k] + (at[k] + reach + 1) as f64 * self.side - p[k]);
                }
            }
            if gap == f64::MAX {
                break; // every cube searched
            }
            gap = (gap - 1e-9 * self.side).max(0.0);
            if found.best.0 < gap * gap {
                break;
            }
        }
        let (d, i, kind) = found.best;
        (i != u32::MAX).then(|| {
            let others = found.other.sqrt().min(gap);
            Nearby {
                kind,
                stays: ((others - d.sqrt()) / 2.0 - 1e-9 * self.side).max(0.0),
                distance: d.sqrt(),
            }
        })
    }

    /// Which cells may be the nearest of the points in the box `lo`–`hi`
    /// (into `out`, by index), or the one type they all have. Every
    /// point q of the box is within r = d + h of the cell nearest its
    /// centre g (at d; h half the box's diagonal), so q's nearest cell is
    /// within r of the box: those cells, gathered from the cubes the box
    /// widened by r touches. A widened box of more than [`BOX_CUBES`]
    /// cubes is not searched.
    fn near_box(&self, lo: [f64; 3], hi: [f64; 3], out: &mut Vec<Cell>) -> Reach {
        out.clear();
        let g = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        let Some(near) = self.kind_near(&g) else {
            return Reach::One(None);
        };
        let half = dot(sub(hi, lo), sub(hi, lo)).sqrt() / 2.0;
        if near.stays > half * (1.0 + 1e-9) + self.margin() {
            return Reach::One(Some(near.kind)); // the whole box is within `stays`
        }
        let reach = (near.distance + half) * (1.0 + 1e-9) + self.margin();
        let [x0, y0, z0] = Self::index(
            self.lo,
            self.side,
            self.dims,
            &[0, 1, 2].map(|k| lo[k] - reach),
        );
        let [x1, y1, z1] = Self::index(
            self.lo,
            self.side,
            self.dims,
            &[0, 1, 2].map(|k| hi[k] + reach),
        );
        if (x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1) > BOX_CUBES {
            return Reach::Far;
        }
        for z in z0..=z1 {
            for y in y0..=y1 {
                out.extend(
                    self.run(x0, x1, y, z)
                        .iter()
                        .filter(|c| within(&c.2, lo, hi, reach)),
                );
            }
        }
        Reach::among(out)
    }

    /// [`Nearest::near_box`] for a box inside one whose cells `wider`
    /// may be the nearest of its points: those of them that may be the
    /// nearest of this box's points, the nearest of its centre found
    /// among them.
    fn narrow(&self, wider: &[Cell], lo: [f64; 3], hi: [f64; 3], out: &mut Vec<Cell>) -> Reach {
        out.clear();
        let g = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        let Some(d2) = nearest_among(wider, &g).map(|(d2, _)| d2) else {
            return Reach::One(None);
        };
        let half = dot(sub(hi, lo), sub(hi, lo)).sqrt() / 2.0;
        let reach = (d2.sqrt() + half) * (1.0 + 1e-9) + self.margin();
        out.extend(wider.iter().filter(|c| within(&c.2, lo, hi, reach)));
        Reach::among(out)
    }

    /// A margin for rounding in distances.
    fn margin(&self) -> f64 {
        1e-6 * self.side
    }

    /// The cells of cubes `x0..=x1` of row (y, z): one run of `sorted`.
    fn run(&self, x0: i64, x1: i64, y: i64, z: i64) -> &[(u32, u8, [f64; 3])] {
        let row = (z * self.dims[1] + y) * self.dims[0];
        let from = self.starts[(row + x0) as usize] as usize;
        &self.sorted[from..self.starts[(row + x1) as usize + 1] as usize]
    }
}

/// A cell of a day: its index in the day's list, type and point.
type Cell = (u32, u8, [f64; 3]);

/// What [`Nearest::near_box`] found for a box.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Reach {
    /// Every point of the box has this nearest type (`None`: there are no
    /// cells).
    One(Option<u8>),
    /// The nearest cell of every point is among those gathered.
    Among,
    /// Too many cubes to gather the cells from.
    Far,
}

impl Reach {
    /// `Among` the cells `near`, or the `One` type they all have.
    fn among(near: &[Cell]) -> Reach {
        match near.split_first() {
            Some((first, rest)) if rest.iter().any(|c| c.1 != first.1) => Reach::Among,
            Some((first, _)) => Reach::One(Some(first.1)),
            // Never (the centre's nearest is within reach); if rounding
            // ever left it out, a search per pixel.
            None => Reach::Far,
        }
    }
}

/// Whether `p` is within `reach` of the box `lo`–`hi`.
fn within(p: &[f64; 3], lo: [f64; 3], hi: [f64; 3], reach: f64) -> bool {
    let d = [0, 1, 2].map(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0));
    dot(d, d) <= reach * reach
}

/// The squared distance and type of the cell of `cells` nearest `p`, the
/// lowest-numbered of equally near ones.
/// Without branches on which is nearer: as for the plane's pictures, a
/// branch mispredicted for many cells cost more than the comparisons.
fn nearest_among(cells: &[Cell], p: &[f64; 3]) -> Option<(f64, u8)> {
    let d2 = |c: &[f64; 3]| (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2);
    let (&(mut at, mut kind, c), rest) = cells.split_first()?;
    let mut best = d2(&c);
    for &(i, k, c) in rest {
        let d = d2(&c);
        // All ones where this cell wins.
        let nearer = u32::from((d < best) | ((d == best) & (i < at))).wrapping_neg();
        at = (at & !nearer) | (i & nearer);
        kind = (kind & !nearer as u8) | (k & nearer as u8);
        best = best.min(d);
    }
    Some((best, kind))
}

/// [`Nearest::kind_at`] for points one after another, each near the one
/// before: while a point is within the distance the last search's type
/// stays the nearest's ([`Nearest::kind_near`]), that type, without a
/// search.
struct Along<'n> {
    near: &'n Nearest,
    /// The last point searched, its cell's type and that distance.
    known: Option<([f64; 3], u8, f64)>,
}

impl<'n> Along<'n> {
    fn new(near: &'n Nearest) -> Along<'n> {
        Along { near, known: None }
    }

    fn kind_at(&mut self, p: &[f64; 3]) -> Option<u8> {
        if let Some((q, kind, stays)) = self.known
            && dot(sub(*p, q), sub(*p, q)) < stays * stays
        {
            return Some(kind);
        }
        let found = self.near.kind_near(p)?;
        self.known = Some((*p, found.kind, found.stays));
        Some(found.kind)
    }
}

/// What [`Nearest::kind_near`] found for a point.
#[derive(Debug, Clone, Copy)]
struct Nearby {
    /// The nearest cell's type.
    kind: u8,
    /// How far from the point the nearest cell stays of that type.
    stays: f64,
    /// The nearest cell's distance.
    distance: f64,
}

/// What a search of [`Nearest::kind_near`] has found so far.
struct Found {
    /// (squared distance, index, type) of the nearest cell; no index: none.
    best: (f64, u32, u8),
    /// The squared distance of the nearest cell of another type than
    /// `best`'s.
    other: f64,
}

impl Found {
    /// Takes in the cells `run` (from `sorted`) for the point `p`.
    fn scan(&mut self, run: &[(u32, u8, [f64; 3])], p: &[f64; 3]) {
        for &(i, kind, c) in run {
            let d = (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2);
            if d < self.best.0 || (d == self.best.0 && i < self.best.1) {
                // The old nearest was nearer than every other cell seen.
                if kind != self.best.2 {
                    self.other = self.best.0;
                }
                self.best = (d, i, kind);
            } else if d < self.other && kind != self.best.2 {
                self.other = d;
            }
        }
    }
}

impl Shell {
    fn corners(&self, f: &[u32; 3]) -> [[f64; 3]; 3] {
        f.map(|i| self.vertices.get(i as usize).copied().unwrap_or([0.0; 3]))
    }

    /// The shade at each corner of each face: 0.35 + 0.65 |n · l| for the
    /// light l and the normal n there ([`normals::corner_normals`]), so a
    /// picture shaded between the corners is smooth where the surface is
    /// and keeps its edges.
    fn corner_shades(&self) -> Vec<[f64; 3]> {
        let light = unit(LIGHT);
        normals::corner_normals(&self.vertices, &self.faces)
            .into_iter()
            .map(|corners| corners.map(|n| 0.35 + 0.65 * dot(n, light).abs()))
            .collect()
    }

    /// The area of each type's cells' Voronoi regions on the mesh, by
    /// sampling every triangle at the same barycentric points.
    fn areas(&self, near: &Nearest, types: usize) -> Vec<u64> {
        let s = AREA_SAMPLES;
        let per_face: Vec<Vec<f64>> = self
            .faces
            .par_iter()
            .map(|f| {
                let [a, b, c] = self.corners(f);
                let area =
                    dot(cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(c, a))).sqrt() / 2.0;
                let mut share = vec![0.0; types.max(1)];
                let mut n = 0.0;
                let mut along = Along::new(near);
                for i in 0..s {
                    for j in 0..s - i {
                        let (u, v) = (
                            (i as f64 + 1.0 / 3.0) / s as f64,
                            (j as f64 + 1.0 / 3.0) / s as f64,
                        );
                        let p = [0, 1, 2].map(|k| a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]));
                        if let Some(kind) = along.kind_at(&p)
                            && let Some(x) = share.get_mut(usize::from(kind))
                        {
                            *x += 1.0;
                        }
                        n += 1.0;
                    }
                }
                share.iter().map(|x| x / n * area).collect()
            })
            .collect();
        (0..types)
            .map(|k| (per_face.iter().map(|s| s[k]).sum::<f64>() * 1e6).round() as u64)
            .collect()
    }

    /// The mesh split `levels` times (each triangle into four), each
    /// vertex coloured by its nearest cell.
    fn coloured(&self, near: &Nearest, colours: &[[u8; 3]], levels: u32) -> Result<Mesh> {
        let mut vertices = self.vertices.clone();
        let mut faces = self.faces.clone();
        for _ in 0..levels {
            let mut mid = std::collections::HashMap::new();
            let mut split = Vec::with_capacity(faces.len() * 4);
            for f in &faces {
                let mut m = [0u32; 3];
                for k in 0..3 {
                    let (a, b) = (f[k], f[(k + 1) % 3]);
                    m[k] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        let (p, q) = (vertices[a as usize], vertices[b as usize]);
                        vertices.push([0, 1, 2].map(|c| (p[c] + q[c]) / 2.0));
                        (vertices.len() - 1) as u32
                    });
                }
                split.extend([
                    [f[0], m[0], m[2]],
                    [m[0], f[1], m[1]],
                    [m[2], m[1], f[2]],
                    m,
                ]);
            }
            faces = split;
        }
        let colours: Vec<Rgb> = vertices
            .par_iter()
            .map(|p| {
                near.kind_at(p)
                    .and_then(|k| colours.get(usize::from(k)))
                    .copied()
                    .unwrap_or([128; 3])
            })
            .collect();
        let mut mesh = Mesh::from_triangles(vertices, &faces)?;
        mesh.set_colours(colours)?;
        Ok(mesh)
    }

    /// The bare mesh.
    fn bare(&self) -> Result<Mesh> {
        Ok(Mesh::from_triangles(self.vertices.clone(), &self.faces)?)
    }

    /// The object seen from `elevation` radians above its equator
    /// (orthographic, z up) at twice the picture's size: per pixel the
    /// depth of the nearest face and its shade there, found once for all
    /// the days (the mesh does not move).
    fn view(&self, elevation: f64) -> View {
        let (sin_e, cos_e) = elevation.sin_cos();
        let towards = [0.0, -cos_e, sin_e]; // towards the viewer
        let right = [1.0, 0.0, 0.0];
        let up = cross(towards, right);
        let screen: Vec<[f64; 3]> = self
            .vertices
            .iter()
            .map(|p| [dot(*p, right), dot(*p, up), dot(*p, towards)])
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
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area.abs() < 1e-12 {
                continue;
            }
            let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
            let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(w);
            let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
            let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(h);
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
        let mut view = View {
            w,
            h,
            scale,
            top: hi[1] + margin,
            axes: [right, up, towards],
            columns: (0..w)
                .map(|x| {
                    let across = (x as f64 + 0.5) / scale + lo[0] - margin;
                    right.map(|k| k * across)
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

/// A surface mosaic's object as [`Shell::view`] sees it.
struct View {
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
    fn canvas(&self) -> Result<Pixmap> {
        let (w, h) = (self.w, self.h);
        Pixmap::new(w as u32, h as u32)
            .ok_or_else(|| anyhow::anyhow!("a {w}×{h} picture is too large"))
    }

    /// The object shaded on `canvas` (from [`View::canvas`]), every point
    /// in its nearest cell's colour, a [`TILE`]-square of pixels at a time
    /// ([`View::colour_square`]): every pixel is painted, so one canvas
    /// serves every day.
    fn paint(&self, near: &Nearest, colours: &[[u8; 3]], canvas: &mut Pixmap) {
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

/// Writes (those of `kinds`) the outputs of a surface mosaic's run.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    params: &Params,
    names: &[&str],
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let colours: Vec<[u8; 3]> = params.types.iter().map(|t| t.colour).collect();
    let (shell, days) = read(records)?;
    let elevation = match params.surface.map(|s| s.control) {
        Some(ControlMap::Plane) => 1.0,
        _ => 0.35,
    };
    let view = kinds.has(Kind::Png).then(|| shell.view(elevation));
    // The view's canvas, and its picture at half the size as RGB: one of
    // each for every day (a day's canvas of a 1400² view is 7.8 MB).
    let mut pictures = match &view {
        Some(view) => {
            let canvas = view.canvas()?;
            let half = 3 * (canvas.width() / 2 * (canvas.height() / 2)) as usize;
            Some((view, canvas, vec![0; half]))
        }
        None => None,
    };
    let mut written = Vec::new();
    let mut counts = Vec::new();
    let mut areas = Vec::new();
    // The last day and its cells, for `surface.png` (a copy of its
    // picture) and `mosaic.obj`.
    let mut last = None;
    for d in &days {
        let mut by_type = vec![0usize; colours.len()];
        for c in &d.cells {
            if let Some(n) = by_type.get_mut(usize::from(c.1)) {
                *n += 1;
            }
        }
        counts.push((d.day, by_type));
        let near = Nearest::new(&d.cells, &shell);
        if kinds.has(Kind::Csv) {
            let path = dir.join(format!("cells_day{:02}.csv", d.day));
            write_csv(d.cells.iter().copied(), &path)?;
            written.push(path);
            areas.push(Some(shell.areas(&near, colours.len())));
        } else {
            areas.push(None);
        }
        if let Some((view, canvas, half)) = &mut pictures {
            let path = dir.join(format!("surface_day{:02}.png", d.day));
            view.paint(&near, &colours, canvas);
            picture::half_rgb_into(canvas, half)?;
            picture::save_rgb(canvas.width() / 2, canvas.height() / 2, half, &path)?;
            written.push(path);
        }
        last = Some((d.day, near));
    }
    if kinds.has(Kind::Csv) {
        let path = dir.join("types.csv");
        write_shares(names, &counts, &areas, &path)?;
        written.push(path);
    }
    if kinds.has(Kind::Obj) {
        let path = dir.join("surface.obj");
        written.extend(write_obj(&path, &shell.bare()?, ObjStyle::PLAIN)?);
    }
    if let Some((day, near)) = last {
        if pictures.is_some() {
            let path = dir.join("surface.png");
            atomic::copy(&dir.join(format!("surface_day{day:02}.png")), &path)?;
            written.push(path);
        }
        if kinds.has(Kind::Obj) {
            let path = dir.join("mosaic.obj");
            let style = ObjStyle {
                vertex_colours: true,
                ..ObjStyle::PLAIN
            };
            written.extend(write_obj(
                &path,
                &shell.coloured(&near, &colours, 2)?,
                style,
            )?);
        }
    }
    written.extend(write_counts_and_mask(params, names, &counts, dir, kinds)?);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` cells on a sphere of `radius` (a Fibonacci lattice), cell i of
    /// type `kind(i, point)`.
    fn sphere(n: u32, radius: f64, kind: impl Fn(u32, [f64; 3]) -> u8) -> Vec<Cell> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / f64::from(n);
                let r = (1.0 - z * z).sqrt();
                let a = f64::from(i) * 2.399_963;
                let p = [r * a.cos(), r * a.sin(), z].map(|x| radius * x);
                (i, kind(i, p), p)
            })
            .collect()
    }

    /// The `t`-th of a set of points spread through the box of ±`radius`
    /// in x and y and ±`height` in z around the origin.
    fn probe(t: f64, radius: f64, height: f64) -> [f64; 3] {
        [
            radius * (t * 0.731).sin(),
            radius * (t * 1.113).cos(),
            height * (t * 0.377).sin(),
        ]
    }

    /// Three patches of one type each, by longitude.
    fn patch(p: [f64; 3]) -> u8 {
        ((p[1].atan2(p[0]) + 3.2) / 2.2) as u8
    }

    /// The nearest cell by looking at every one, the lowest-numbered of
    /// equally near ones.
    fn nearest_of_all(cells: &[(u32, u8, [f64; 3])], p: &[f64; 3]) -> Option<u8> {
        let d = |c: &[f64; 3]| (0..3).map(|k| (c[k] - p[k]).powi(2)).sum::<f64>();
        let mut best: Option<(f64, usize)> = None;
        for (i, c) in cells.iter().enumerate() {
            if best.is_none_or(|(b, _)| d(&c.2) < b) {
                best = Some((d(&c.2), i));
            }
        }
        best.map(|(_, i)| cells[i].1)
    }

    #[test]
    fn the_grid_finds_the_nearest_cell_of_every_point() {
        // Cells on a sphere of radius 10 (a Fibonacci lattice), each type
        // its index mod 7, and pairs of cells at one place (ties); points
        // on, inside and far outside it.
        let n = 600;
        let mut cells = sphere(n, 10.0, |i, _| (i % 7) as u8);
        for i in 0..50 {
            let twin = cells[i * 11].2;
            cells.push((n + i as u32, 6 - (i % 7) as u8, twin));
        }
        let shell = Shell::default();
        let near = Nearest::new(&cells, &shell);
        for i in 0..4_000u32 {
            let t = f64::from(i);
            let scale = [1.0, 0.3, 1.7, 6.0][i as usize % 4];
            let p = probe(t, 10.0 * scale, 10.0 * scale);
            assert_eq!(near.kind_at(&p), nearest_of_all(&cells, &p), "at {p:?}");
        }
        // Within the distance it reports, the nearest cell's type stays
        // the same (points at 0.999 of it, in 8 directions, checked cell
        // by cell).
        let mut stayed = 0;
        for i in 0..2_000u32 {
            let t = f64::from(i);
            let p = probe(t, 10.0, 9.0);
            let Nearby { kind, stays, .. } = near.kind_near(&p).expect("cells");
            for step in [
                [1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.6, 0.8, 0.0],
            ] {
                for sign in [-1.0, 1.0] {
                    let q = [0, 1, 2].map(|k| p[k] + sign * 0.999 * stays * step[k]);
                    assert_eq!(nearest_of_all(&cells, &q), Some(kind), "{q:?} near {p:?}");
                }
            }
            stayed += usize::from(stays > 0.0);
        }
        // All but those nearest to a twin (equally near to both: 0).
        assert!(stayed > 1_700, "{stayed}");
        // Along a path of small steps the answers are the searches'.
        let mut along = Along::new(&near);
        for i in 0..20_000u32 {
            let t = f64::from(i) * 0.0005;
            let p = [
                10.5 * (t * 3.1).sin(),
                10.5 * (t * 2.3).cos(),
                10.0 * (t * 0.7).sin(),
            ];
            assert_eq!(along.kind_at(&p), nearest_of_all(&cells, &p), "at {p:?}");
        }
        // Exactly on the twins: the lower-numbered one.
        for i in 0..50 {
            let at = cells[i * 11];
            assert_eq!(near.kind_at(&at.2), Some(at.1));
        }
        assert_eq!(Nearest::new(&[], &shell).kind_at(&[0.0; 3]), None);
    }

    #[test]
    fn across_a_patch_of_one_type_the_type_stays_further_than_the_cell() {
        // 2,000 cells on a sphere in three patches of one type each (by
        // longitude), with cells of a fourth type sprinkled in.
        let n = 2_000;
        let cells = sphere(n, 5.0, |i, p| if i % 37 == 0 { 3 } else { patch(p) });
        let near = Nearest::new(&cells, &Shell::default());
        let (mut beyond, mut searched) = (0, 0);
        for i in 0..1_500u32 {
            let t = f64::from(i);
            let p = probe(t, 5.0, 4.5);
            let Nearby { kind, stays, .. } = near.kind_near(&p).expect("cells");
            assert_eq!(Some(kind), nearest_of_all(&cells, &p), "at {p:?}");
            // The gap between the nearest cell and the next of any type.
            let mut d: Vec<f64> = cells
                .iter()
                .map(|c| (0..3).map(|k| (c.2[k] - p[k]).powi(2)).sum::<f64>().sqrt())
                .collect();
            d.sort_by(f64::total_cmp);
            searched += 1;
            beyond += usize::from(stays > (d[1] - d[0]) / 2.0 + 1e-6);
            for j in 0..16 {
                let a = f64::from(j) * std::f64::consts::FRAC_PI_8;
                let step = [a.cos(), a.sin() * 0.6, a.sin() * 0.8];
                let q = [0, 1, 2].map(|k| p[k] + 0.999 * stays * step[k]);
                assert_eq!(nearest_of_all(&cells, &q), Some(kind), "{q:?} near {p:?}");
            }
        }
        // Inside the patches, most points' type stays further than the
        // point's nearest cell does.
        assert!(beyond * 2 > searched, "{beyond} of {searched}");
    }

    #[test]
    fn the_cells_gathered_for_a_box_hold_the_nearest_of_its_every_point() {
        // Three patches on a sphere as above; boxes of three sizes around
        // points near it, some flat, and each box's quarters.
        let n = 3_000;
        let cells = sphere(n, 5.0, |_, p| patch(p));
        let near = Nearest::new(&cells, &Shell::default());
        // Every point of a grid in the box, corners included.
        let grid = |lo: [f64; 3], hi: [f64; 3]| {
            (0..7 * 7 * 7).map(move |i| {
                let f = [i % 7, i / 7 % 7, i / 49].map(|x| f64::from(x) / 6.0);
                [0, 1, 2].map(|k| lo[k] + f[k] * (hi[k] - lo[k]))
            })
        };
        let check = |reach: Reach, among: &[Cell], lo, hi| {
            for q in grid(lo, hi) {
                let kind = match reach {
                    Reach::One(kind) => kind,
                    Reach::Among => nearest_among(among, &q).map(|(_, k)| k),
                    Reach::Far => return,
                };
                assert_eq!(nearest_of_all(&cells, &q), kind, "{q:?} in {lo:?}-{hi:?}");
            }
        };
        let (mut one, mut among, mut narrowed) = (0, 0, 0);
        let (mut gathered, mut quarter) = (Vec::new(), Vec::new());
        for i in 0..600u32 {
            let t = f64::from(i);
            let size = [0.05, 0.2, 0.6][i as usize % 3];
            let g = probe(t, 5.0, 4.5);
            let half = [size, size * 0.7, if i % 2 == 0 { 0.0 } else { size * 0.4 }];
            let lo = [0, 1, 2].map(|k| g[k] - half[k]);
            let hi = [0, 1, 2].map(|k| g[k] + half[k]);
            let reach = near.near_box(lo, hi, &mut gathered);
            check(reach, &gathered, lo, hi);
            match reach {
                Reach::One(_) => one += 1,
                Reach::Among => among += 1,
                Reach::Far => {}
            }
            if reach != Reach::Among {
                continue;
            }
            // A quarter of the box (its lower x and y half).
            let qhi = [g[0], g[1], hi[2]];
            let narrow = near.narrow(&gathered, lo, qhi, &mut quarter);
            check(narrow, &quarter, lo, qhi);
            narrowed += usize::from(narrow == Reach::Among && quarter.len() < gathered.len());
        }
        // Most boxes lie inside a patch; the others' quarters need fewer
        // cells.
        assert!(one > 300, "{one} of 600");
        assert!(among > 50 && narrowed * 2 > among, "{among}, {narrowed}");
    }

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

    #[test]
    fn the_cubes_are_bounded_by_the_cells() {
        // 200,000 cells on a sphere: cubes of the cells' spacing would be
        // 259³, 87 a cell.
        let n = 200_000;
        let cells = sphere(n, 1.0, |_, _| 0);
        let near = Nearest::new(&cells, &Shell::default());
        let cubes = near.starts.len() - 1;
        assert!(
            cubes as i64 <= CUBES_PER_CELL * i64::from(n) + 4_096,
            "{cubes}"
        );
        assert_eq!(near.kind_at(&[0.0, 0.0, 1.5]), Some(0));
    }
}
