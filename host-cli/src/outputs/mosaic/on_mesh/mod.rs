//! Mosaics grown on a mesh (MClone thesis Secs. 3.2, 4.1; the core's
//! `SurfaceMosaic`): per streamed day `cells_dayNN.csv` (`id,type,x,y,z`)
//! and a shaded picture of the object with every point coloured by its
//! nearest cell (`surface_dayNN.png`; `surface.png` the last day);
//! `surface.obj` the mesh the cells live on, `mosaic.obj` the last day
//! coloured on it (a colour per vertex, on the mesh split twice);
//! `types.csv` each type's share of the cells and of the area (the area
//! by sampling every triangle); the cell counts chart and the mask as for
//! the plane; `plot.svg` the last day's type borders and the object's
//! outline in the pictures' view (`edges`).

mod control;
mod edges;
mod nearest;
mod view;

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context, Result, anyhow};
use morphogen::fx::Real as _;
use morphogen::mosaic::ControlMap;
use morphogen::mosaic::Params;
use morphogen::stream::Record;
use nalgebra::Vector3;
use rayon::prelude::*;

use super::{Measured, by_type, write_counts_and_mask, write_csv, write_mosaic_obj, write_tables};
use crate::outputs::driver::{self, Closing, Products, Still};
use crate::outputs::kinds::{Kinds, Pixels, Product};
use crate::outputs::mesh::{Mesh, ObjStyle, Rgb};
use crate::outputs::numbered::{FileSeries, Numbering};
use crate::outputs::plot::Drawing;
use crate::records::{Place, Records};
use control::Unrolled;
use nearest::{Along, Nearest};
use view::View;

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
    let units = |p: &[morphogen::fx::Fx; 3]| p.map(f64::from_fx);
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

impl Shell {
    /// The lowest and highest coordinates of its vertices.
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.vertices
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
                (
                    [0, 1, 2].map(|c| lo[c].min(p[c])),
                    [0, 1, 2].map(|c| hi[c].max(p[c])),
                )
            })
    }

    fn corners(&self, f: &[u32; 3]) -> [[f64; 3]; 3] {
        f.map(|i| self.vertices.get(i as usize).copied().unwrap_or([0.0; 3]))
    }

    /// The area of each type's cells' Voronoi regions on the mesh, by
    /// sampling every triangle at the same barycentric points.
    fn areas(&self, near: &Nearest, types: usize) -> Vec<u64> {
        let s = AREA_SAMPLES;
        let per_face: Vec<Vec<f64>> = self
            .faces
            .par_iter()
            .map(|f| {
                let [a, b, c] = self.corners(f).map(Vector3::from);
                let area = (b - a).cross(&(c - a)).norm() / 2.0;
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
}

/// Groups a surface mosaic's records into days, gathering the mesh the
/// cells live on as it goes by.
#[derive(Debug, Default)]
pub(super) struct ShellFramer {
    shell: Shell,
    current: Option<Day>,
}

impl ShellFramer {
    /// Takes the next record; returns the day it ends, if any.
    fn push(&mut self, r: &Record) -> Option<Day> {
        let units = |p: &[morphogen::fx::Fx; 3]| p.map(f64::from_fx);
        match r {
            Record::FrameStart { time, .. } => {
                return self.current.replace(Day {
                    day: time.floor_int(),
                    cells: Vec::new(),
                });
            }
            Record::MeshVertex { p, .. } => self.shell.vertices.push(units(p)),
            Record::Triangle { v } => self.shell.faces.push(*v),
            Record::SurfaceCell { id, kind, p } => {
                if let Some(d) = self.current.as_mut() {
                    d.cells.push((*id, *kind, units(p)));
                }
            }
            Record::FrameEnd { .. } => return self.current.take(),
            _ => {}
        }
        None
    }
}

/// A day's picture: the object painted by the day's cells, and the cells'
/// regions it was painted with.
pub(super) struct Painted {
    picture: driver::Rgb,
    near: Nearest,
}

impl Still for Painted {
    fn pixels(&self) -> Pixels<'_> {
        self.picture.pixels()
    }
}

/// A surface mosaic run's products ([`driver::write`], the module's
/// files); no animation.
struct Surface<'a> {
    dir: &'a Path,
    params: &'a Params<'a>,
    names: &'a [&'a str],
    kinds: Kinds,
    colours: Vec<[u8; 3]>,
    /// The mesh, and the view of it the pictures show (with `png`), once
    /// surveyed.
    shell: Shell,
    view: Option<View>,
    /// Per day: its number and the cells of each type.
    counts: Vec<(i32, Vec<usize>)>,
    /// The latest day whose regions were found (by position), kept for
    /// `mosaic.obj`, which shows the last day; and the last day.
    latest: Mutex<Option<(usize, Nearest)>>,
    last: Option<Day>,
}

impl Surface<'_> {
    /// The object painted by the cells whose regions are `near`.
    fn paint(&self, near: &Nearest) -> Result<driver::Rgb> {
        let view = self.view.as_ref().context("the surface has no view")?;
        let mut canvas = view.canvas()?;
        view.paint(near, &self.colours, &mut canvas);
        driver::Rgb::halved(&canvas)
    }

    /// The elevation the object is seen from, radians: a plane's control
    /// map from higher up.
    fn elevation(&self) -> f64 {
        match self.params.surface.map(|s| s.control) {
            Some(ControlMap::Plane) => 1.0,
            _ => 0.35,
        }
    }
}

