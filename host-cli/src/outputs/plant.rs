//! L-system plants (`abop-*` presets and `run --grammar FILE`): a PNG
//! (orthographic view along −z onto the x–y plane, y up, segments with
//! their widths, polygons filled, drawn back to front), an OBJ (segments
//! as square prisms of side `width`, polygons as faces; streamed a piece
//! at a time through [`mesh::obj_part`]), `model.glb` (the same mesh in
//! the palette's colours, for a last frame of at most
//! [`GLB_MAX_VERTICES`] vertices), a CSV of every segment and, for a
//! grammar that emits several frames (`animate = 1`), `animation.png` of
//! its derivation steps (every frame, or 60 spread evenly), and with
//! `--only plot` `plot.svg` (the last frame's lines, a layer per colour).
//! Pictures, meshes and the plot show the last frame; the CSV has them
//! all.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::stream::Record;
use morphogen_stream_text::text::{self, Whole};
use tiny_skia::{Color, Pixmap};

use super::driver::{Rgb, Still};
use super::fill::Filler;
use super::kinds::{Kinds, PictureSeries, Product, Sequence, StreamedMesh};
use super::mesh::{self, GroupId, Numbers, ObjStyle};
use super::plot::{Drawing, Pen, Stroke};
use super::slots::animation_frames;
use crate::atomic::OutputFile;
use crate::records::{Place, Records};

mod depth;

fn p3(p: &[Fx; 3]) -> [f64; 3] {
    [f64::from_fx(p[0]), f64::from_fx(p[1]), f64::from_fx(p[2])]
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
    fn colour(&self) -> u16 {
        match self {
            Item::Segment { colour, .. } | Item::Polygon { colour, .. } => *colour,
        }
    }

    fn depth(&self) -> f64 {
        match self {
            Item::Segment { a, b, .. } => (a[2] + b[2]) / 2.0,
            Item::Polygon { points, .. } => {
                points.iter().map(|p| p[2]).sum::<f64>() / points.len().max(1) as f64
            }
        }
    }
}

/// The items of the frame read from `start` (the place of its frame
/// start, or the first record when there is none) to its end: each
/// handed to `each` in stream order. A polygon takes the points among the
/// records that follow it, as many records as it has vertices.
fn frame_items<R: Records + ?Sized>(
    records: &R,
    start: Place,
    mut each: impl FnMut(Item) -> Result<()>,
) -> Result<()> {
    // The polygon being filled: records still to take, its points, colour.
    let mut open: Option<(usize, Vec<[f64; 3]>, u16)> = None;
    records.visit_while(start, |_, r| {
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
            return Ok(true);
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
                width: f64::from_fx(*width),
                colour: *colour,
            })?,
            Record::Polygon { vertices, colour } if *vertices == 0 => each(Item::Polygon {
                points: Vec::new(),
                colour: *colour,
            })?,
            Record::Polygon { vertices, colour } => {
                open = Some((usize::from(*vertices), Vec::new(), *colour));
            }
            Record::FrameEnd { .. } => return Ok(false),
            _ => {}
        }
        Ok(true)
    })?;
    // A polygon cut short by the end of the stream keeps the points it has.
    match open {
        Some((_, points, colour)) => each(Item::Polygon { points, colour }),
        None => Ok(()),
    }
}

/// The largest colour index with a colour of its own; beyond it,
/// [`palette`] repeats this one.
pub const LAST_COLOUR: u16 = 12;

/// The material of colour index `i` in `mesh` (`colour_<i>`, the indices
/// beyond [`LAST_COLOUR`] sharing its material).
fn material(mesh: &mut mesh::Mesh, i: u16) -> Result<mesh::MaterialId> {
    let i = i.min(LAST_COLOUR);
    Ok(mesh.material(&format!("colour_{i}"), palette(i))?)
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
    let x = f64::from(i.min(LAST_COLOUR));
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

/// Draws the items `back_to_front` hands out (in painter's order) into a
/// picture `size` pixels across its longer side, framing `extent`.
fn render(
    extent: Extent,
    size: u32,
    back_to_front: impl FnOnce(&mut dyn FnMut(&Item)) -> Result<()>,
) -> Result<Pixmap> {
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
        [
            (margin + (p[0] - lo[0]) * scale) as f32,
            (margin + (hi[1] - p[1]) * scale) as f32,
        ]
    };
    let mut filler = Filler::default();
    back_to_front(&mut |item| match item {
        Item::Segment {
            a,
            b,
            width,
            colour,
        } => {
            let width = ((width * scale) as f32).max(0.6);
            filler.segment(&mut pixmap, px(a), px(b), width, palette(*colour));
        }
        Item::Polygon { points, colour } => {
            let points: Vec<[f32; 2]> = points.iter().map(px).collect();
            filler.polygon(&mut pixmap, &points, palette(*colour));
        }
    })?;
    Ok(pixmap)
}

