//! How a horn frame is drawn: the camera, the shaded solid with its
//! monthly bands, the pen strokes, and the fit of several frames to one
//! scale (horn paper, Figs. 9–10).

use anyhow::{Context, Result};
use tiny_skia::{Color, Pixmap};

use super::frames::{Frame, P3, Ring};
use super::shape::{HORN, Mesh, Triangle, centroid, mesh};
use crate::outputs::driver::Rgb;
use crate::outputs::plot::{self, Drawing, Pen, Stroke};
use crate::outputs::raster::depth_key;
use crate::outputs::{normals, picture, raster};

/// A view: rotation of the skull frame into screen axes (x right, y up,
/// z towards the viewer).
#[derive(Debug, Clone, Copy, PartialEq)]
struct View {
    rows: [P3; 3],
}

impl View {
    /// Turned by `yaw` about the skull's y axis, then tilted by `pitch`
    /// about the screen's x axis (radians).
    fn new(yaw: f64, pitch: f64, roll: f64) -> View {
        let (sy, cy) = yaw.sin_cos();
        let (sp, cp) = pitch.sin_cos();
        let (sr, cr) = roll.sin_cos();
        let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
        let rx = [[1.0, 0.0, 0.0], [0.0, cp, -sp], [0.0, sp, cp]];
        let rz = [[cr, -sr, 0.0], [sr, cr, 0.0], [0.0, 0.0, 1.0]];
        let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
            let mut m = [[0.0; 3]; 3];
            for (i, row) in m.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
                }
            }
            m
        };
        View {
            rows: mul(rz, mul(rx, ry)).map(P3::from),
        }
    }

    fn apply(&self, p: P3) -> P3 {
        P3::new(
            self.rows[0].dot(&p),
            self.rows[1].dot(&p),
            self.rows[2].dot(&p),
        )
    }
}

/// The camera used for every horn picture.
fn camera() -> View {
    View::new(-0.35, 0.45, -2.4)
}

/// Screen-space bounds (min x, min y, max x, max y) of a frame.
fn bounds(view: &View, frame: &Frame) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in frame.rings.iter().flat_map(|r| &r.points) {
        let q = view.apply(*p);
        b = [
            b[0].min(q[0]),
            b[1].min(q[1]),
            b[2].max(q[0]),
            b[3].max(q[1]),
        ];
    }
    b
}

pub(super) fn background() -> Color {
    Color::from_rgba8(250, 249, 246, 255)
}

/// Draws `mesh` into `pixmap`, mapping screen cm to pixels by `scale`
/// with `origin` (screen cm) at `at` (pixels).
fn draw(pixmap: &mut Pixmap, mesh: &Mesh, view: &View, origin: [f64; 2], at: [f32; 2], scale: f64) {
    for (p, rgb) in shaded(mesh, view, origin, at, scale) {
        raster::smooth_triangle(pixmap, p, rgb);
    }
}

/// A triangle to draw: its corners in pixels and their colours.
type Shaded = ([[f32; 2]; 3], [[u8; 3]; 3]);

/// The triangles of `mesh` facing the camera, back to front, in pixels
/// (screen cm mapped by `scale`, `origin` at `at`), each with the colour
/// of its corners: its band's, Lambert-shaded by the normal at the corner
/// ([`normals::corner_normals`]), so the horn shades smoothly round and
/// along, and its bands and the tip's cap keep their edges.
fn shaded(mesh: &Mesh, view: &View, origin: [f64; 2], at: [f32; 2], scale: f64) -> Vec<Shaded> {
    let light = normals::unit(P3::new(-0.45, 0.6, 0.66));
    let screen: Vec<P3> = mesh.vertices.iter().map(|&p| view.apply(p)).collect();
    let all: Vec<&Triangle> = mesh.groups.iter().flat_map(|g| g.1.iter()).collect();
    let indices: Vec<[u32; 3]> = all.iter().map(|(t, _)| t.map(|k| k as u32)).collect();
    let corners = normals::corner_normals(&screen, &indices);
    let tris: Vec<(f64, usize)> = all
        .iter()
        .enumerate()
        .filter_map(|(i, &&(t, _))| {
            let (a, b, c) = (screen[t[0]], screen[t[1]], screen[t[2]]);
            let n = (b - a).cross(&(c - a));
            // Back faces of the closed surface are hidden.
            (n[2] > 0.0).then(|| ((a[2] + b[2] + c[2]) / 3.0, i))
        })
        .collect();
    // Back to front: the stable sort by depth, of keys and positions.
    let mut order: Vec<(i64, usize)> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| (depth_key(t.0), i))
        .collect();
    order.sort_unstable();
    let px = |p: P3| {
        [
            at[0] + ((p[0] - origin[0]) * scale) as f32,
            at[1] - ((p[1] - origin[1]) * scale) as f32,
        ]
    };
    // No anti-aliasing per triangle (it would leave seams between them);
    // pictures are drawn at twice their size and averaged down instead.
    order
        .into_iter()
        .map(|(_, i)| {
            let k = tris[i].1;
            let (t, month) = *all[k];
            let band = match month {
                Some(m) if m % 2 == 1 => 0.86,
                Some(_) => 1.0,
                None => 0.8,
            };
            let rgb = corners[k].map(|n| {
                let lambert = P3::from(n).dot(&light).max(0.0);
                let k = (0.35 + 0.65 * lambert) * band;
                HORN.map(|v| (v * k).clamp(0.0, 255.0) as u8)
            });
            (t.map(|v| px(screen[v])), rgb)
        })
        .collect()
}

