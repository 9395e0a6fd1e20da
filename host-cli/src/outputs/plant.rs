//! L-system plants (`abop-*` presets and `run --grammar FILE`): a PNG
//! (orthographic view along −z onto the x–y plane, y up, segments with
//! their widths, polygons filled, drawn back to front), an OBJ (segments
//! as square prisms of side `width`, polygons as faces) and a CSV of every
//! segment. Pictures and meshes show the last frame; the CSV has them all.

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::fx::Fx;
use morphogen::stream::Record;
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform,
};

use super::picture;
use super::text::{self, Whole};
use crate::atomic::OutputFile;
use crate::records::{Place, Records};

mod depth;

fn f(v: Fx) -> f64 {
    f64::from(v.to_bits()) / 65_536.0
}

fn p3(p: &[Fx; 3]) -> [f64; 3] {
    [f(p[0]), f(p[1]), f(p[2])]
}

/// A drawable item of a frame.
#[derive(Debug, Clone)]
enum Item {
    Segment {
        a: [f64; 3],
        b: [f64; 3],
        width: f64,
        colour: u16,
    },
    Polygon {
        points: Vec<[f64; 3]>,
        colour: u16,
    },
}

impl Item {
    fn depth(&self) -> f64 {
        match self {
            Item::Segment { a, b, .. } => (a[2] + b[2]) / 2.0,
            Item::Polygon { points, .. } => {
                points.iter().map(|p| p[2]).sum::<f64>() / points.len().max(1) as f64
            }
        }
    }
}

/// The items of the last frame, read from `last` (the place of the last
/// frame start, or the first record when there is none): each handed to
/// `each` in stream order. A polygon takes the points among the records
/// that follow it, as many records as it has vertices.
fn last_frame<R: Records + ?Sized>(
    records: &R,
    last: Place,
    mut each: impl FnMut(Item) -> Result<()>,
) -> Result<()> {
    // The polygon being filled: records still to take, its points, colour.
    let mut open: Option<(usize, Vec<[f64; 3]>, u16)> = None;
    records.visit(last, |_, r| {
        if let Some((left, points, _)) = &mut open {
            if let Record::Point { p } = r {
                points.push(p3(p));
            }
            *left -= 1;
            if *left == 0
                && let Some((_, points, colour)) = open.take()
            {
                each(Item::Polygon { points, colour })?;
            }
            return Ok(());
        }
        match r {
            Record::Segment {
                a,
                b,
                width,
                colour,
            } => each(Item::Segment {
                a: p3(a),
                b: p3(b),
                width: f(*width),
                colour: *colour,
            })?,
            Record::Polygon { vertices, colour } if *vertices == 0 => each(Item::Polygon {
                points: Vec::new(),
                colour: *colour,
            })?,
            Record::Polygon { vertices, colour } => {
                open = Some((usize::from(*vertices), Vec::new(), *colour));
            }
            _ => {}
        }
        Ok(())
    })?;
    // A polygon cut short by the end of the stream keeps the points it has.
    match open {
        Some((_, points, colour)) => each(Item::Polygon { points, colour }),
        None => Ok(()),
    }
}

/// The colour of index `i`: a ramp from bark brown (0) through olive to
/// leaf green (8) and yellow-green (12), constant beyond.
#[must_use]
pub fn palette(i: u16) -> [u8; 3] {
    const STOPS: [(f64, [f64; 3]); 4] = [
        (0.0, [101.0, 67.0, 33.0]),
        (4.0, [110.0, 110.0, 40.0]),
        (8.0, [50.0, 130.0, 45.0]),
        (12.0, [150.0, 195.0, 70.0]),
    ];
    let x = f64::from(i.min(12));
    let k = STOPS
        .iter()
        .rposition(|s| s.0 <= x)
        .unwrap_or(0)
        .min(STOPS.len() - 2);
    let ((x0, c0), (x1, c1)) = (STOPS[k], STOPS[k + 1]);
    let t = (x - x0) / (x1 - x0);
    let mix = |j: usize| (c0[j] + (c1[j] - c0[j]) * t).round() as u8;
    [mix(0), mix(1), mix(2)]
}

fn paint(colour: u16) -> Paint<'static> {
    let [r, g, b] = palette(colour);
    let mut paint = Paint::default();
    paint.set_color(Color::from_rgba8(r, g, b, 255));
    paint.anti_alias = true;
    paint
}

