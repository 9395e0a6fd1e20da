//! Mosaics grown on a mesh (MClone thesis Secs. 3.2, 4.1; the core's
//! `mosaic::surface`): per streamed day `cells_dayNN.csv` (`id,type,x,y,z`)
//! and a shaded picture of the object with every point coloured by its
//! nearest cell (`surface_dayNN.png`; `surface.png` the last day);
//! `surface.obj` the mesh the cells live on, `mosaic.obj` the last day
//! coloured on it (a colour per vertex, on the mesh split twice);
//! `types.csv` each type's share of the cells and of the area (the area
//! by sampling every triangle); the cell counts chart and the mask as for
//! the plane.

mod control;
mod nearest;
mod view;

use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::fx::Real as _;
use morphogen::mosaic::ControlMap;
use morphogen::mosaic::Params;
use morphogen::stream::Record;
use nalgebra::Vector3;
use rayon::prelude::*;

use super::kinds::{Kind, Kinds};
use super::mesh::{Mesh, ObjStyle, Rgb, write_obj};
use super::mosaic::{
    write_counts_and_mask, write_csv, write_mosaic_obj, write_pattern, write_shares,
};
use super::numbered::{FileSeries, Numbering};
use super::picture;
use crate::atomic;
use crate::records::{Place, Records};
use control::Unrolled;
use nearest::{Along, Nearest};

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
    let numbering = Numbering::days(params.days);
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
    let mut figures = Vec::new();
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
            let path = dir.join(numbering.name(FileSeries::CELLS, d.day));
            write_csv(d.cells.iter().copied(), &path)?;
            written.push(path);
            areas.push(Some(shell.areas(&near, colours.len())));
            let unrolled = Unrolled::new(&shell, &near, params, colours.len());
            figures.push(Some(
                (0..colours.len())
                    .map(|k| unrolled.raster().figures(k as u8 + 2))
                    .collect(),
            ));
        } else {
            areas.push(None);
            figures.push(None);
        }
        if let Some((view, canvas, half)) = &mut pictures {
            let path = dir.join(numbering.name(FileSeries::SURFACES, d.day));
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
        let path = dir.join("pattern.csv");
        write_pattern(names, &counts, &figures, &path)?;
        written.push(path);
    }
    if kinds.has(Kind::Obj) {
        let path = dir.join("surface.obj");
        written.extend(write_obj(&path, &shell.bare()?, ObjStyle::PLAIN)?);
    }
    if let Some((day, near)) = last {
        if pictures.is_some() {
            let path = dir.join("surface.png");
            atomic::copy(&dir.join(numbering.name(FileSeries::SURFACES, day)), &path)?;
            written.push(path);
        }
        if kinds.has(Kind::Obj) {
            written.extend(write_mosaic_obj(dir, &shell.coloured(&near, &colours, 2)?)?);
        }
    }
    written.extend(write_counts_and_mask(params, names, &counts, dir, kinds)?);
    Ok(written)
}
