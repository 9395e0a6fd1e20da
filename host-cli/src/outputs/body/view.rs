//! How a body frame (or a wrapped bone) is drawn: seen from the side,
//! shaded flat or smooth, on the ground, fitted to the frames' extent;
//! and its outline as pen strokes.

use anyhow::Result;
use nalgebra::Vector3;
use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::frames::Frame;
use crate::outputs::picture::Canvases;
use crate::outputs::plot::{self, Drawing, Pen};
use crate::outputs::{normals, raster};

/// Pictures are drawn at this many times their size, then averaged down
/// (anti-aliasing for the triangles of [`raster`]).
pub(super) const OVERSAMPLE: f32 = 2.0;

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
pub(super) fn colour(title: &str) -> [f32; 3] {
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
pub(super) fn ground(pixmap: &mut Pixmap, y: f32) {
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
pub(super) fn side_view(
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
