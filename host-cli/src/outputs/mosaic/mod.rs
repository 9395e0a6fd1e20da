//! Mosaic presets (MClone): per streamed day a CSV of the cells
//! (`cells_dayNN.csv`: `id,type,x,y,z`, their points on the object the
//! domain makes, `object`) and a Voronoi picture (`day_NN.png`: every
//! pixel takes the colour of the type of its nearest cell, distances periodic where the
//! domain wraps, the cylinder unrolled with u to the right and v down);
//! on a cylinder also the shaded object (`surface_dayNN.png`);
//! `mosaic.png` (and `surface.png`) is the last day; `surface.obj` the
//! bare surface and `mosaic.obj` the last day coloured on it;
//! `animation.png` the days in order (every day, or 60 spread evenly);
//! `cells.png`/`cells.svg` the number of cells of each type per day, in
//! the types' colours; the control mask, if any, as `mask.pbm`;
//! `plot.svg` the last day's cell edges (`edges`). Days are written in
//! parallel.

mod edges;
mod object;
pub mod on_mesh;
mod pattern;
mod voronoi;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Result, anyhow};
use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::mosaic::Params;
use morphogen::stream::Record;
use morphogen_stream_text::text;

use super::chart::{Axis, Chart, Series};
use super::driver::{self, Closing, Products, Rgb, Still};
use super::kinds::{Kinds, Pixels, Product, Sequence};
use super::mesh::{Mesh, ObjStyle};
use super::numbered::{FileSeries, Numbering};
use super::plot::Drawing;
use crate::atomic::OutputFile;
use crate::records::Records;
use object::{Surface, SurfaceView};

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

/// Groups a mosaic stream's records into days: a frame start begins a
/// day (handing over one left open), a frame end hands it over.
#[derive(Debug, Default)]
pub(super) struct DayFramer {
    current: Option<Day>,
}

impl DayFramer {
    /// Takes the next record; returns the day it ends, if any.
    fn push(&mut self, r: &Record) -> Option<Day> {
        match r {
            Record::FrameStart { time, .. } => self.current.replace(Day {
                day: time.floor_int(),
                cells: Vec::new(),
            }),
            Record::Cell { id, kind, p } => {
                if let Some(d) = self.current.as_mut() {
                    d.cells.push((*id, *kind, p[0], p[1]));
                }
                None
            }
            Record::FrameEnd { .. } => self.current.take(),
            _ => None,
        }
    }
}

/// The cells of each type in `cells`, by their types' `kinds`: at least
/// one count per type of `types`.
pub(super) fn by_type(kinds: impl Iterator<Item = u8>, types: usize) -> Vec<usize> {
    let mut by_type = vec![0usize; types];
    for kind in kinds {
        let k = usize::from(kind);
        if by_type.len() <= k {
            by_type.resize(k + 1, 0);
        }
        by_type[k] += 1;
    }
    by_type
}

/// What a day's files measure for `types.csv` and `pattern.csv`: each
/// type's area and the figures of its pattern.
pub(super) type Measured = (Vec<u64>, Vec<Figures>);

/// A planar mosaic run's products ([`driver::write`], the module's
/// files).
struct Plane<'a> {
    dir: &'a Path,
    params: &'a Params<'a>,
    names: &'a [&'a str],
    kinds: Kinds,
    colours: Vec<[u8; 3]>,
    surface: Surface,
    /// The pictures' size, pixels.
    size: (u32, u32),
    /// The object the surface pictures show, found once.
    view: Option<SurfaceView>,
    /// Per day: its number and the cells of each type.
    counts: Vec<(i32, Vec<usize>)>,
    /// The last day.
    last: Option<Day>,
    /// The picture of the latest day drawn so far (by position), kept
    /// for `mosaic.obj`, which shows the last day.
    latest: Mutex<Option<(usize, Indexed)>>,
}