/// The last frame's plot in `horn.png`'s view: its outline (the
/// mesh's [`plot::silhouette`]) and its growth rings, the rings where
/// one monthly band of `horn.png` meets the next, each drawn where it
/// faces the viewer (its points turned towards the viewer from the
/// ring's centre).
pub(super) fn drawing(frame: &Frame, j: u32) -> Drawing {
    let view = camera();
    let m = mesh(frame, j);
    let screen: Vec<[f64; 3]> = m.vertices.iter().map(|&p| view.apply(p).into()).collect();
    let triangles: Vec<[u32; 3]> = m
        .groups
        .iter()
        .flat_map(|(_, tris)| tris.iter().map(|(t, _)| t.map(|k| k as u32)))
        .collect();
    let month = |r: &Ring| u32::from(r.ring) * 12 / j.max(1);
    let mut rings = Vec::new();
    for (k, ring) in frame.rings.iter().enumerate() {
        let before = k.checked_sub(1).map(|b| &frame.rings[b]);
        let boundary = before.is_none_or(|b| month(b) != month(ring) || b.module != ring.module);
        if !boundary || before.is_some_and(|b| b.points == ring.points) {
            continue;
        }
        rings.extend(facing_arcs(ring, &view));
    }
    let pen = |name: &str, colour, strokes| Pen {
        name: name.into(),
        colour,
        strokes,
    };
    Drawing {
        pens: vec![
            pen(
                "outline",
                [40, 30, 20],
                plot::silhouette(&screen, &triangles),
            ),
            pen("rings", [160, 110, 50], rings),
        ],
    }
}

