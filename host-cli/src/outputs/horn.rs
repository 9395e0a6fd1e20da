//! `ram-horn`, `ram-horn-animation`: one Wavefront OBJ per frame and PNG
//! renders of the compound solid (horn paper, Sec. 7, Figs. 8–10).
//!
//! Each frame's rings become a closed triangle mesh: one group
//! `g module_<i>` per module, two triangles between each pair of
//! consecutive rings, a fan closing the tip (module 1's upper base) and one
//! closing the base (the youngest module's active area). Modules meet on
//! rings with identical coordinates (the kernel emits both). Triangles are
//! counter-clockwise seen from outside (the orientation is read off the
//! first rings, so any outline orientation works).
//!
//! `horn.png` is the last frame, shaded smoothly, with the monthly
//! increments as alternating bands (crowded in winter: the annual rings);
//! `years.png` shows the frames at the end of each year side by side, to
//! the same scale.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen::fx::Real as _;
use morphogen::horn::HornParams;
use morphogen::stream::Record;
use nalgebra::Vector3;
use tiny_skia::{Color, Pixmap};

use super::chart::{Axis, Chart, Series};
use super::driver::{self, Closing, Montage, Products, Rgb};
use super::kinds::{Kinds, MeshFiles, Product};
use super::numbered::FileSeries;
use super::plot::{self, Drawing, Pen, Stroke};
use super::raster::depth_key;
use super::slots::OrderedAnimation;
use super::text::trimmed;
use super::{mesh, normals, picture, raster, tip_bend};
use crate::records::Records;

/// A point in cm.
pub type P3 = Vector3<f64>;

/// One cross-section of a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Ring {
    /// Module (1 = the tip).
    pub module: u16,
    /// Ring index within the module.
    pub ring: u16,
    /// Its points, cm.
    pub points: Vec<P3>,
}

/// One frame of the horn.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Frame {
    /// Frame index.
    pub index: u32,
    /// Global time, years.
    pub years: f64,
    /// The rings, module 1 first.
    pub rings: Vec<Ring>,
}

/// Groups a horn stream's records into frames, one record at a time.
#[derive(Debug, Default)]
pub struct Framer {
    current: Option<Frame>,
    /// Points the current ring still announces.
    expected: usize,
}

impl Framer {
    /// Takes the next record; returns the frame it ends, if any.
    ///
    /// # Errors
    /// When points arrive outside a ring, a ring is short of points, or
    /// frames do not balance.
    pub fn push(&mut self, r: &Record) -> Result<Option<Frame>> {
        match r {
            Record::FrameStart { frame, time } => {
                if self.current.is_some() {
                    bail!("frame {frame} starts before the previous one ended");
                }
                self.current = Some(Frame {
                    index: *frame,
                    years: f64::from_fx(*time),
                    rings: Vec::new(),
                });
            }
            Record::Ring {
                module,
                ring,
                points,
            } => {
                let f = self.current.as_mut().context("a ring outside a frame")?;
                if self.expected != 0 {
                    bail!(
                        "frame {}: a ring is short of {} points",
                        f.index,
                        self.expected
                    );
                }
                self.expected = usize::from(*points);
                f.rings.push(Ring {
                    module: *module,
                    ring: *ring,
                    points: Vec::with_capacity(self.expected),
                });
            }
            Record::Point { p } => {
                let f = self.current.as_mut().context("a point outside a frame")?;
                let ring = f.rings.last_mut().context("a point before any ring")?;
                if self.expected == 0 {
                    bail!("frame {}: more points than the ring announced", f.index);
                }
                ring.points.push(P3::new(
                    f64::from_fx(p[0]),
                    f64::from_fx(p[1]),
                    f64::from_fx(p[2]),
                ));
                self.expected -= 1;
            }
            Record::FrameEnd { frame } => {
                let f = self
                    .current
                    .take()
                    .context("a frame ends that never started")?;
                if f.index != *frame || self.expected != 0 {
                    bail!("frame {frame} ends unbalanced");
                }
                return Ok(Some(f));
            }
            _ => {}
        }
        Ok(None)
    }

