//! Mosaic presets (MClone): per streamed day a CSV of the cells
//! (`cells_dayNN.csv`: `id,type,x,y,z`, their points on the
//! [`Surface`]) and a Voronoi picture (`day_NN.png`: every pixel takes the
//! colour of the type of its nearest cell, distances periodic where the
//! domain wraps, the cylinder unrolled with u to the right and v down);
//! on a cylinder also the shaded object (`surface_dayNN.png`);
//! `mosaic.png` (and `surface.png`) is the last day; `surface.obj` the
//! bare surface and `mosaic.obj` the last day coloured on it;
//! `animation.png` the days in order (every day, or 60 spread evenly);
//! `cells.png`/`cells.svg` the number of cells of each type per day, in
//! the types' colours; the control mask, if any, as `mask.pbm`. Days are
//! written in parallel.

mod pattern;
mod voronoi;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Result, anyhow};
use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::mosaic::Params;
use morphogen::stream::Record;

use super::chart::{Axis, Chart, Series, write_chart};
use super::kinds::{Kind, Kinds};
use super::mesh::{Mesh, ObjStyle, write_obj};
use super::numbered::{FileSeries, Numbering};
use super::picture;
use super::pipeline::pipeline;
use super::slots::{OrderedAnimation, animation_frames};
use super::surface::Surface;
use super::text;
use crate::atomic::{self, OutputFile, write_atomic};
use crate::records::{Place, Records};

pub use pattern::{Figures, Raster};
pub use voronoi::{Indexed, voronoi};
use voronoi::{palette, picture_size};

/// One streamed day.
#[derive(Debug, Default)]
pub struct Day {
    /// The day number.
    pub day: i32,
    /// `(id, type, u, v)` of each cell.
    pub cells: Vec<(u32, u8, Fx, Fx)>,
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
                    d.cells.push((*id, *kind, p[0], p[1]));
                }
            }
            _ => {}
        }
    }
    out
}

/// The chart of the number of cells of each type per day.
fn cells_chart(colours: &[[u8; 3]], names: &[&str], counts: &[(i32, Vec<usize>)]) -> Chart {
    let mut chart = Chart::new(
        "Cells per type",
        Axis::new("time", "days"),
        Axis::new("cells", "count"),
    );
    let types = counts.iter().map(|(_, c)| c.len()).max().unwrap_or(0);
    for k in 0..types {
        let points = counts
            .iter()
            .map(|(day, c)| (f64::from(*day), c.get(k).copied().unwrap_or(0) as f64))
            .collect();
        let label = match names.get(k).filter(|n| !n.is_empty()) {
            Some(name) => format!("{name} (type {k})"),
            None => format!("type {k}"),
        };
        let mut series = Series::line(label, points);
        if let Some(&rgb) = colours.get(k) {
            series = series.with_colour(rgb);
        }
        chart = chart.with_series(series);
    }
    chart
}

/// Writes `types.csv`: per streamed day and type, its cells and their
/// share of all cells, and its share of the area (the Voronoi regions of
/// its cells, counted in the day's picture): where the two differ, the
/// type's cells are packed denser or looser than the rest.
pub(super) fn write_shares(
    names: &[&str],
    counts: &[(i32, Vec<usize>)],
    areas: &[Option<Vec<u64>>],
    path: &Path,
) -> Result<()> {
    OutputFile::write_with(path, |file| {
        file.write_all(b"day,type,name,cells,cell_share,area_share\n")?;
        for ((day, cells), area) in counts.iter().zip(areas) {
            let all_cells = cells.iter().sum::<usize>().max(1) as f64;
            let all_area = area.as_ref().map_or(0, |a| a.iter().sum::<u64>()).max(1) as f64;
            for (k, &n) in cells.iter().enumerate() {
                let name = names.get(k).copied().unwrap_or("");
                let share = n as f64 / all_cells;
                let area = area
                    .as_ref()
                    .and_then(|a| a.get(k))
                    .map_or(0.0, |&a| a as f64 / all_area);
                writeln!(file, "{day},{k},{name},{n},{share:.4},{area:.4}")?;
            }
        }
        Ok(())
    })
}

/// Writes `pattern.csv`: per streamed day and type, the figures of its
/// pattern in the day's Voronoi picture ([`Figures`]), on the plane or
/// unrolled from a mesh alike.
pub(super) fn write_pattern(
    names: &[&str],
    counts: &[(i32, Vec<usize>)],
    figures: &[Option<Vec<Figures>>],
    path: &Path,
) -> Result<()> {
    OutputFile::write_with(path, |file| {
        file.write_all(b"day,type,name,patches,runs_per_row,width,correlation_u,correlation_v\n")?;
        for ((day, _), figures) in counts.iter().zip(figures) {
            for (k, f) in figures.iter().flatten().enumerate() {
                let name = names.get(k).copied().unwrap_or("");
                let [cu, cv] = f.correlation;
                writeln!(
                    file,
                    "{day},{k},{name},{},{:.2},{:.3},{cu:.3},{cv:.3}",
                    f.patches, f.runs_per_row, f.width
                )?;
            }
        }
        Ok(())
    })
}