/// A plant's strokes for `plot.svg`, seen as `plant.png` sees it (x–y,
/// y up): a pen per colour index, a segment continuing the stroke its
/// colour drew last when it starts where that stroke ends (the turtle's
/// unbroken lines), a polygon of three or more points a closed stroke.
#[derive(Debug, Default)]
struct Strokes {
    by_colour: BTreeMap<u16, Vec<Stroke>>,
}

impl Strokes {
    /// Adds the next item in stream order.
    fn push(&mut self, item: &Item) {
        let colour = item.colour().min(LAST_COLOUR);
        let strokes = self.by_colour.entry(colour).or_default();
        match item {
            Item::Segment { a, b, .. } => {
                let (a, b) = ([a[0], a[1]], [b[0], b[1]]);
                match strokes.last_mut() {
                    Some(s) if !s.closed && s.points.last() == Some(&a) => s.points.push(b),
                    _ => strokes.push(Stroke::open(vec![a, b])),
                }
            }
            Item::Polygon { points, .. } if points.len() >= 3 => strokes.push(Stroke {
                points: points.iter().map(|p| [p[0], p[1]]).collect(),
                closed: true,
            }),
            Item::Polygon { .. } => {}
        }
    }

    /// The drawing: a pen per colour index, in its palette colour.
    fn drawing(self) -> Drawing {
        let pens = self.by_colour.into_iter().map(|(colour, strokes)| Pen {
            name: format!("colour {colour}"),
            colour: palette(colour),
            strokes,
        });
        Drawing {
            pens: pens.collect(),
        }
    }
}

/// The most vertices of a plant's `model.glb` (its last frame, held whole
/// while the file is built): a larger plant gets none, so the memory of
/// drawing it stays bounded by its pictures.
pub const GLB_MAX_VERTICES: usize = 1 << 16;

/// How the plant OBJ prints numbers: in full, without normals.
const PLANT_OBJ: ObjStyle = ObjStyle {
    numbers: Numbers::Exact,
    normals: false,
    vertex_colours: false,
};

/// Adds `item` to `group` of `mesh` (a segment as a square prism, a polygon of 3 or
/// more points as a face) in the palette's colour when `coloured`.
fn add(mesh: &mut mesh::Mesh, group: GroupId, item: &Item, coloured: bool) -> Result<()> {
    match item {
        Item::Segment {
            a,
            b,
            width,
            colour,
        } => {
            mesh.push_square_prism(group, [*a, *b], *width, coloured.then(|| palette(*colour)))?;
        }
        Item::Polygon { points, colour } => {
            if points.len() < 3 {
                return Ok(());
            }
            let mut corners = Vec::with_capacity(points.len());
            for p in points {
                corners.push(if coloured {
                    mesh.push_coloured_vertex(*p, palette(*colour))?
                } else {
                    mesh.push_vertex(*p)?
                });
            }
            mesh.push_face(group, &corners)?;
        }
    }
    Ok(())
}

/// The frame starts of a plant stream (with each frame's index) and the
/// extent of all its segments.
struct Frames {
    starts: Vec<(Place, u32)>,
    extent: Extent,
}