    /// Checks that the stream did not end inside a frame.
    ///
    /// # Errors
    /// When it did.
    pub fn finish(&self) -> Result<()> {
        if self.current.is_some() {
            bail!("the stream ends inside a frame");
        }
        Ok(())
    }
}

/// Groups a horn stream's records into frames.
///
/// # Errors
/// When points arrive outside a ring, a ring is short of points, or frames
/// do not balance.
pub fn frames(records: &[Record]) -> Result<Vec<Frame>> {
    let mut framer = Framer::default();
    let mut out = Vec::new();
    for r in records {
        out.extend(framer.push(r)?);
    }
    framer.finish()?;
    Ok(out)
}

/// A triangle by vertex indices, with its month (for the stripes); caps
/// have `None`.
pub type Triangle = ([usize; 3], Option<u32>);

/// A frame as a triangle mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions, cm.
    pub vertices: Vec<P3>,
    /// Per module: the module and its triangles.
    pub groups: Vec<(u16, Vec<Triangle>)>,
}

fn centroid(points: &[P3]) -> P3 {
    let n = points.len().max(1) as f64;
    points.iter().fold(P3::zeros(), |s, p| s + p) / n
}

/// The mesh of `frame`; `rings_per_year` (J) maps ring indices to months.
#[must_use]
pub fn mesh(frame: &Frame, rings_per_year: u32) -> Mesh {
    let mut m = Mesh::default();
    let mut starts = Vec::with_capacity(frame.rings.len());
    for r in &frame.rings {
        starts.push(m.vertices.len());
        m.vertices.extend_from_slice(&r.points);
    }
    // Orientation: is (A₀, A₁, B₀) outward on the first pair of rings?
    let outward = frame
        .rings
        .windows(2)
        .find(|w| w[0].module == w[1].module && w[0].points.len() >= 2)
        .is_none_or(|w| {
            let (a, b) = (&w[0].points, &w[1].points);
            let n = (a[1] - a[0]).cross(&(b[0] - a[0]));
            n.dot(&(a[0] - centroid(a))) > 0.0
        });
    for (k, w) in frame.rings.windows(2).enumerate() {
        if w[0].module != w[1].module || w[0].points.len() != w[1].points.len() {
            continue;
        }
        let month = u32::from(w[0].ring) * 12 / rings_per_year.max(1);
        let (a, b, n) = (starts[k], starts[k + 1], w[0].points.len());
        if m.groups.last().is_none_or(|g| g.0 != w[0].module) {
            m.groups.push((w[0].module, Vec::new()));
        }
        let Some((_, group)) = m.groups.last_mut() else {
            continue;
        };
        for i in 0..n {
            let j = (i + 1) % n;
            let (t1, t2) = if outward {
                ([a + i, a + j, b + i], [a + j, b + j, b + i])
            } else {
                ([a + i, b + i, a + j], [a + j, b + i, b + j])
            };
            group.push((t1, Some(month)));
            group.push((t2, Some(month)));
        }
    }
    // Caps: the tip and the skull end, each a fan from its centroid.
    let last = frame.rings.len();
    let caps = [
        (0usize, 1usize),
        (last.saturating_sub(1), last.saturating_sub(2)),
    ];
    for (cap, neighbour) in caps {
        if last < 2 {
            break;
        }
        let ring = &frame.rings[cap];
        let c = centroid(&ring.points);
        let away = c - centroid(&frame.rings[neighbour].points);
        let centre = m.vertices.len();
        m.vertices.push(c);
        let (s, n) = (starts[cap], ring.points.len());
        let Some(group) = m.groups.iter_mut().find(|g| g.0 == ring.module) else {
            continue;
        };
        for i in 0..n {
            let j = (i + 1) % n;
            let normal = (ring.points[i] - c).cross(&(ring.points[j] - c));
            let tri = if normal.dot(&away) > 0.0 {
                [centre, s + i, s + j]
            } else {
                [centre, s + j, s + i]
            };
            group.1.push((tri, None));
        }
    }
    m
}