/// Writes (those of `kinds`) the CSVs, the Voronoi PNGs, the animation,
/// the cell counts chart (its legend by the types' `names`, where given)
/// and the mask of `params`' run, a day at a time as the days are read.
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
    let domain = &params.domain;
    let surface = Surface::of(domain);
    let (w, h) = picture_size(domain);
    // The object the surface pictures show, found once.
    let view = if kinds.has(Kind::Png) {
        surface.view([w, h])?
    } else {
        None
    };
    let picked = if kinds.has(Kind::Anim) {
        animation_frames(records.frame_starts()?)
    } else {
        Vec::new()
    };
    let anim_path = dir.join("animation.png");
    // Indexed frames (a third of the bytes, no RGB copy) when the labels'
    // colours fit the palette beside the types'; RGB otherwise.
    let apng = if picked.len() > 1 {
        let size = (u32::try_from(w)?, u32::try_from(h)?);
        match OrderedAnimation::indexed(&anim_path, size, &palette(&colours), picked.len())? {
            Some(apng) => Some((apng, true)),
            None => Some((
                OrderedAnimation::new(&anim_path, size.0, size.1, picked.len())?,
                false,
            )),
        }
    } else {
        None
    };
    let mut last: Option<Arc<Day>> = None;
    // The picture of the latest day drawn so far (by position), kept for
    // mosaic.obj, which shows the last day.
    let latest: Mutex<Option<(usize, Indexed)>> = Mutex::new(None);
    // Per day: its number and the cells of each type.
    let mut counts: Vec<(i32, Vec<usize>)> = Vec::new();
    type Measured = (Vec<PathBuf>, Option<(Vec<u64>, Vec<Figures>)>);
    let per_day: Vec<Measured> = pipeline(
        |send| {
            let mut current: Option<Day> = None;
            let mut hand_over = |day: Day| {
                let mut by_type = vec![0usize; colours.len()];
                for &(_, kind, _, _) in &day.cells {
                    let k = usize::from(kind);
                    if by_type.len() <= k {
                        by_type.resize(k + 1, 0);
                    }
                    by_type[k] += 1;
                }
                let position = counts.len();
                let slot = picked.binary_search(&position).ok();
                counts.push((day.day, by_type));
                let day = Arc::new(day);
                last = Some(Arc::clone(&day));
                send((day, position, slot))
            };
            records.visit(Place::START, |_, r| {
                match r {
                    Record::FrameStart { time, .. } => {
                        let next = Day {
                            day: time.floor_int(),
                            cells: Vec::new(),
                        };
                        if let Some(done) = current.replace(next) {
                            hand_over(done)?;
                        }
                    }
                    Record::Cell { id, kind, p } => {
                        if let Some(d) = current.as_mut() {
                            d.cells.push((*id, *kind, p[0], p[1]));
                        }
                    }
                    _ => {}
                }
                Ok(())
            })?;
            current.map_or(Ok(()), hand_over)
        },
        |(d, position, slot): (Arc<Day>, usize, Option<usize>)| {
            let mut paths = Vec::with_capacity(2);
            if kinds.has(Kind::Csv) {
                let csv = dir.join(numbering.name(FileSeries::CELLS, d.day));
                let unit = |v: Fx| f64::from_fx(v);
                let points = d
                    .cells
                    .iter()
                    .map(|&(id, kind, u, v)| (id, kind, surface.point(unit(u), unit(v))));
                write_csv(points, &csv)?;
                paths.push(csv);
            }
            let animated = apng.as_ref().zip(slot);
            let mut areas = None;
            if kinds.has(Kind::Png) || kinds.has(Kind::Csv) || animated.is_some() {
                let picture = voronoi(domain, &colours, &d.cells);
                areas = kinds.has(Kind::Csv).then(|| {
                    let figures = (0..colours.len())
                        .map(|k| picture.raster(domain).figures(k as u8 + 2))
                        .collect();
                    (picture.areas(colours.len()), figures)
                });
                if kinds.has(Kind::Png) {
                    let png = dir.join(numbering.name(FileSeries::DAYS, d.day));
                    picture.save(&png)?;
                    paths.push(png);
                    if let Some(view) = &view {
                        let png = dir.join(numbering.name(FileSeries::SURFACES, d.day));
                        let drawn = view.paint(picture.palette(), &|i| picture.index(i))?;
                        picture::save(&drawn, &png)?;
                        paths.push(png);
                    }
                }
                if let Some(((apng, indexed), slot)) = animated {
                    let frame = if *indexed {
                        picture.indices().to_vec()
                    } else {
                        picture.rgb()
                    };
                    apng.frame(slot, frame, format!("day {}", d.day))?;
                }
                let mut latest = latest
                    .lock()
                    .map_err(|_| anyhow!("a mosaic picture writer stopped"))?;
                if latest.as_ref().is_none_or(|(at, ..)| *at < position) {
                    *latest = Some((position, picture));
                }
            }
            Ok((paths, areas))
        },
    )?;
    let (paths, measured): (Vec<_>, Vec<_>) = per_day.into_iter().unzip();
    let mut written: Vec<PathBuf> = paths.into_iter().flatten().collect();
    if kinds.has(Kind::Csv) {
        let (areas, figures): (Vec<_>, Vec<_>) = measured
            .into_iter()
            .map(|m| m.map_or((None, None), |(a, f)| (Some(a), Some(f))))
            .unzip();
        let path = dir.join("types.csv");
        write_shares(names, &counts, &areas, &path)?;
        written.push(path);
        let path = dir.join("pattern.csv");
        write_pattern(names, &counts, &figures, &path)?;
        written.push(path);
    }
    if let Some((apng, _)) = apng {
        apng.finish()?;
        written.push(anim_path);
    }
    if kinds.has(Kind::Obj) {
        let path = dir.join("surface.obj");
        written.extend(write_obj(&path, &surface.mesh(None)?, ObjStyle::PLAIN)?);
    }
    if let Some(last) = last.filter(|_| kinds.has(Kind::Png) || kinds.has(Kind::Obj)) {
        let drawn = latest
            .into_inner()
            .map_err(|_| anyhow!("a mosaic picture writer stopped"))?;
        let picture = match drawn {
            Some((at, picture)) if at + 1 == counts.len() => picture,
            _ => voronoi(domain, &colours, &last.cells),
        };
        if kinds.has(Kind::Png) {
            // Every day's pictures were written: the last day's again.
            let path = dir.join("mosaic.png");
            atomic::copy(&dir.join(numbering.name(FileSeries::DAYS, last.day)), &path)?;
            written.push(path);
            if view.is_some() {
                let path = dir.join("surface.png");
                atomic::copy(
                    &dir.join(numbering.name(FileSeries::SURFACES, last.day)),
                    &path,
                )?;
                written.push(path);
            }
        }
        if kinds.has(Kind::Obj) {
            let coloured = surface.mesh(Some(&|u, v| picture.at(u, v)))?;
            written.extend(write_mosaic_obj(dir, &coloured)?);
        }
    }
    written.extend(write_counts_and_mask(params, names, &counts, dir, kinds)?);
    Ok(written)
}

