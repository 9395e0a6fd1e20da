//! Bodies (`horse-growth`, `cow-growth`, `horse-trot`, or an OBJ with a
//! cylinder file): an OBJ per frame, a side-view PNG per frame (one age
//! each) at one common scale, a strip of the yearly ages side by side
//! (`ages.png`), and `summary.txt` with the binding counts and per-frame
//! sizes.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::body::BindingSummary;
use morphogen::stream::Record;
use rayon::prelude::*;
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::picture;
use super::raster;
use super::text;
use crate::atomic::{OutputFile, write_atomic};

/// Pictures are drawn at this many times their size, then averaged down
/// (anti-aliasing for the triangles of [`raster`]).
const OVERSAMPLE: f32 = 2.0;

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

fn fx(v: morphogen::fx::Fx) -> f64 {
    f64::from(v.to_bits()) / 65_536.0
}

/// Splits a record stream into frames.
#[must_use]
pub fn frames(records: &[Record]) -> Vec<Frame> {
    let mut out = Vec::new();
    let mut current: Option<Frame> = None;
    for r in records {
        match r {
            Record::FrameStart { frame, time } => {
                current = Some(Frame {
                    index: *frame,
                    age: fx(*time),
                    ..Frame::default()
                });
            }
            Record::MeshVertex { id, p } => {
                if let Some(f) = current.as_mut() {
                    let i = *id as usize;
                    if f.vertices.len() <= i {
                        f.vertices.resize(i + 1, [0.0; 3]);
                    }
                    f.vertices[i] = p.map(fx);
                }
            }
            Record::Triangle { v } => {
                if let Some(f) = current.as_mut() {
                    f.triangles.push(*v);
                }
            }
            Record::FrameEnd { .. } => out.extend(current.take()),
            _ => {}
        }
    }
    out
}

/// Writes the OBJ of a frame to `path`, headed by the comment `header`
/// and named `object`.
///
/// # Errors
/// When the file cannot be written.
pub fn obj(frame: &Frame, header: &str, object: &str, path: &Path) -> Result<()> {
    OutputFile::write_with(path, |file| {
        writeln!(file, "# {header}\no {object}")?;
        let mut line = Vec::with_capacity(64);
        for v in &frame.vertices {
            line.clear();
            line.push(b'v');
            for &c in v {
                line.push(b' ');
                text::decimals_5(&mut line, c);
            }
            line.push(b'\n');
            file.write_all(&line)?;
        }
        for t in &frame.triangles {
            line.clear();
            line.push(b'f');
            for &k in t {
                line.push(b' ');
                text::int(&mut line, u64::from(k) + 1);
            }
            line.push(b'\n');
            file.write_all(&line)?;
        }
        Ok(())
    })
}

/// Side-view bounds (x, y) over frames, with a margin.
pub(crate) fn bounds(frames: &[&Frame]) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, 0.0f64, f64::MIN);
    for f in frames {
        for v in &f.vertices {
            x0 = x0.min(v[0]);
            x1 = x1.max(v[0]);
            y0 = y0.min(v[1]);
            y1 = y1.max(v[1]);
        }
    }
    if x0 > x1 {
        return (0.0, 1.0, 0.0, 1.0);
    }
    let m = 0.04 * (x1 - x0).max(y1 - y0);
    (x0 - m, x1 + m, y0 - m, y1 + m)
}

/// Body colour and ground colour per model.
fn colour(title: &str) -> [f32; 3] {
    if title.starts_with("cow") {
        [0.86, 0.85, 0.82]
    } else {
        [0.62, 0.36, 0.18]
    }
}