/// The OBJ and glTF mesh of a frame (its geometry `m`): one group
/// `module_<i>` per module, vertex colours the horn's with the picture's
/// monthly bands (so the annual rings show), in the material `horn`,
/// headed by `title`.
///
/// # Errors
/// Never for a mesh of [`mesh()`].
pub fn solid(frame: &Frame, m: &Mesh, title: &str, rings_per_year: u32) -> Result<mesh::Mesh> {
    let mut out = mesh::Mesh::new();
    out.comment(title);
    out.comment("units: cm; skull frame (module k grows along +x)");
    let shade = |k: f64| HORN.map(|v| (v * k).round().clamp(0.0, 255.0) as u8);
    let mut vertices = m.vertices.iter();
    for r in &frame.rings {
        let month = u32::from(r.ring) * 12 / rings_per_year.max(1);
        let rgb = shade(if month % 2 == 1 { 0.86 } else { 1.0 });
        for v in vertices.by_ref().take(r.points.len()) {
            out.push_coloured_vertex((*v).into(), rgb)?;
        }
    }
    for v in vertices {
        out.push_coloured_vertex((*v).into(), shade(0.8))?;
    }
    let horn = out.material("horn", shade(1.0))?;
    for (module, tris) in &m.groups {
        let g = out.group(Some(&format!("module_{module}")), Some(horn))?;
        for (t, _) in tris {
            out.push_face(g, &t.map(|k| k as u32))?;
        }
    }
    Ok(out)
}

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