/// Writes `mosaic.obj`: `coloured`, the surface with the last day's
/// cells on it as a colour per vertex, on the plane or on a mesh alike.
pub(super) fn write_mosaic_obj(dir: &Path, coloured: &Mesh) -> Result<Vec<PathBuf>> {
    let style = ObjStyle {
        vertex_colours: true,
        ..ObjStyle::PLAIN
    };
    write_obj(&dir.join("mosaic.obj"), coloured, style)
}

/// Writes the cells-per-type chart (`cells.png`, `cells.svg`, when there
/// is more than one day) and the control mask (`mask.pbm`) of a mosaic's
/// run, on the plane or on a mesh alike.
///
/// # Errors
/// When a file cannot be written.
pub(super) fn write_counts_and_mask(
    params: &Params,
    names: &[&str],
    counts: &[(i32, Vec<usize>)],
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let colours: Vec<[u8; 3]> = params.types.iter().map(|t| t.colour).collect();
    let mut written = Vec::new();
    if counts.len() > 1 {
        let chart = cells_chart(&colours, names, counts);
        write_chart(&chart, dir, "cells", (900, 500), kinds, &mut written)?;
    }
    if let Some(mask) = &params.mask {
        let path = dir.join("mask.pbm");
        write_atomic(&path, morphogen_scenario::mask::to_pbm(mask).as_bytes())?;
        written.push(path);
    }
    Ok(written)
}

/// Writes `cells`, `(id, type, point)` each, as `id,type,x,y,z` lines
/// under a header: a point read from the stream (a cell's place on a mesh,
/// on the plane its position with z = 0) as the exact decimals of its
/// 16.16 bits, a point computed from one (on a cylinder, a torus) in the
/// shortest form that reads back ([`text::float`]).
pub(super) fn write_csv(
    cells: impl Iterator<Item = (u32, u8, [f64; 3])>,
    path: &Path,
) -> Result<()> {
    OutputFile::write_with(path, |file| {
        file.write_all(b"id,type,x,y,z\n")?;
        let mut line = Vec::with_capacity(64);
        for (id, kind, point) in cells {
            line.clear();
            text::int(&mut line, id);
            line.push(b',');
            text::int(&mut line, kind);
            for c in point {
                line.push(b',');
                text::float(&mut line, c);
            }
            line.push(b'\n');
            file.write_all(&line)?;
        }
        Ok(())
    })
}
