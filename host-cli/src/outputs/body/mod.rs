//! Bodies (`horse-growth`, `cow-growth`, `horse-trot`, or an OBJ with a
//! cylinder file): an OBJ per frame and `model.glb` with every frame, a
//! side-view PNG per frame (one age each) at one common scale and the
//! same views as `animation.png`, a strip of the yearly ages side by side
//! (`ages.png`, each labelled), the growth table's columns over age
//! (`growth.png`, `growth.svg`), `summary.txt` with the binding counts
//! and per-frame sizes, and `plot.svg` the last frame's outline in the
//! side view.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};
use morphogen::body::{BindingSummary, GrowthTable};
use morphogen::fx::{Fx, Real};
use morphogen::stream::Record;
use morphogen_stream_text::text::trimmed;

use super::chart::{Axis, Chart, Series, series_colour};
use super::driver::{self, Closing, Montage, Products, Rgb};
use super::kinds::{Kinds, MeshFiles, Sequence};
use super::mesh;
use super::numbered::FileSeries;
use super::picture::Canvases;
use super::plot::Drawing;
use crate::records::Records;

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "body.mtl";

mod frames;
mod view;

pub use frames::{Frame, Framer, frames, solid};
pub(crate) use view::{
    BACKGROUND, Extent, Placement, Shading, bounds, canvas, canvases, draw, outline, rgb_of,
};
use view::{colour, ground, side_view};

/// Whether a frame of age `age` (months) is at a whole year.
fn whole_year(age: f64) -> bool {
    (age / 12.0 - (age / 12.0).round()).abs() < 1e-6
}

/// The growth table's columns over age: interpolated lines from the
/// first to the last age, the measured values as dots of the same colour.
fn table_chart(table: &GrowthTable<'_>) -> Chart {
    let age = |v: Fx| f64::from_fx(v);
    let (first, last) = match (table.ages.first(), table.ages.last()) {
        (Some(&a), Some(&b)) => (age(a), age(b)),
        _ => (0.0, 1.0),
    };
    let mut chart = Chart::new(
        "Growth table",
        Axis::new("age", "months"),
        Axis::new("length", table.unit),
    );
    for (k, column) in table.columns.iter().enumerate() {
        let colour = series_colour(k);
        let line = (0..=120)
            .filter_map(|i| {
                let a = first + (last - first) * f64::from(i) / 120.0;
                let v = table.value(u8::try_from(k).ok()?, a)?;
                Some((a, v))
            })
            .collect();
        let measured = table
            .ages
            .iter()
            .zip(column.values)
            .map(|(&a, &v)| (age(a), f64::from_fx(v)))
            .collect();
        chart = chart
            .with_series(Series::line(column.name.as_str(), line).with_colour(colour))
            .with_series(Series::points("", measured).with_colour(colour));
    }
    chart
}

/// A frame's label: its age.
fn label(age: f64) -> String {
    format!("age {} months", trimmed(age, 1))
}

/// A body run's products ([`driver::write`]): `frame_NNN.obj`,
/// `model.glb`, `side_NNN.png` and `animation.png` (every frame, or 60
/// spread evenly) at one common scale, `ages.png` (the yearly ages, at
/// most six), `growth.png`/`growth.svg` (with a growth table),
/// `summary.txt` (with the binding counts, when known, and each frame's
/// side-view extent) and `plot.svg` (the last frame's outline).
struct Body<'a> {
    title: &'a str,
    binding: Option<BindingSummary>,
    table: Option<&'a GrowthTable<'a>>,
    count: usize,
    extent: Extent,
    /// The first frame's vertices and triangles.
    first: Option<(usize, usize)>,
    /// Each frame's line of the summary's table.
    sizes: String,
    /// The frames at whole years: their positions and ages.
    yearly: Vec<(usize, f64)>,
    /// The side views' bounds and canvases, once surveyed.
    sides: Option<(Bounds, Canvases)>,
    /// The last frame, for its outline.
    last: Option<Frame>,
}

/// Side-view bounds: least and most x, least and most y.
type Bounds = (f64, f64, f64, f64);

/// Pixels across a side view.
const SIDE_WIDTH: u32 = 640;

/// Pixels across a tile of `ages.png`.
const PANEL: u32 = 300;

impl Body<'_> {
    /// The side views' bounds (with a margin) and canvases.
    fn sides(&self) -> Result<&(Bounds, Canvases)> {
        self.sides
            .as_ref()
            .ok_or_else(|| anyhow!("the body's frames are not surveyed"))
    }

    /// The yearly frames `ages.png` shows (at most six, evenly) and their
    /// ages.
    fn strip(&self) -> Vec<(usize, f64)> {
        let step = self.yearly.len().div_ceil(6).max(1);
        self.yearly.iter().copied().step_by(step).collect()
    }

    /// The side view's height, pixels, at the scale of `bounds`.
    fn height(b: Bounds, width: u32) -> u32 {
        let s = f64::from(width) / (b.1 - b.0);
        ((b.3 - b.2) * s).ceil().max(1.0) as u32
    }
}