const HORN: [f64; 3] = [222.0, 204.0, 168.0];

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "horn.mtl";
fn background() -> Color {
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
fn drawing(frame: &Frame, j: u32) -> Drawing {
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

/// Rows of `horn.png`'s drawing a band holds ([`save_picture`]): even, so
/// halving pairs the rows the whole drawing would pair.
const BAND: u32 = 150;

/// Saves `frame` alone as a `width × height` picture at `path`, fitted to
/// a drawing of twice that size, drawn [`BAND`] rows at a time on one
/// canvas and halved band by band: the pixels of the whole drawing, whose
/// canvas (17 MB for `horn.png`) is never held.
fn save_picture(frame: &Frame, j: u32, (width, height): (u32, u32), path: &Path) -> Result<()> {
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
    picture::save_rgb(width, height, &rgb, path)
}

/// Frames drawn to one scale, that of the full-grown horn, the skull end
/// of every horn at the same place in its cell.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Fit {
    cell: u32,
    view: View,
    /// The full-grown horn's box: its corner is where the skull origin sits.
    corner: [f64; 2],
    margin: f64,
    scale: f64,
}

impl Fit {
    /// Cells of `cell` pixels (drawn at that size, saved at half) to the
    /// scale of `last` (none: a unit box).
    fn new(last: Option<&Frame>, cell: u32) -> Fit {
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
    fn draw(&self, pixmap: &mut Pixmap, frame: &Frame, j: u32) {
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

/// A frame's label: its time in years.
fn label(frame: &Frame) -> String {
    format!("year {}", trimmed(frame.years, 2))
}

/// The length of a frame's centre line (through its rings' centres, cm)
/// and its bend: the total turning of that line, degrees.
fn centre_line(frame: &Frame) -> (f64, f64) {
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

/// A horn run's products ([`driver::write`]): `frame_NNN.obj` and
/// `model.glb`; `years.png`, the frames at the end of each year to the
/// scale of the last of them; `animation.png`, every frame (or 60 spread
/// evenly) to the last frame's scale, the skull end fixed, a frame both
/// show drawn once; `horn.png`, the last frame alone; `bend.png`/`.svg`,
/// the centre line's length and total turning over time; and
/// `e1-bend.png`/`.svg`, the paper's Fig. 11 from the parameters
/// ([`super::tip_bend`]).
struct Horn<'a> {
    params: &'a HornParams<'a>,
    /// Rings per module (J), which map ring indices to months.
    j: u32,
    /// Frames seen, the positions of those that end a year, and the
    /// last of those.
    count: usize,
    years: Vec<usize>,
    last_year: Option<Frame>,
    last: Option<Frame>,
    /// Years, centre-line length (cm) and bend (degrees) of every frame.
    lines: Vec<(f64, f64, f64)>,
    /// The scales of `years.png` and of the animation, once surveyed.
    fits: Option<(Fit, Fit)>,
}

impl Horn<'_> {
    /// The scales of `years.png` and of the animation.
    fn fits(&self) -> Result<(Fit, Fit)> {
        self.fits.context("the horn's frames are not surveyed")
    }

    /// `frame` drawn to `fit`, halved.
    fn drawn(&self, fit: &Fit, frame: &Frame) -> Result<Rgb> {
        let mut p = Pixmap::new(fit.cell, fit.cell).context("picture size must be positive")?;
        p.fill(background());
        fit.draw(&mut p, frame, self.j);
        Rgb::halved(&p)
    }
}

impl Products for Horn<'_> {
    type Frame = Frame;
    type Framer = Framer;
    type Picture = Rgb;
    type Measure = ();

    fn push(framer: &mut Framer, record: &Record) -> Result<Option<Frame>> {
        framer.push(record)
    }

    fn end(framer: &Framer) -> Result<()> {
        framer.finish()
    }

    fn survey(&mut self, frame: Frame) -> Result<()> {
        let (length, bend) = centre_line(&frame);
        self.lines.push((frame.years, length, bend));
        if is_year_end(&frame) {
            self.years.push(self.count);
            self.last_year = Some(frame.clone());
        }
        self.count += 1;
        self.last = Some(frame);
        Ok(())
    }

    fn surveyed(&mut self, _framer: Framer) {
        let year_fit = Fit::new(self.last_year.as_ref(), 800);
        self.fits = Some((year_fit, Fit::new(self.last.as_ref(), 800)));
    }

    fn index(frame: &Frame) -> i64 {
        i64::from(frame.index)
    }

    fn mesh_files(&self) -> Option<MeshFiles> {
        Some(MeshFiles {
            library: LIBRARY,
            scene: "horn".into(),
            metres: 0.01,
        })
    }

    fn mesh(&self, frame: &Frame) -> Result<Option<mesh::Mesh>> {
        let title = format!(
            "morphogen horn, frame {} at t = {} years",
            frame.index, frame.years
        );
        solid(frame, &mesh(frame, self.j), &title, self.j).map(Some)
    }

    fn stills(&self) -> Option<FileSeries> {
        None
    }

    fn animation(&self, path: &Path, frames: usize) -> Result<Option<OrderedAnimation>> {
        OrderedAnimation::new(path, 400, 400, frames).map(Some)
    }
    fn picture(&self, frame: &Frame) -> Result<Rgb> {
        self.drawn(&self.fits()?.1, frame)
    }

    fn label(&self, frame: &Frame) -> String {
        label(frame)
    }

    fn montage(&self) -> Option<Montage> {
        self.last.as_ref()?;
        let c = background().to_color_u8();
        Some(Montage {
            name: "years",
            frames: self.years.clone(),
            tile: (400, 400),
            columns: self.years.len().clamp(1, 4) as u32,
            background: [c.red(), c.green(), c.blue()],
        })
    }

    fn tile(&self, frame: &Frame, _n: usize) -> Result<Option<Rgb>> {
        let (year_fit, anim_fit) = self.fits()?;
        if year_fit == anim_fit {
            return Ok(None);
        }
        self.drawn(&year_fit, frame).map(Some)
    }

    fn plot(&self) -> Result<Option<Drawing>> {
        Ok(self.last.as_ref().map(|last| drawing(last, self.j)))
    }

    fn close(self, dir: &Path, kinds: Kinds, _run: Closing<()>) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        let Some(last) = self.last else {
            return Ok(written);
        };
        let save = |path: &Path| save_picture(&last, self.j, (1200, 900), path);
        written.extend(kinds.picture(Product::Picture, dir, "horn", save)?);
        let lines = &self.lines;
        if lines.len() > 1 {
            let chart = Chart::new(
                "Horn centre line",
                Axis::new("time", "years"),
                Axis::new("bend (total turning)", "degrees"),
            )
            .with_y2(Axis::new("length", "cm"))
            .with_series(Series::line(
                "bend",
                lines.iter().map(|&(t, _, b)| (t, b)).collect(),
            ))
            .with_series(
                Series::line("length", lines.iter().map(|&(t, l, _)| (t, l)).collect()).on_right(),
            );
            written.extend(kinds.chart(&chart, dir, "bend", (900, 500))?);
        }
        if kinds.wants(Product::Chart) {
            let chart = tip_bend::chart(&tip_bend::samples(self.params)?);
            written.extend(kinds.chart(&chart, dir, "e1-bend", (900, 500))?);
        }
        Ok(written)
    }
}

/// Writes (those of `kinds`) a horn run's files (`Horn`).
///
/// # Errors
/// A malformed stream, unreadable records, or a file that cannot be
/// written.
pub fn write<R: Records + ?Sized>(
    records: &R,
    dir: &Path,
    params: &HornParams<'_>,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let horn = Horn {
        params,
        j: u32::from(params.rings_per_module),
        count: 0,
        years: Vec::new(),
        last_year: None,
        last: None,
        lines: Vec::new(),
        fits: None,
    };
    driver::write(horn, records, dir, kinds)
}