impl Products for Plane<'_> {
    type Frame = Day;
    type Framer = DayFramer;
    type Picture = Indexed;
    type Measure = Measured;

    fn push(framer: &mut DayFramer, record: &Record) -> Result<Option<Day>> {
        Ok(framer.push(record))
    }

    fn survey(&mut self, day: Day) -> Result<()> {
        let by_type = by_type(day.cells.iter().map(|c| c.1), self.colours.len());
        self.counts.push((day.day, by_type));
        self.last = Some(day);
        Ok(())
    }

    fn index(day: &Day) -> i64 {
        i64::from(day.day)
    }

    fn numbering(&self, _count: usize) -> Numbering {
        Numbering::days(self.params.days)
    }

    fn stills(&self) -> Option<FileSeries> {
        Some(FileSeries::DAYS)
    }

    fn animation(&self, frames: usize) -> Result<Option<Sequence>> {
        Ok(Some(Sequence {
            size: self.size,
            palette: Some(palette(&self.colours)),
            frames,
        }))
    }

    fn picture(&self, day: &Day) -> Result<Indexed> {
        Ok(voronoi(&self.params.domain, &self.colours, &day.cells))
    }

    fn label(&self, day: &Day) -> String {
        format!("day {}", day.day)
    }

    fn frame_work(&self) -> (bool, bool) {
        let tables = self.kinds.wants(Product::Table);
        (tables || self.kinds.wants(Product::FramePicture), tables)
    }

    fn frame_files(
        &self,
        d: &Day,
        position: usize,
        picture: Option<Indexed>,
        numbering: Numbering,
    ) -> Result<(Vec<PathBuf>, Option<Measured>)> {
        let (dir, domain) = (self.dir, &self.params.domain);
        let unit = |v: Fx| f64::from_fx(v);
        let points = || {
            d.cells
                .iter()
                .map(|&(id, kind, u, v)| (id, kind, self.surface.point(unit(u), unit(v))))
        };
        let stem = numbering.stem(FileSeries::CELLS, d.day);
        let mut paths = self
            .kinds
            .table(dir, &stem, |path| write_csv(points(), path))?;
        let Some(picture) = picture else {
            return Ok((paths, None));
        };
        let measured = self.kinds.wants(Product::Table).then(|| {
            let figures = (0..self.colours.len())
                .map(|k| picture.raster(domain).figures(k as u8 + 2))
                .collect();
            (picture.areas(self.colours.len()), figures)
        });
        if let Some(view) = &self.view {
            let stem = numbering.stem(FileSeries::SURFACES, d.day);
            let drawn = Rgb::opaque(&view.paint(picture.palette(), &|i| picture.index(i))?);
            let kinds = self.kinds;
            paths.extend(kinds.picture(Product::FramePicture, &drawn.pixels(), dir, &stem)?);
        }
        let mut latest = self
            .latest
            .lock()
            .map_err(|_| anyhow!("a mosaic picture writer stopped"))?;
        if latest.as_ref().is_none_or(|(at, ..)| *at < position) {
            *latest = Some((position, picture));
        }
        Ok((paths, measured))
    }

    fn plot(&self) -> Result<Option<Drawing>> {
        let domain = &self.params.domain;
        let last = self.last.as_ref();
        last.map(|day| edges::drawing(domain, &day.cells))
            .transpose()
    }

    fn close(self, dir: &Path, kinds: Kinds, run: Closing<Measured>) -> Result<Vec<PathBuf>> {
        let mut written = write_tables(self.names, &self.counts, run.measures, dir, kinds)?;
        let meshes = kinds.wants(Product::Mesh);
        if meshes {
            let bare = self.surface.mesh(None)?;
            written.extend(kinds.mesh(&bare, dir, "surface", ObjStyle::PLAIN)?);
        }
        if let Some(last) = self
            .last
            .filter(|_| kinds.wants(Product::Picture) || meshes)
        {
            let drawn = self
                .latest
                .into_inner()
                .map_err(|_| anyhow!("a mosaic picture writer stopped"))?;
            let picture = match drawn {
                Some((at, picture)) if at + 1 == self.counts.len() => picture,
                _ => voronoi(&self.params.domain, &self.colours, &last.cells),
            };
            // The last day's pictures again.
            written.extend(kinds.picture(Product::Picture, &picture.pixels(), dir, "mosaic")?);
            if let Some(view) = self.view.as_ref().filter(|_| kinds.wants(Product::Picture)) {
                let drawn = Rgb::opaque(&view.paint(picture.palette(), &|i| picture.index(i))?);
                written.extend(kinds.picture(Product::Picture, &drawn.pixels(), dir, "surface")?);
            }
            if meshes {
                let coloured = self.surface.mesh(Some(&|u, v| picture.at(u, v)))?;
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

/// Writes (those of `kinds`) `types.csv` and `pattern.csv` from the
/// days' `counts` and what their files `measured` (by the days'
/// positions), on the plane or on a mesh alike.
///
/// # Errors
/// When a file cannot be written.
pub(super) fn write_tables(
    names: &[&str],
    counts: &[(i32, Vec<usize>)],
    measured: Vec<(usize, Measured)>,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    if !kinds.wants(Product::Table) {
        return Ok(Vec::new());
    }
    let mut areas = vec![None; counts.len()];
    let mut figures = vec![None; counts.len()];
    for (position, (a, f)) in measured {
        if let (Some(area), Some(figure)) = (areas.get_mut(position), figures.get_mut(position)) {
            (*area, *figure) = (Some(a), Some(f));
        }
    }
    let mut written = kinds.table(dir, "types", |path| {
        write_shares(names, counts, &areas, path)
    })?;
    let pattern = |path: &Path| write_pattern(names, counts, &figures, path);
    written.extend(kinds.table(dir, "pattern", pattern)?);
    Ok(written)
}

/// Writes (those of `kinds`) the files of `params`' run (`Plane`), the
/// types named `names` where given.
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
    let surface = Surface::of(&params.domain);
    let (w, h) = picture_size(&params.domain);
    let view = if kinds.wants(Product::FramePicture) {
        surface.view([w, h])?
    } else {
        None
    };
    let plane = Plane {
        dir,
        params,
        names,
        kinds,
        colours: params.types.iter().map(|t| t.colour).collect(),
        surface,
        size: (u32::try_from(w)?, u32::try_from(h)?),
        view,
        counts: Vec::new(),
        last: None,
        latest: Mutex::new(None),
    };
    driver::write(plane, records, dir, kinds)
}

/// Writes `mosaic.obj` (of `kinds`): `coloured`, the surface with the
/// last day's cells on it as a colour per vertex, on the plane or on a
/// mesh alike.
pub(super) fn write_mosaic_obj(dir: &Path, coloured: &Mesh, kinds: Kinds) -> Result<Vec<PathBuf>> {
    let style = ObjStyle {
        vertex_colours: true,
        ..ObjStyle::PLAIN
    };
    kinds.mesh(coloured, dir, "mosaic", style)
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
        written.extend(kinds.chart(&chart, dir, "cells", (900, 500))?);
    }
    if let Some(mask) = &params.mask {
        let pixels = Pixels::Bits {
            size: (mask.width.into(), mask.height.into()),
            bits: mask.bits,
        };
        written.extend(kinds.picture(Product::Bitmap, &pixels, dir, "mask")?);
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