/// The x–y bounding box of the items handed to [`Extent::include`].
#[derive(Debug, Clone, Copy)]
struct Extent {
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Extent {
    fn new() -> Extent {
        Extent {
            lo: [f64::MAX; 2],
            hi: [f64::MIN; 2],
        }
    }

    fn include(&mut self, item: &Item) {
        let mut extend = |p: &[f64; 3]| {
            for (k, &v) in p.iter().take(2).enumerate() {
                self.lo[k] = self.lo[k].min(v);
                self.hi[k] = self.hi[k].max(v);
            }
        };
        match item {
            Item::Segment { a, b, .. } => {
                extend(a);
                extend(b);
            }
            Item::Polygon { points, .. } => points.iter().for_each(extend),
        }
    }
}

/// Draws the items `back_to_front` hands out (in painter's order) to a
/// `size`-pixel-wide PNG at `path`, framing `extent`.
fn png(
    extent: Extent,
    size: u32,
    back_to_front: impl FnOnce(&mut dyn FnMut(&Item)) -> Result<()>,
    path: &Path,
) -> Result<()> {
    let Extent { mut lo, mut hi } = extent;
    if lo[0] > hi[0] {
        (lo, hi) = ([-1.0, -1.0], [1.0, 1.0]);
    }
    let margin = 20.0;
    let span = [(hi[0] - lo[0]).max(1e-6), (hi[1] - lo[1]).max(1e-6)];
    let scale = (f64::from(size) - 2.0 * margin) / span[0].max(span[1]);
    let width = (span[0] * scale + 2.0 * margin).ceil() as u32;
    let height = (span[1] * scale + 2.0 * margin).ceil() as u32;
    let mut pixmap = Pixmap::new(width.max(1), height.max(1)).context("the picture has no size")?;
    pixmap.fill(Color::from_rgba8(250, 250, 245, 255));
    let px = |p: &[f64; 3]| {
        (
            (margin + (p[0] - lo[0]) * scale) as f32,
            (margin + (hi[1] - p[1]) * scale) as f32,
        )
    };
    back_to_front(&mut |item| match item {
        Item::Segment {
            a,
            b,
            width,
            colour,
        } => {
            let mut pb = PathBuilder::new();
            let (ax, ay) = px(a);
            let (bx, by) = px(b);
            pb.move_to(ax, ay);
            pb.line_to(bx, by);
            let Some(path) = pb.finish() else { return };
            let stroke = Stroke {
                width: ((width * scale) as f32).max(0.6),
                line_cap: LineCap::Round,
                line_join: LineJoin::Round,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &paint(*colour), &stroke, Transform::identity(), None);
        }
        Item::Polygon { points, colour } => {
            let mut pb = PathBuilder::new();
            for (i, p) in points.iter().enumerate() {
                let (x, y) = px(p);
                if i == 0 {
                    pb.move_to(x, y);
                } else {
                    pb.line_to(x, y);
                }
            }
            pb.close();
            let Some(path) = pb.finish() else { return };
            pixmap.fill_path(
                &path,
                &paint(*colour),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    })?;
    picture::save(&pixmap, path)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn scaled(a: [f64; 3], s: f64) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if n == 0.0 {
        return [0.0; 3];
    }
    [a[0] * s / n, a[1] * s / n, a[2] * s / n]
}

/// Appends the OBJ line `v x y z`.
fn vertex(line: &mut Vec<u8>, p: [f64; 3]) {
    line.push(b'v');
    for c in p {
        line.push(b' ');
        text::float(line, c);
    }
    line.push(b'\n');
}

/// The OBJ being written: every segment a square prism (4 side faces),
/// every polygon one face.
struct Obj<W> {
    out: W,
    line: Vec<u8>,
    /// The index of the next vertex.
    next: usize,
}

impl<W: Write> Obj<W> {
    fn new(mut out: W) -> io::Result<Obj<W>> {
        out.write_all(
            b"# morphogen L-system plant: segments as square prisms, polygons as faces\n",
        )?;
        Ok(Obj {
            out,
            line: Vec::with_capacity(256),
            next: 1,
        })
    }

    fn item(&mut self, item: &Item) -> io::Result<()> {
        let (line, next) = (&mut self.line, self.next);
        match item {
            Item::Segment { a, b, width, .. } => {
                let d = sub(*b, *a);
                let helper = if d[0].abs() < d[1].abs().max(d[2].abs()) {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let r = width.max(1e-4) / 2.0;
                let u = scaled(cross(d, helper), r);
                let v = scaled(cross(d, u), r);
                let corners = [
                    [u[0] + v[0], u[1] + v[1], u[2] + v[2]],
                    [v[0] - u[0], v[1] - u[1], v[2] - u[2]],
                    [-u[0] - v[0], -u[1] - v[1], -u[2] - v[2]],
                    [u[0] - v[0], u[1] - v[1], u[2] - v[2]],
                ];
                line.clear();
                for end in [a, b] {
                    for c in &corners {
                        vertex(line, [end[0] + c[0], end[1] + c[1], end[2] + c[2]]);
                    }
                }
                for k in 0..4 {
                    let k1 = (k + 1) % 4;
                    line.push(b'f');
                    for corner in [next + k, next + k1, next + 4 + k1, next + 4 + k] {
                        line.push(b' ');
                        text::int(line, corner);
                    }
                    line.push(b'\n');
                }
                self.out.write_all(line)?;
                self.next += 8;
            }
            Item::Polygon { points, .. } => {
                if points.len() < 3 {
                    return Ok(());
                }
                line.clear();
                for p in points {
                    vertex(line, *p);
                }
                line.push(b'f');
                for k in 0..points.len() {
                    line.push(b' ');
                    text::int(line, next + k);
                }
                line.push(b'\n');
                self.out.write_all(line)?;
                self.next += points.len();
            }
        }
        Ok(())
    }
}

/// Writes the CSV of every segment of every frame to `path`; returns the
/// place of the last frame start (the first record when there is none).
fn csv<R: Records + ?Sized>(records: &R, path: &Path) -> Result<Place> {
    let mut out = OutputFile::create(path)?;
    let cannot = || format!("cannot write {}", path.display());
    out.write_all(b"frame,ax,ay,az,bx,by,bz,width,colour\n")
        .with_context(cannot)?;
    let mut line = Vec::with_capacity(160);
    let mut frame = 0u32;
    let mut last = Place::START;
    records.visit(Place::START, |place, r| {
        match r {
            Record::FrameStart { frame: k, .. } => {
                frame = *k;
                last = place;
            }
            Record::Segment {
                a,
                b,
                width,
                colour,
            } => {
                line.clear();
                text::int(&mut line, frame);
                for &v in a.iter().chain(b).chain([width]) {
                    line.push(b',');
                    text::fx(&mut line, v, Whole::Bare);
                }
                line.push(b',');
                text::int(&mut line, *colour);
                line.push(b'\n');
                out.write_all(&line).with_context(cannot)?;
            }
            _ => {}
        }
        Ok(())
    })?;
    out.finish()?;
    Ok(last)
}

/// Writes `plant.png`, `plant.obj` and `segments.csv`: the CSV in a pass
/// over every record, then the mesh and the picture's extent in a pass
/// over the last frame, which is drawn back to front from memory or, when
/// larger than [`depth::BUDGET`], from sorted runs spilled into `dir`.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(records: &R, dir: &Path) -> Result<Vec<PathBuf>> {
    let csv_path = dir.join("segments.csv");
    let last = csv(records, &csv_path)?;
    let obj_path = dir.join("plant.obj");
    let mut obj = Obj::new(OutputFile::create(&obj_path)?)
        .with_context(|| format!("cannot write {}", obj_path.display()))?;
    let mut extent = Extent::new();
    let mut sorted = depth::Sort::new(dir);
    last_frame(records, last, |item| {
        extent.include(&item);
        obj.item(&item)
            .with_context(|| format!("cannot write {}", obj_path.display()))?;
        sorted.push(item)
    })?;
    obj.out.finish()?;
    let png_path = dir.join("plant.png");
    png(extent, 1000, |draw| sorted.drain(draw), &png_path)?;
    Ok(vec![png_path, obj_path, csv_path])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palette_ramps_from_bark_to_leaf() {
        assert_eq!(palette(0), [101, 67, 33]);
        assert_eq!(palette(8), [50, 130, 45]);
        assert_eq!(palette(12), palette(400));
    }
}