/// Whether `frame` is at the end of a year (shown in `years.png`).
fn is_year_end(frame: &Frame) -> bool {
    (frame.years - frame.years.round()).abs() < 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Collect(Vec<Record>);

    impl morphogen::stream::Sink for Collect {
        fn record(&mut self, r: &Record) -> Result<(), morphogen::stream::SinkError> {
            self.0.push(r.clone());
            Ok(())
        }
    }

    fn records(name: &str) -> Vec<Record> {
        let scenario = morphogen_scenario::builtin(name).unwrap();
        let mut sink = Collect(Vec::new());
        scenario
            .with_preset(|p| morphogen_scenario::run::run(p, 0, &mut sink, &mut |_| {}))
            .unwrap();
        sink.0
    }

    #[test]
    fn meshes_are_closed_and_wound_outwards() {
        let frames = frames(&records("ram-horn")).unwrap();
        assert_eq!(frames.len(), 16);
        for f in &frames {
            let m = mesh(f, 24);
            let modules = f.rings.last().unwrap().module;
            assert_eq!(m.groups.len(), usize::from(modules));
            // The signed volume of a closed outward mesh is positive, and
            // every side triangle faces away from its ring's centre.
            let mut volume = 0.0;
            for (_, tris) in &m.groups {
                for (t, _) in tris {
                    let (a, b, c) = (m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
                    volume += a.dot(&b.cross(&c)) / 6.0;
                }
            }
            assert!(volume > 100.0, "frame {}: volume {volume} cm³", f.index);
            let (a, b) = (&f.rings[0].points, &f.rings[1].points);
            let n = (m.vertices[m.groups[0].1[0].0[1]] - a[0])
                .cross(&(m.vertices[m.groups[0].1[0].0[2]] - a[0]));
            assert!(n.dot(&(a[0] - centroid(a))) > 0.0 || b.is_empty());
        }
        let mut text = Vec::new();
        let f = frames.last().unwrap();
        let solid = solid(f, &mesh(f, 24), "t", 24).unwrap();
        mesh::obj(&solid, mesh::ObjStyle::PLAIN, None, &mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        for i in 1..=8 {
            assert!(text.contains(&format!("\ng module_{i}\n")));
        }
    }

    #[test]
    fn animation_frames_taken_from_the_montage_are_those_drawn_alone() {
        // ram-horn's 16 frames are half-yearly: with years.png, the 8 at a
        // year's end are its tiles, the others drawn; alone, all drawn.
        let records = records("ram-horn");
        let scenario = morphogen_scenario::builtin("ram-horn").unwrap();
        scenario.with_preset(|p| {
            let morphogen::preset::Model::Horn(params) = p.model else {
                unreachable!("ram-horn is a horn")
            };
            let (both, alone) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
            let kinds = |list| Kinds::parse(list).unwrap();
            write(&records, both.path(), params, kinds("png,anim")).unwrap();
            write(&records, alone.path(), params, kinds("anim")).unwrap();
            assert!(both.path().join("years.png").exists());
            assert!(!alone.path().join("years.png").exists());
            let read = |dir: &Path| std::fs::read(dir.join("animation.png")).unwrap();
            assert!(read(both.path()) == read(alone.path()));
        });
    }
}