/// Draws `frame` seen from its left side (+z), orthographic, painter's
/// order far to near, Lambert-shaded, into a [`canvas`] where model point
/// (x, y) lands at `(ox + s·x, oy − s·y)` in the saved picture's pixels.
pub(crate) fn draw(pixmap: &mut Pixmap, frame: &Frame, base: [f32; 3], s: f32, ox: f32, oy: f32) {
    let (s, ox, oy) = (s * OVERSAMPLE, ox * OVERSAMPLE, oy * OVERSAMPLE);
    let light = {
        let l = [-0.35f64, 0.65, 0.68];
        let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        l.map(|c| c / n)
    };
    let mut order: Vec<(f64, usize)> = Vec::with_capacity(frame.triangles.len());
    for (i, t) in frame.triangles.iter().enumerate() {
        let Some(p) = t
            .iter()
            .map(|&v| frame.vertices.get(v as usize))
            .collect::<Option<Vec<_>>>()
        else {
            continue;
        };
        let z = (p[0][2] + p[1][2] + p[2][2]) / 3.0;
        order.push((z, i));
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
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
        let lambert = ((n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / len).max(0.0);
        let k = (0.35 + 0.65 * lambert) as f32;
        let shade = Color::from_rgba(base[0] * k, base[1] * k, base[2] * k, 1.0)
            .unwrap_or(Color::BLACK)
            .to_color_u8();
        let at = |p: [f64; 3]| [ox + s * p[0] as f32, oy - s * p[1] as f32];
        raster::triangle(
            pixmap,
            [at(a), at(b), at(c)],
            [shade.red(), shade.green(), shade.blue()],
        );
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

/// A blank picture of `width × height` pixels once saved (drawn at
/// [`OVERSAMPLE`] times that).
pub(crate) fn canvas(width: u32, height: u32) -> Result<Pixmap> {
    let k = OVERSAMPLE as u32;
    let mut p = Pixmap::new(width * k, height * k).context("picture size must be positive")?;
    p.fill(Color::from_rgba8(246, 244, 238, 255));
    Ok(p)
}

/// Saves a [`canvas`] at its own size.
pub(crate) fn save(pixmap: &Pixmap, path: &Path) -> Result<()> {
    picture::save(&picture::half(pixmap)?, path)
}

/// Side view of one frame, `width` pixels wide, at the scale fitting
/// `bounds`.
fn side_view(frame: &Frame, title: &str, b: (f64, f64, f64, f64), width: u32) -> Result<Pixmap> {
    let s = f64::from(width) / (b.1 - b.0);
    let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
    let mut p = canvas(width, height)?;
    let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
    ground(&mut p, oy);
    draw(&mut p, frame, colour(title), s as f32, ox, oy);
    Ok(p)
}

/// Frames at whole years (every 12 months), at most six, for the strip.
fn yearly(frames: &[Frame]) -> Vec<&Frame> {
    let picked: Vec<&Frame> = frames
        .iter()
        .filter(|f| (f.age / 12.0 - (f.age / 12.0).round()).abs() < 1e-6)
        .collect();
    let step = picked.len().div_ceil(6).max(1);
    picked.into_iter().step_by(step).collect()
}

/// All of a body run's files: `frame_NNN.obj`, `side_NNN.png`, `ages.png`
/// and `summary.txt` (with `binding`, when known).
///
/// # Errors
/// When a file cannot be written.
pub fn write(
    title: &str,
    records: &[Record],
    dir: &Path,
    binding: Option<BindingSummary>,
) -> Result<Vec<PathBuf>> {
    let frames = frames(records);
    let mut written = Vec::new();
    let all: Vec<&Frame> = frames.iter().collect();
    let b = bounds(&all);
    let mut summary = format!("{title}: {} frames\n", frames.len());
    if let Some(f) = frames.first() {
        let _ = writeln!(
            summary,
            "vertices {}, triangles {}",
            f.vertices.len(),
            f.triangles.len()
        );
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
    for f in &frames {
        let fb = bounds(&[f]);
        let _ = writeln!(
            summary,
            "{:5}  {:11.2}  {:6.2}  {:6.2}",
            f.index,
            f.age,
            fb.1 - fb.0,
            fb.3 - fb.2
        );
    }
    let per_frame: Vec<[PathBuf; 2]> = frames
        .par_iter()
        .map(|f| {
            let obj_path = dir.join(format!("frame_{:03}.obj", f.index));
            let header = format!("{title} frame {}, age {:.2} months", f.index, f.age);
            obj(f, &header, "body", &obj_path)?;
            let png_path = dir.join(format!("side_{:03}.png", f.index));
            save(&side_view(f, title, b, 640)?, &png_path)?;
            Ok([obj_path, png_path])
        })
        .collect::<Result<_>>()?;
    written.extend(per_frame.into_iter().flatten());
    let strip = yearly(&frames);
    if !strip.is_empty() {
        let panel = 300u32;
        let s = f64::from(panel) / (b.1 - b.0);
        let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
        let mut p = canvas(panel * strip.len() as u32, height)?;
        let oy = (b.3 * s) as f32;
        ground(&mut p, oy);
        for (k, f) in strip.iter().enumerate() {
            let ox = (panel as f64 * k as f64 - b.0 * s) as f32;
            draw(&mut p, f, colour(title), s as f32, ox, oy);
        }
        let path = dir.join("ages.png");
        save(&p, &path)?;
        let ages: Vec<String> = strip.iter().map(|f| format!("{:.0}", f.age)).collect();
        let _ = writeln!(summary, "ages.png shows months {}", ages.join(", "));
        written.push(path);
    }
    let path = dir.join("summary.txt");
    write_atomic(&path, summary.as_bytes())?;
    written.push(path);
    Ok(written)
}