/// Reads every record once: writes the CSV of every segment of every
/// frame to `path` (when given) and finds the frames.
fn csv<R: Records + ?Sized>(records: &R, path: Option<&Path>) -> Result<Frames> {
    let mut out = path.map(OutputFile::create).transpose()?;
    let cannot = || {
        format!(
            "cannot write {}",
            path.map_or(Path::new(""), |p| p).display()
        )
    };
    if let Some(out) = &mut out {
        out.write_all(b"frame,ax,ay,az,bx,by,bz,width,colour\n")
            .with_context(cannot)?;
    }
    let mut line = Vec::with_capacity(160);
    let mut frame = 0u32;
    let mut frames = Frames {
        starts: Vec::new(),
        extent: Extent::new(),
    };
    records.visit(Place::START, |place, r| {
        match r {
            Record::FrameStart { frame: k, .. } => {
                frame = *k;
                frames.starts.push((place, *k));
            }
            Record::Segment {
                a,
                b,
                width,
                colour,
            } => {
                frames.extent.include(&Item::Segment {
                    a: p3(a),
                    b: p3(b),
                    width: 0.0,
                    colour: 0,
                });
                let Some(out) = &mut out else {
                    return Ok(());
                };
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
    if let Some(out) = out {
        out.finish()?;
    }
    Ok(frames)
}

/// Writes (those of `kinds`) `plant.png`, `plant.obj`, `model.glb`,
/// `segments.csv`, `plot.svg` and `animation.png`: the CSV in a pass over
/// every record, then the mesh, the plot's strokes (held in memory) and
/// the picture's extent in a pass over the last frame, which is drawn
/// back to front from memory or, when larger than a budget of 1 MiB, from
/// sorted runs spilled into `dir`; then each animated frame the same way.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(records: &R, dir: &Path, kinds: Kinds) -> Result<Vec<PathBuf>> {
    let mut frames = None;
    let tables = kinds.table(dir, "segments", |path| {
        frames = Some(csv(records, Some(path))?);
        Ok(())
    })?;
    let frames = match frames {
        Some(frames) => frames,
        None => csv(records, None)?,
    };
    let last = frames.starts.last().map_or(Place::START, |s| s.0);
    // Every colour's material, so that the OBJ can stream.
    let mut colours = mesh::Mesh::new();
    for i in 0..=LAST_COLOUR {
        material(&mut colours, i)?;
    }
    let streamed = StreamedMesh {
        stem: "plant",
        what: "the plant's last frame",
        comment: "morphogen L-system plant: segments as square prisms, polygons as faces",
        materials: &colours,
        style: PLANT_OBJ,
        max_vertices: GLB_MAX_VERTICES,
    };
    let mut meshes = kinds.mesh_streams(dir, &streamed)?;
    let mut extent = Extent::new();
    let mut sorted = kinds.wants(Product::Picture).then(|| depth::Sort::new(dir));
    let mut strokes = kinds.wants(Product::Drawing).then(Strokes::default);
    frame_items(records, last, |item| {
        extent.include(&item);
        if let Some(strokes) = &mut strokes {
            strokes.push(&item);
        }
        if !meshes.is_empty() {
            let mut piece = mesh::Mesh::new();
            let colour = material(&mut piece, item.colour())?;
            let group = piece.group(None, Some(colour))?;
            add(&mut piece, group, &item, true)?;
            for m in &mut meshes {
                m.piece(&piece)?;
            }
        }
        match &mut sorted {
            Some(sorted) => sorted.push(item),
            None => Ok(()),
        }
    })?;
    let mut written = Vec::new();
    if let Some(sorted) = sorted {
        let drawn = Rgb::opaque(&render(extent, 1000, |draw| sorted.drain(draw))?);
        written.extend(kinds.picture(Product::Picture, &drawn.pixels(), dir, "plant")?);
    }
    for m in meshes {
        written.extend(m.finish()?);
    }
    written.extend(tables);
    if let Some(strokes) = strokes {
        written.extend(kinds.drawing(&strokes.drawing(), dir)?);
    }
    if kinds.wants(Product::Animation) && frames.starts.len() > 1 {
        written.extend(animate(records, dir, &frames, extent, kinds)?);
    }
    Ok(written)
}

/// Writes (those of `kinds`) `animation.png` of a plant's frames (every
/// frame, or 60 spread evenly), each drawn as `plant.png` is, to the
/// extent of all of them; returns the paths.
fn animate<R: Records + ?Sized>(
    records: &R,
    dir: &Path,
    frames: &Frames,
    last: Extent,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let mut extent = frames.extent;
    for k in 0..2 {
        extent.lo[k] = extent.lo[k].min(last.lo[k]);
        extent.hi[k] = extent.hi[k].max(last.hi[k]);
    }
    let picked = animation_frames(frames.starts.len());
    let mut series: Option<Vec<Box<dyn PictureSeries>>> = None;
    for (slot, &k) in picked.iter().enumerate() {
        let (start, index) = frames.starts[k];
        let mut sorted = depth::Sort::new(dir);
        frame_items(records, start, |item| sorted.push(item))?;
        let drawn = Rgb::opaque(&render(extent, 480, |draw| sorted.drain(draw))?);
        let series = match &mut series {
            Some(series) => series,
            None => series.insert(kinds.animations(
                dir,
                &Sequence {
                    size: (drawn.width, drawn.height),
                    palette: None,
                    frames: picked.len(),
                },
            )?),
        };
        for s in series.iter() {
            s.frame(slot, &drawn.pixels(), &format!("step {index}"))?;
        }
    }
    let mut written = Vec::new();
    for s in series.into_iter().flatten() {
        written.extend(s.finish()?);
    }
    Ok(written)
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