impl Products for Surface<'_> {
    type Frame = Day;
    type Framer = ShellFramer;
    type Picture = Painted;
    type Measure = Measured;

    fn push(framer: &mut ShellFramer, record: &Record) -> Result<Option<Day>> {
        Ok(framer.push(record))
    }

    fn survey(&mut self, day: Day) -> Result<()> {
        let counted = day
            .cells
            .iter()
            .map(|c| c.1)
            .filter(|&k| usize::from(k) < self.colours.len());
        self.counts
            .push((day.day, by_type(counted, self.colours.len())));
        self.last = Some(day);
        Ok(())
    }

    fn surveyed(&mut self, framer: ShellFramer) {
        self.shell = framer.shell;
        self.view = self
            .kinds
            .wants(Product::FramePicture)
            .then(|| self.shell.view(self.elevation()));
    }

    fn index(day: &Day) -> i64 {
        i64::from(day.day)
    }

    fn numbering(&self, _count: usize) -> Numbering {
        Numbering::days(self.params.days)
    }

    fn stills(&self) -> Option<FileSeries> {
        Some(FileSeries::SURFACES)
    }

    fn picture(&self, day: &Day) -> Result<Painted> {
        let near = Nearest::new(&day.cells, &self.shell);
        Ok(Painted {
            picture: self.paint(&near)?,
            near,
        })
    }

    fn label(&self, day: &Day) -> String {
        format!("day {}", day.day)
    }

    fn frame_work(&self) -> (bool, bool) {
        (
            self.kinds.wants(Product::Table) || self.kinds.wants(Product::Mesh),
            false,
        )
    }

    fn frame_files(
        &self,
        d: &Day,
        position: usize,
        picture: Option<Painted>,
        numbering: Numbering,
    ) -> Result<(Vec<PathBuf>, Option<Measured>)> {
        let near = match picture {
            Some(p) => p.near,
            None => Nearest::new(&d.cells, &self.shell),
        };
        let stem = numbering.stem(FileSeries::CELLS, d.day);
        let cells = |path: &Path| write_csv(d.cells.iter().copied(), path);
        let paths = self.kinds.table(self.dir, &stem, cells)?;
        let mut measured = None;
        if self.kinds.wants(Product::Table) {
            let types = self.colours.len();
            let unrolled = Unrolled::new(&self.shell, &near, self.params, types);
            let figures = (0..types)
                .map(|k| unrolled.raster().figures(k as u8 + 2))
                .collect();
            measured = Some((self.shell.areas(&near, types), figures));
        }
        let mut latest = self
            .latest
            .lock()
            .map_err(|_| anyhow!("a mosaic writer stopped"))?;
        if latest.as_ref().is_none_or(|(at, _)| *at < position) {
            *latest = Some((position, near));
        }
        Ok((paths, measured))
    }

    fn plot(&self) -> Result<Option<Drawing>> {
        let Some(last) = &self.last else {
            return Ok(None);
        };
        let near = Nearest::new(&last.cells, &self.shell);
        let axes = view::axes(self.elevation());
        Ok(Some(edges::drawing(
            &self.shell,
            &near,
            last.cells.len(),
            axes,
        )))
    }

    fn close(mut self, dir: &Path, kinds: Kinds, run: Closing<Measured>) -> Result<Vec<PathBuf>> {
        let mut written = write_tables(self.names, &self.counts, run.measures, dir, kinds)?;
        let meshes = kinds.wants(Product::Mesh);
        if meshes {
            let bare = self.shell.bare()?;
            written.extend(kinds.mesh(&bare, dir, "surface", ObjStyle::PLAIN)?);
        }
        let pictured = self.view.is_some() && kinds.wants(Product::Picture);
        if let Some(last) = self.last.as_ref().filter(|_| pictured || meshes) {
            let latest = self
                .latest
                .get_mut()
                .map_err(|_| anyhow!("a mosaic writer stopped"))?
                .take();
            let near = match latest {
                Some((at, near)) if at + 1 == self.counts.len() => near,
                _ => Nearest::new(&last.cells, &self.shell),
            };
            if pictured {
                // The last day's picture again.
                let drawn = self.paint(&near)?;
                written.extend(kinds.picture(Product::Picture, &drawn.pixels(), dir, "surface")?);
            }
            if meshes {
                let coloured = self.shell.coloured(&near, &self.colours, 2)?;
                written.extend(write_mosaic_obj(dir, &coloured, kinds)?);
            }
        }
        written.extend(write_counts_and_mask(
            self.params,
            self.names,
            &self.counts,
            dir,
            kinds,
        )?);
        Ok(written)
    }
}

/// Writes (those of `kinds`) the files of `params`' run on a mesh
/// (`Surface`), the types named `names` where given.
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
    let surface = Surface {
        dir,
        params,
        names,
        kinds,
        colours: params.types.iter().map(|t| t.colour).collect(),
        shell: Shell::default(),
        view: None,
        counts: Vec::new(),
        latest: Mutex::new(None),
        last: None,
    };
    driver::write(surface, records, dir, kinds)
}
