//! Bodies (`horse-growth`, `cow-growth`, `horse-trot`, or an OBJ with a
//! cylinder file): an OBJ per frame and `model.glb` with every frame, a
//! side-view PNG per frame (one age each) at one common scale and the
//! same views as `animation.png`, a strip of the yearly ages side by side
//! (`ages.png`, each labelled), the growth table's columns over age
//! (`growth.png`, `growth.svg`) and `summary.txt` with the binding counts
//! and per-frame sizes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::body::{BindingSummary, GrowthTable};
use morphogen::fx::{Fx, Real};
use morphogen::stream::Record;
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::chart::write_chart;
use super::chart::{Axis, Chart, Series, series_colour};
use super::kinds::{Kind, Kinds};
use super::mesh::{self, GlbWriter, Library, ObjStyle, write_frame_obj};
use super::montage::save_montage;
use super::numbered::{FileSeries, Numbering};
use super::picture::Canvases;
use super::pipeline::pipeline;
use super::slots::{ANIMATION_DELAY_MS, OrderedAnimation, animation_frames};
use super::text::trimmed;
use super::{normals, picture, raster};
use crate::atomic::write_atomic;
use crate::records::{Place, Records};

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

/// Draws `frame` seen from its left side (+z), orthographic, painter's
/// order far to near, Lambert-shaded as `shading` says, into a [`canvas`]
/// where model point (x, y) lands at `(ox + s·x, oy − s·y)` in the saved
/// picture's pixels.
pub(crate) fn draw(
    pixmap: &mut Pixmap,
    frame: &Frame,
    (base, shading): ([f32; 3], Shading),
    s: f32,
    ox: f32,
    oy: f32,
) {
    let (s, ox, oy) = (s * OVERSAMPLE, ox * OVERSAMPLE, oy * OVERSAMPLE);
    let light = {
        let l = [-0.35f64, 0.65, 0.68];
        let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        l.map(|c| c / n)
    };
    let corners = match shading {
        Shading::Flat => Vec::new(),
        Shading::Smooth => normals::corner_normals(&frame.vertices, &frame.triangles),
    };
    // Red, green and blue of `base` Lambert-shaded by the normal `n` of
    // length `len`.
    let shade = |n: [f64; 3], len: f64| {
        let lambert = ((n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / len).max(0.0);
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
        let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len <= 0.0 || n[2] < 0.0 {
            continue; // degenerate, or facing away from the viewer
        }
        let at = |p: [f64; 3]| [ox + s * p[0] as f32, oy - s * p[1] as f32];
        let p = [at(a), at(b), at(c)];
        match corners.get(i) {
            Some(corners) => raster::smooth_triangle(pixmap, p, corners.map(|n| shade(n, 1.0))),
            None => raster::triangle(pixmap, p, shade(n, len)),
        }
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
    Canvases::new(width * k, height * k, Color::from_rgba8(246, 244, 238, 255))
}

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
    draw(
        &mut p,
        frame,
        (colour(title), Shading::Flat),
        s as f32,
        ox,
        oy,
    );
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

/// All of a body run's files (those of `kinds`): `frame_NNN.obj`,
/// `model.glb`, `side_NNN.png`, `animation.png` (every frame, or 60
/// spread evenly), `ages.png`, `growth.png`/`growth.svg` (with `table`)
/// and `summary.txt` (with `binding`, when known). Two passes, a frame at
/// a time: the sizes and the common scale, then the files.
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
    let mut count = 0usize;
    let mut extent = Extent::new();
    let mut first = None;
    let mut sizes = String::new();
    // The frames at whole years (by position), at most six of them below.
    let mut yearly = Vec::new();
    let mut framer = Framer::default();
    records.visit(Place::START, |_, r| {
        if let Some(f) = framer.push(r) {
            first.get_or_insert((f.vertices.len(), f.triangles.len()));
            let fb = bounds(&[&f]);
            let _ = writeln!(
                sizes,
                "{:5}  {:11.2}  {:6.2}  {:6.2}",
                f.index,
                f.age,
                fb.1 - fb.0,
                fb.3 - fb.2
            );
            extent.include(&f);
            if whole_year(f.age) {
                yearly.push(count);
            }
            count += 1;
        }
        Ok(())
    })?;
    let b = extent.bounds();
    let numbering = Numbering::frames(count);
    let mut summary = format!("{title}: {count} frames\n");
    if let Some((vertices, triangles)) = first {
        let _ = writeln!(summary, "vertices {vertices}, triangles {triangles}");
    }
    if let Some(s) = binding {
        let _ = writeln!(
            summary,
            "vertices in no cylinder (following the nearest): {}\nvertices blended from n cylinders (n = 1, 2, ...): {:?}",
            s.unbound,
            &s.by_count[1..]
        );
    }
    summary.push_str("frame  age(months)  length  height  (side-view extent of the body)\n");
    summary.push_str(&sizes);
    let step = yearly.len().div_ceil(6).max(1);
    let strip: Vec<usize> = if kinds.has(Kind::Png) {
        yearly.into_iter().step_by(step).collect()
    } else {
        Vec::new()
    };
    let panel = 300u32;
    let s = f64::from(panel) / (b.1 - b.0);
    let oy = (b.3 * s) as f32;
    let mut ages = Vec::new();
    let mut picture = if strip.is_empty() {
        None
    } else {
        let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
        let mut p = canvas(panel * strip.len() as u32, height)?;
        ground(&mut p, oy);
        Some(p)
    };
    let side_width = 640u32;
    // As side_view sizes its pictures.
    let side_scale = f64::from(side_width) / (b.1 - b.0);
    let side_height = ((b.3 - b.2) * side_scale).ceil().max(1.0) as u32;
    let sides = canvases(side_width, side_height);
    let picked = if kinds.has(Kind::Anim) && count > 1 {
        animation_frames(count)
    } else {
        Vec::new()
    };
    let anim_path = dir.join("animation.png");
    let apng = if picked.is_empty() {
        None
    } else {
        Some(OrderedAnimation::new(
            &anim_path,
            side_width,
            side_height,
            picked.len(),
        )?)
    };
    let rgb = rgb_of(colour(title));
    let mut glb = kinds.has(Kind::Glb).then(|| GlbWriter::new(title, 0.0254));
    let mut library = Library::new(dir, LIBRARY);
    let per_frame: Vec<Vec<PathBuf>> = pipeline(
        |send| {
            let mut framer = Framer::default();
            let mut k = 0usize;
            records.visit(Place::START, |_, r| {
                let Some(f) = framer.push(r) else {
                    return Ok(());
                };
                if let (Some(slot), Some(p)) = (strip.iter().position(|&i| i == k), &mut picture) {
                    let ox = (f64::from(panel) * slot as f64 - b.0 * s) as f32;
                    draw(p, &f, (colour(title), Shading::Flat), s as f32, ox, oy);
                    ages.push(f.age);
                }
                let header = format!("{title} frame {}, age {:.2} months", f.index, f.age);
                let m = if kinds.has(Kind::Obj) || glb.is_some() {
                    Some(solid(&f, &header, "body", rgb)?)
                } else {
                    None
                };
                if let (Some(glb), Some(m)) = (&mut glb, &m) {
                    glb.push_frame(m, k as f32 * f32::from(ANIMATION_DELAY_MS) / 1000.0)?;
                }
                if let Some(m) = m.as_ref().filter(|_| kinds.has(Kind::Obj)) {
                    library.write_once(m)?;
                }
                let slot = picked.binary_search(&k).ok();
                k += 1;
                send((f, m, slot))
            })
        },
        |(f, m, slot): (Frame, Option<mesh::Mesh>, Option<usize>)| {
            let mut paths = Vec::with_capacity(2);
            if let Some(m) = m.filter(|_| kinds.has(Kind::Obj)) {
                let obj_path = dir.join(numbering.name(FileSeries::FRAMES, f.index));
                write_frame_obj(&obj_path, &m, ObjStyle::PLAIN, LIBRARY)?;
                paths.push(obj_path);
            }
            let apng = apng.as_ref().zip(slot);
            if kinds.has(Kind::Png) || apng.is_some() {
                let side = side_view(&f, title, b, side_width, &sides)?;
                let view = picture::half_rgb(&side)?;
                let (w, h) = (side.width() / 2, side.height() / 2);
                sides.give_back(side);
                if kinds.has(Kind::Png) {
                    let png_path = dir.join(numbering.name(FileSeries::SIDES, f.index));
                    picture::save_rgb(w, h, &view, &png_path)?;
                    paths.push(png_path);
                }
                if let Some((apng, slot)) = apng {
                    apng.frame(slot, view, label(f.age))?;
                }
            }
            Ok(paths)
        },
    )?;
    let mut written: Vec<PathBuf> = per_frame.into_iter().flatten().collect();
    written.extend(library.written());
    if let Some(glb) = glb {
        let path = dir.join("model.glb");
        glb.write(&path)?;
        written.push(path);
    }
    if let Some(apng) = apng {
        apng.finish()?;
        written.push(anim_path);
    }
    if let Some(p) = picture {
        let (w, h) = (p.width() / 2 / ages.len().max(1) as u32, p.height() / 2);
        let labels: Vec<_> = (0..)
            .zip(&ages)
            .map(|(n, &age)| ([n * w, 0, w, h], label(age)))
            .collect();
        let path = dir.join("ages.png");
        save_montage(&p, &labels, &path)?;
        let months: Vec<String> = ages.iter().map(|a| format!("{a:.0}")).collect();
        let _ = writeln!(summary, "ages.png shows months {}", months.join(", "));
        written.push(path);
    }
    if let Some(table) = table.filter(|t| !t.columns.is_empty()) {
        let chart = table_chart(table);
        write_chart(&chart, dir, "growth", (900, 560), kinds, &mut written)?;
    }
    let path = dir.join("summary.txt");
    write_atomic(&path, summary.as_bytes())?;
    written.push(path);
    Ok(written)
}