/// The arcs of `ring` that face the viewer, on the screen, each ending
/// where the ring turns away (between its points): a whole ring facing
/// it is one closed stroke.
fn facing_arcs(ring: &Ring, view: &View) -> Vec<Stroke> {
    let c = centroid(&ring.points);
    // How far each point's side faces the viewer: its depth from the centre.
    let depth: Vec<f64> = ring.points.iter().map(|&p| view.apply(p - c)[2]).collect();
    let at = |i: usize| {
        let q = view.apply(ring.points[i]);
        [q[0], q[1]]
    };
    let n = ring.points.len();
    let Some(start) = (0..n).find(|&i| depth[i] <= 0.0) else {
        let mut whole = Stroke::open((0..n).map(at).collect());
        whole.closed = true;
        return vec![whole];
    };
    // From a point facing away, round the ring once.
    let mut arcs = Vec::new();
    let mut arc: Vec<[f64; 2]> = Vec::new();
    let mut before = start;
    for i in (1..=n).map(|k| (start + k) % n) {
        let (d0, d1) = (depth[before], depth[i]);
        if (d0 > 0.0) != (d1 > 0.0) {
            let t = d0 / (d0 - d1);
            let (p, q) = (at(before), at(i));
            arc.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
        if d1 > 0.0 {
            arc.push(at(i));
        } else if arc.len() > 1 {
            arcs.push(Stroke::open(std::mem::take(&mut arc)));
        } else {
            arc.clear();
        }
        before = i;
    }
    arcs
}

/// Rows of `horn.png`'s drawing a band holds ([`whole_picture`]): even, so
/// halving pairs the rows the whole drawing would pair.
const BAND: u32 = 150;

/// `frame` alone as a `width × height` picture, fitted to a drawing of
/// twice that size, drawn [`BAND`] rows at a time on one canvas and
/// halved band by band: the pixels of the whole drawing, whose canvas
/// (17 MB for `horn.png`) is never held.
pub(super) fn whole_picture(frame: &Frame, j: u32, (width, height): (u32, u32)) -> Result<Rgb> {
    let (w, h) = (2 * width, 2 * height);
    let view = camera();
    let b = bounds(&view, frame);
    let margin = 0.06 * f64::from(w.min(h));
    let scale = ((f64::from(w) - 2.0 * margin) / (b[2] - b[0]).max(1e-6))
        .min((f64::from(h) - 2.0 * margin) / (b[3] - b[1]).max(1e-6));
    let used = [(b[2] - b[0]) * scale, (b[3] - b[1]) * scale];
    let at = [
        ((f64::from(w) - used[0]) / 2.0) as f32,
        (f64::from(h) - (f64::from(h) - used[1]) / 2.0) as f32,
    ];
    let mut canvas = Pixmap::new(w, BAND.min(h)).context("picture size must be positive")?;
    let tris = shaded(&mesh(frame, j), &view, [b[0], b[1]], at, scale);
    // Each band's triangles, back to front (h > 0: at least one band).
    let mut bands = vec![Vec::new(); h.div_ceil(BAND) as usize];
    for (p, colour) in tris {
        let rows = raster::rows(p);
        let last = (rows.end() / BAND).min(bands.len() as u32 - 1);
        for band in rows.start() / BAND..=last {
            bands[band as usize].push((p, colour));
        }
    }
    let mut rgb = vec![0; 3 * width as usize * height as usize];
    let band_bytes = 3 * width as usize * BAND as usize / 2;
    let rows = rgb.chunks_mut(band_bytes);
    for ((top, tris), rgb) in (0..h).step_by(BAND as usize).zip(bands).zip(rows) {
        if h - top < canvas.height() {
            canvas = Pixmap::new(w, h - top).context("picture size must be positive")?;
        }
        canvas.fill(background());
        let first = u16::try_from(top).context("picture too tall to draw in bands")?;
        for (p, colour) in tris {
            raster::smooth_triangle_in_band(&mut canvas, first, p, colour);
        }
        picture::half_rgb_into(&canvas, rgb)?;
    }
    Ok(Rgb {
        width,
        height,
        bytes: rgb,
    })
}

/// Frames drawn to one scale, that of the full-grown horn, the skull end
/// of every horn at the same place in its cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Fit {
    pub(super) cell: u32,
    view: View,
    /// The full-grown horn's box: its corner is where the skull origin sits.
    corner: [f64; 2],
    margin: f64,
    scale: f64,
}

impl Fit {
    /// Cells of `cell` pixels (drawn at that size, saved at half) to the
    /// scale of `last` (none: a unit box).
    pub(super) fn new(last: Option<&Frame>, cell: u32) -> Fit {
        let view = camera();
        let b = last.map_or([0.0, 0.0, 1.0, 1.0], |last| bounds(&view, last));
        let margin = 0.05 * f64::from(cell);
        let scale = ((f64::from(cell) - 2.0 * margin) / (b[2] - b[0]).max(1e-6))
            .min((f64::from(cell) - 2.0 * margin) / (b[3] - b[1]).max(1e-6));
        Fit {
            cell,
            view,
            corner: [b[0], b[1]],
            margin,
            scale,
        }
    }

    /// Draws `frame` into `pixmap`, a cell.
    pub(super) fn draw(&self, pixmap: &mut Pixmap, frame: &Frame, j: u32) {
        let at = [
            self.margin as f32,
            (f64::from(self.cell) - self.margin) as f32,
        ];
        draw(
            pixmap,
            &mesh(frame, j),
            &self.view,
            self.corner,
            at,
            self.scale,
        );
    }
}

/// The length of a frame's centre line (through its rings' centres, cm)
/// and its bend: the total turning of that line, degrees.
pub(super) fn centre_line(frame: &Frame) -> (f64, f64) {
    let centres: Vec<P3> = frame.rings.iter().map(|r| centroid(&r.points)).collect();
    let steps: Vec<P3> = centres
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.norm_squared() > 1e-12)
        .collect();
    let length = steps.iter().map(P3::norm).sum();
    let bend = steps
        .windows(2)
        .map(|w| {
            let c = w[0].dot(&w[1]) / (w[0].norm_squared() * w[1].norm_squared()).sqrt();
            c.clamp(-1.0, 1.0).acos().to_degrees()
        })
        .sum();
    (length, bend)
}
