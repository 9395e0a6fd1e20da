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
use nalgebra::Vector3;
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::chart::{Axis, Chart, Series, series_colour};
use super::driver::{self, Closing, Montage, Products, Rgb};
use super::kinds::{Kinds, MeshFiles};
use super::mesh;
use super::numbered::FileSeries;
use super::picture::Canvases;
use super::plot::{self, Drawing, Pen};
use super::slots::OrderedAnimation;
use super::text::trimmed;
use super::{normals, raster};
use crate::atomic::write_atomic;
use crate::records::Records;

/// Pictures are drawn at this many times their size, then averaged down
/// (anti-aliasing for the triangles of [`raster`]).
const OVERSAMPLE: f32 = 2.0;

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "body.mtl";

/// One decoded frame of a body stream.
#[derive(Debug, Default, Clone)]
pub struct Frame {
    /// Frame index.
    pub index: u32,
    /// Age, months.
    pub age: f64,
    /// Vertex positions by id.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles by vertex id.
    pub triangles: Vec<[u32; 3]>,
}

/// Splits a record stream into frames, one record at a time: a frame
/// start begins a frame (dropping one left open), a frame end hands it
/// over.
#[derive(Debug, Default)]
pub struct Framer {
    current: Option<Frame>,
}

impl Framer {
    /// Takes the next record; returns the frame it ends, if any.
    pub fn push(&mut self, r: &Record) -> Option<Frame> {
        match r {
            Record::FrameStart { frame, time } => {
                self.current = Some(Frame {
                    index: *frame,
                    age: f64::from_fx(*time),
                    ..Frame::default()
                });
            }
            Record::MeshVertex { id, p } => {
                if let Some(f) = self.current.as_mut() {
                    let i = *id as usize;
                    if f.vertices.len() <= i {
                        f.vertices.resize(i + 1, [0.0; 3]);
                    }
                    f.vertices[i] = p.map(f64::from_fx);
                }
            }
            Record::Triangle { v } => {
                if let Some(f) = self.current.as_mut() {
                    f.triangles.push(*v);
                }
            }
            Record::FrameEnd { .. } => return self.current.take(),
            _ => {}
        }
        None
    }
}

/// Splits a record stream into frames.
#[must_use]
pub fn frames(records: &[Record]) -> Vec<Frame> {
    let mut framer = Framer::default();
    records.iter().filter_map(|r| framer.push(r)).collect()
}

/// The mesh of a frame for OBJ and glTF: one group of its triangles,
/// named `object`, headed by the comment `header`, every vertex `rgb`,
/// in the material `object` of that colour.
///
/// # Errors
/// When a triangle names a vertex the frame lacks.
pub fn solid(frame: &Frame, header: &str, object: &str, rgb: [u8; 3]) -> Result<mesh::Mesh> {
    let mut m = mesh::Mesh::from_triangles(frame.vertices.clone(), &frame.triangles)?;
    m.comment(header);
    m.set_object(object)?;
    m.set_colours(vec![rgb; frame.vertices.len()])?;
    let material = m.material(object, rgb)?;
    m.paint(material)?;
    Ok(m)
}

/// A colour of [`draw`] (0–1) as RGB bytes.
pub(crate) fn rgb_of(base: [f32; 3]) -> [u8; 3] {
    base.map(|c| (c * 255.0).round().clamp(0.0, 255.0) as u8)
}

/// The side-view extent (x, y) of frames seen so far; y from 0 at least
/// (the ground).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extent {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Extent {
    pub(crate) fn new() -> Extent {
        Extent {
            x0: f64::MAX,
            x1: f64::MIN,
            y0: 0.0,
            y1: f64::MIN,
        }
    }

    pub(crate) fn include(&mut self, frame: &Frame) {
        for v in &frame.vertices {
            self.x0 = self.x0.min(v[0]);
            self.x1 = self.x1.max(v[0]);
            self.y0 = self.y0.min(v[1]);
            self.y1 = self.y1.max(v[1]);
        }
    }

    /// The bounds with a margin.
    pub(crate) fn bounds(&self) -> (f64, f64, f64, f64) {
        let Extent { x0, x1, y0, y1 } = *self;
        if x0 > x1 {
            return (0.0, 1.0, 0.0, 1.0);
        }
        let m = 0.04 * (x1 - x0).max(y1 - y0);
        (x0 - m, x1 + m, y0 - m, y1 + m)
    }
}

/// Side-view bounds (x, y) over frames, with a margin.
pub(crate) fn bounds(frames: &[&Frame]) -> (f64, f64, f64, f64) {
    let mut extent = Extent::new();
    frames.iter().for_each(|f| extent.include(f));
    extent.bounds()
}

/// Body colour and ground colour per model.
fn colour(title: &str) -> [f32; 3] {
    if title.starts_with("cow") {
        [0.86, 0.85, 0.82]
    } else {
        [0.62, 0.36, 0.18]
    }
}

/// How [`draw`] shades a frame's triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Shading {
    /// One shade a triangle: the body's polygons, as the paper draws them.
    Flat,
    /// Between the shades at the corners ([`normals::corner_normals`]):
    /// the smooth surface of a wrapped bone.
    Smooth,
}

/// Where [`draw`] puts a frame: model point (x, y) at `(ox + s·x,
/// oy − s·y)` in the saved pixels of a picture whose left edge is `left`
/// pixels into it (a montage's tile, drawn on a canvas of its own to the
/// very pixels of the whole montage).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Placement {
    pub s: f32,
    pub ox: f32,
    pub oy: f32,
    pub left: f32,
}