impl Products for Body<'_> {
    type Frame = Frame;
    type Framer = Framer;
    type Picture = Rgb;
    type Measure = ();

    fn push(framer: &mut Framer, record: &Record) -> Result<Option<Frame>> {
        Ok(framer.push(record))
    }

    fn survey(&mut self, f: Frame) -> Result<()> {
        self.first
            .get_or_insert((f.vertices.len(), f.triangles.len()));
        let fb = bounds(&[&f]);
        writeln!(
            self.sizes,
            "{:5}  {:11.2}  {:6.2}  {:6.2}",
            f.index,
            f.age,
            fb.1 - fb.0,
            fb.3 - fb.2
        )?;
        self.extent.include(&f);
        if whole_year(f.age) {
            self.yearly.push((self.count, f.age));
        }
        self.count += 1;
        self.last = Some(f);
        Ok(())
    }

    fn surveyed(&mut self, _framer: Framer) {
        let b = self.extent.bounds();
        self.sides = Some((b, canvases(SIDE_WIDTH, Body::height(b, SIDE_WIDTH))));
    }

    fn index(frame: &Frame) -> i64 {
        i64::from(frame.index)
    }

    fn mesh_files(&self) -> Option<MeshFiles> {
        Some(MeshFiles {
            library: LIBRARY,
            scene: self.title.into(),
            metres: 0.0254,
        })
    }

    fn mesh(&self, f: &Frame) -> Result<Option<mesh::Mesh>> {
        let header = format!("{} frame {}, age {:.2} months", self.title, f.index, f.age);
        solid(f, &header, "body", rgb_of(colour(self.title))).map(Some)
    }

    fn stills(&self) -> Option<FileSeries> {
        Some(FileSeries::SIDES)
    }

    fn animation(&self, frames: usize) -> Result<Option<Sequence>> {
        let height = Body::height(self.extent.bounds(), SIDE_WIDTH);
        Ok(Some(Sequence {
            size: (SIDE_WIDTH, height),
            palette: None,
            frames,
        }))
    }
    fn picture(&self, f: &Frame) -> Result<Rgb> {
        let (b, sides) = self.sides()?;
        let side = side_view(f, self.title, *b, SIDE_WIDTH, sides)?;
        let rgb = Rgb::halved(&side);
        sides.give_back(side);
        rgb
    }

    fn label(&self, f: &Frame) -> String {
        label(f.age)
    }

    fn montage(&self) -> Option<Montage> {
        let strip = self.strip();
        if strip.is_empty() {
            return None;
        }
        let b = self.extent.bounds();
        Some(Montage {
            name: "ages",
            frames: strip.iter().map(|&(k, _)| k).collect(),
            tile: (PANEL, Body::height(b, PANEL)),
            columns: strip.len() as u32,
            background: BACKGROUND,
        })
    }

    fn tile(&self, f: &Frame, n: usize) -> Result<Option<Rgb>> {
        let (b, _) = self.sides()?;
        let s = f64::from(PANEL) / (b.1 - b.0);
        let oy = (b.3 * s) as f32;
        let mut p = canvas(PANEL, Body::height(*b, PANEL))?;
        ground(&mut p, oy);
        let at = Placement {
            left: (PANEL as usize * n) as f32,
            ..Placement::new(s as f32, (f64::from(PANEL) * n as f64 - b.0 * s) as f32, oy)
        };
        draw(&mut p, f, (colour(self.title), Shading::Flat), at);
        Rgb::halved(&p).map(Some)
    }

    fn plot(&self) -> Result<Option<Drawing>> {
        Ok(self.last.as_ref().map(outline))
    }

    fn close(self, dir: &Path, kinds: Kinds, run: Closing<()>) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        let mut summary = format!("{}: {} frames\n", self.title, self.count);
        if let Some((vertices, triangles)) = self.first {
            writeln!(summary, "vertices {vertices}, triangles {triangles}")?;
        }
        if let Some(s) = self.binding {
            writeln!(
                summary,
                "vertices in no cylinder (following the nearest): {}\nvertices blended from n cylinders (n = 1, 2, ...): {:?}",
                s.unbound,
                &s.by_count[1..]
            )?;
        }
        summary.push_str("frame  age(months)  length  height  (side-view extent of the body)\n");
        summary.push_str(&self.sizes);
        if run.montage {
            let months: Vec<String> = self
                .strip()
                .iter()
                .map(|(_, a)| format!("{a:.0}"))
                .collect();
            writeln!(summary, "ages.png shows months {}", months.join(", "))?;
        }
        if let Some(table) = self.table.filter(|t| !t.columns.is_empty()) {
            let chart = table_chart(table);
            written.extend(kinds.chart(&chart, dir, "growth", (900, 560))?);
        }
        written.extend(kinds.text(&summary, dir, "summary")?);
        Ok(written)
    }
}

/// Writes (those of `kinds`) a body run's files (`Body`), its title
/// `title`, with its cylinders' `binding` and growth `table` when known.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    title: &str,
    records: &R,
    dir: &Path,
    binding: Option<BindingSummary>,
    table: Option<&GrowthTable<'_>>,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let body = Body {
        title,
        binding,
        table,
        count: 0,
        extent: Extent::new(),
        first: None,
        sizes: String::new(),
        yearly: Vec::new(),
        sides: None,
        last: None,
    };
    driver::write(body, records, dir, kinds)
}