impl Placement {
    /// Model point (x, y) at `(ox + s·x, oy − s·y)`.
    pub(crate) fn new(s: f32, ox: f32, oy: f32) -> Placement {
        Placement {
            s,
            ox,
            oy,
            left: 0.0,
        }
    }
}

/// Draws `frame` seen from its left side (+z), orthographic, painter's
/// order far to near, Lambert-shaded as `shading` says, into a [`canvas`]
/// where `at` places it.
pub(crate) fn draw(
    pixmap: &mut Pixmap,
    frame: &Frame,
    (base, shading): ([f32; 3], Shading),
    at: Placement,
) {
    let Placement { s, ox, oy, left } = at;
    let left = left * OVERSAMPLE;
    let (s, ox, oy) = (s * OVERSAMPLE, ox * OVERSAMPLE, oy * OVERSAMPLE);
    let light = Vector3::new(-0.35f64, 0.65, 0.68).normalize();
    let corners = match shading {
        Shading::Flat => Vec::new(),
        Shading::Smooth => normals::corner_normals(&frame.vertices, &frame.triangles),
    };
    // Red, green and blue of `base` Lambert-shaded by the normal `n` of
    // length `len`.
    let shade = |n: Vector3<f64>, len: f64| {
        let lambert = (n.dot(&light) / len).max(0.0);
        let k = (0.35 + 0.65 * lambert) as f32;
        let c = Color::from_rgba(base[0] * k, base[1] * k, base[2] * k, 1.0)
            .unwrap_or(Color::BLACK)
            .to_color_u8();
        [c.red(), c.green(), c.blue()]
    };
    let mut order: Vec<(i64, usize)> = Vec::with_capacity(frame.triangles.len());
    for (i, t) in frame.triangles.iter().enumerate() {
        let z = |v: u32| frame.vertices.get(v as usize).map(|p| p[2]);
        let (Some(a), Some(b), Some(c)) = (z(t[0]), z(t[1]), z(t[2])) else {
            continue;
        };
        order.push((raster::depth_key((a + b + c) / 3.0), i));
    }
    // Back to front: the stable sort by depth, as keys and positions.
    order.sort_unstable();
    for (_, i) in order {
        let t = frame.triangles[i];
        let [a, b, c] = t.map(|v| frame.vertices[v as usize]);
        let [pa, pb, pc] = [a, b, c].map(Vector3::from);
        let n = (pb - pa).cross(&(pc - pa));
        let len = n.norm();
        if len <= 0.0 || n.z < 0.0 {
            continue; // degenerate, or facing away from the viewer
        }
        let at = |p: [f64; 3]| [ox + s * p[0] as f32 - left, oy - s * p[1] as f32];
        let p = [at(a), at(b), at(c)];
        match corners.get(i) {
            Some(corners) => {
                let shaded = corners.map(|n| shade(Vector3::from(n), 1.0));
                raster::smooth_triangle(pixmap, p, shaded);
            }
            None => raster::triangle(pixmap, p, shade(n, len)),
        }
    }
}

/// The frame's outline for a pen plotter, in [`draw`]'s view (along −z,
/// y up): one pen, `outline`.
pub(crate) fn outline(frame: &Frame) -> Drawing {
    Drawing {
        pens: vec![Pen {
            name: "outline".into(),
            colour: [60, 50, 40],
            strokes: plot::silhouette(&frame.vertices, &frame.triangles),
        }],
    }
}

/// The ground line at `y` (saved picture's pixels) across a [`canvas`].
fn ground(pixmap: &mut Pixmap, y: f32) {
    let mut pb = PathBuilder::new();
    pb.move_to(0.0, y * OVERSAMPLE);
    pb.line_to(pixmap.width() as f32, y * OVERSAMPLE);
    if let Some(path) = pb.finish() {
        let mut paint = Paint::default();
        paint.set_color(Color::from_rgba8(120, 140, 90, 255));
        let stroke = Stroke {
            width: 2.0 * OVERSAMPLE,
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    }
}

/// Blank pictures of `width × height` pixels once saved (drawn at
/// [`OVERSAMPLE`] times that), for frame after frame.
pub(crate) fn canvases(width: u32, height: u32) -> Canvases {
    let k = OVERSAMPLE as u32;
    let [r, g, b] = BACKGROUND;
    Canvases::new(width * k, height * k, Color::from_rgba8(r, g, b, 255))
}

/// The colour behind a body or a bone.
pub(crate) const BACKGROUND: [u8; 3] = [246, 244, 238];

/// A blank picture of `width × height` pixels once saved (drawn at
/// [`OVERSAMPLE`] times that).
pub(crate) fn canvas(width: u32, height: u32) -> Result<Pixmap> {
    canvases(width, height).take()
}

/// Side view of one frame, `width` pixels wide, at the scale fitting
/// `bounds`, drawn on a canvas of `sides` (as high as that scale needs).
fn side_view(
    frame: &Frame,
    title: &str,
    b: (f64, f64, f64, f64),
    width: u32,
    sides: &Canvases,
) -> Result<Pixmap> {
    let s = f64::from(width) / (b.1 - b.0);
    let mut p = sides.take()?;
    let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
    ground(&mut p, oy);
    let at = Placement::new(s as f32, ox, oy);
    draw(&mut p, frame, (colour(title), Shading::Flat), at);
    Ok(p)
}

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

    fn animation(&self, path: &Path, frames: usize) -> Result<Option<OrderedAnimation>> {
        let height = Body::height(self.extent.bounds(), SIDE_WIDTH);
        OrderedAnimation::new(path, SIDE_WIDTH, height, frames).map(Some)
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
        let path = dir.join("summary.txt");
        write_atomic(&path, summary.as_bytes())?;
        written.push(path);
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
