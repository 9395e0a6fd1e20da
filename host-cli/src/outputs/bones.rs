//! Bones (`long-bone`, `long-bone-random`, `bone-growth`, `bone-plate`,
//! `bone-ossification`): an OBJ and a
//! shaded PNG per wrapped frame, `model.glb` with every frame,
//! `animation.png` of the pictures (several frames), `bones.png` with
//! every frame side by side at one scale, each labelled with its L-system
//! steps (the paper's Fig. 2 and 3), `summary.txt`, which
//! checks each mesh again in f64: Euler characteristic and the worst
//! |V − V0| / V0 over its vertices, and `wrap.png`/`.svg`: how the
//! shrinkwrap of the last frame converged, iteration by iteration.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::bones::{BonesParams, MCU_TRIANGLES, MCU_VERTICES};
use morphogen::fx::{Fx, Real};
use morphogen::shrinkwrap::{Element, Phase, Shrinkwrap, WrapParams, worst_level_error};
use morphogen::stream::Record;
use nalgebra::Vector3;

use super::animation::{AnimationWriter, Pixels};
use super::body::{self, Extent, Frame, Shading, canvas, canvases, draw, rgb_of, solid};
use super::chart::{Axis, Chart, Series, write_png, write_svg};
use super::kinds::{Kind, Kinds};
use super::mesh::{GlbWriter, Library, ObjStyle, write_frame_obj};
use super::montage::save_montage;
use super::numbered::{FileSeries, Numbering};
use super::picture;
use super::slots::{ANIMATION_DELAY_MS, animation_frames};
use super::text::trimmed;
use crate::atomic::write_atomic;
use crate::records::{Place, Records};

/// Bone colour.
const BONE: [f32; 3] = [0.89, 0.86, 0.78];

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "bone.mtl";

/// A frame's skeleton as streamed.
type Skeleton = Vec<Element<Fx>>;

/// Splits a bones stream into frames and their skeletons (the segments
/// since the frame's start, a `Polygon` record tagging the edges that
/// follow as one polygon element), one record at a time.
#[derive(Debug, Default)]
struct Framer {
    frames: body::Framer,
    /// The skeleton of the frame being read, as streamed.
    fixed: Skeleton,
    /// Edges of the polygon element being read still to come (a
    /// `Polygon` record of k vertices is followed by its k edges).
    edges: u8,
}

impl Framer {
    /// Takes the next record; returns the frame it ends and its skeleton
    /// (as streamed, and in f64).
    fn push(&mut self, r: &Record) -> Option<(Frame, Skeleton, Vec<Element<f64>>)> {
        match r {
            Record::FrameStart { .. } => {
                self.fixed.clear();
                self.edges = 0;
            }
            Record::Polygon { vertices, .. } => {
                self.edges = u8::try_from(*vertices).unwrap_or(u8::MAX);
            }
            Record::Segment { a, b, width, .. } => {
                let v = |p: &[Fx; 3]| Vector3::from(*p);
                self.fixed.push(Element {
                    polygon: self.edges,
                    ..Element::segment(v(a), v(b), *width)
                });
                self.edges = self.edges.saturating_sub(1);
            }
            _ => {}
        }
        let frame = self.frames.push(r)?;
        let fixed = std::mem::take(&mut self.fixed);
        let skeleton = fixed.iter().map(in_f64).collect();
        Some((frame, fixed, skeleton))
    }
}

/// A skeleton element in f64.
fn in_f64(e: &Element<Fx>) -> Element<f64> {
    e.convert(f64::from_fx)
}

/// One iteration of a shrinkwrap run: its level V0, its mesh's vertices
/// and the worst |V − V0| / V0 over them (in f64).
#[derive(Debug, Clone, Copy, PartialEq)]
struct WrapStep {
    level: f64,
    vertices: usize,
    worst: f64,
}

/// The shrinkwrap of `skeleton` with `params` done again, as the device
/// does it (bones paper Sec. 5: raise V0 by ΔV, move, split), measured
/// after its start and after every iteration.
///
/// # Errors
/// As the run's own errors (a capacity, the iteration limit).
fn wrap_steps(skeleton: &[Element<Fx>], params: &WrapParams) -> Result<Vec<WrapStep>> {
    let mut wrap = Box::new(Shrinkwrap::<Fx, MCU_VERTICES, MCU_TRIANGLES>::new(Fx::ZERO));
    let reference: Vec<Element<f64>> = skeleton.iter().map(in_f64).collect();
    let measure = |wrap: &Shrinkwrap<Fx, MCU_VERTICES, MCU_TRIANGLES>| {
        let level = f64::from_fx(wrap.level());
        let points: Vec<Vector3<f64>> = wrap
            .mesh()
            .vertices()
            .iter()
            .map(|p| p.map(f64::from_fx))
            .collect();
        WrapStep {
            level,
            vertices: points.len(),
            worst: worst_level_error(&reference, params.weights, &points, level),
        }
    };
    wrap.start(skeleton, params)?;
    let mut steps = vec![measure(&wrap)];
    loop {
        let phase = wrap.iterate(skeleton)?;
        steps.push(measure(&wrap));
        if phase == Phase::Done {
            return Ok(steps);
        }
    }
}

/// The chart of a shrinkwrap run: the worst level error (%) against the
/// split tolerance, and the mesh's vertices on the right.
fn wrap_chart(steps: &[WrapStep], tolerance: f64, frame: u32) -> Chart {
    let along = |f: &dyn Fn(&WrapStep) -> f64| -> Vec<(f64, f64)> {
        steps
            .iter()
            .enumerate()
            .map(|(i, s)| (i as f64, f(s)))
            .collect()
    };
    let last = steps.len().saturating_sub(1) as f64;
    Chart::new(
        format!("Shrinkwrap of frame {frame}, iteration by iteration"),
        Axis::new("iteration", "count"),
        Axis::new("worst |V − V0| / V0", "%"),
    )
    .with_y2(Axis::new("mesh vertices", "count"))
    .with_series(Series::line(
        "worst level error",
        along(&|s| 100.0 * s.worst),
    ))
    .with_series(Series::line(
        "split tolerance",
        vec![(0.0, 100.0 * tolerance), (last, 100.0 * tolerance)],
    ))
    .with_series(Series::line("vertices", along(&|s| s.vertices as f64)).on_right())
}

/// A frame's vertices as vectors.
fn points(frame: &Frame) -> Vec<Vector3<f64>> {
    frame.vertices.iter().map(|v| Vector3::from(*v)).collect()
}

/// V − E + F of a frame's mesh.
fn euler(frame: &Frame) -> i64 {
    let mut edges: Vec<(u32, u32)> = frame
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    frame.vertices.len() as i64 - edges.len() as i64 + frame.triangles.len() as i64
}

/// A frame's label: its L-system steps.
fn label(steps: f64) -> String {
    format!("step {}", trimmed(steps, 1))
}

/// Writes (those of `kinds`) `frame_NNN.obj`, `model.glb`,
/// `bone_NNN.png`, `animation.png` (every frame, or 60 spread evenly),
/// `bones.png` and `summary.txt`, in two passes a frame at a time: the
/// frame count and the common scale, then the files.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    preset: &str,
    params: &BonesParams,
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let mut count = 0usize;
    let mut extent = Extent::new();
    let mut frames = body::Framer::default();
    let mut seed = 0;
    records.visit(Place::START, |_, r| {
        if let Record::Header(h) = r {
            seed = h.seed;
        }
        if let Some(f) = frames.push(r) {
            extent.include(&f);
            count += 1;
        }
        Ok(())
    })?;
    let b = extent.bounds();
    let numbering = Numbering::frames(count);
    let level = f64::from_fx(params.wrap.target);
    let levels = match params.wrap.target_max {
        None => format!("{level}"),
        Some(top) => format!("{level} to {} (drawn per frame)", f64::from_fx(top)),
    };
    // Frame k's wrap, its V0 and ΔV drawn as the run drew them.
    let frame_wrap =
        |k: u32, steps: f64| params.frame_wrap(params.frame_seed(seed, k), steps as u8);
    let mut summary = format!(
        "{preset}: {count} frames, V0 = {levels}\nframe  steps  elements  vertices  triangles  V-E+F  worst |V-V0|/V0\n",
    );
    let width = 360u32;
    let s = f64::from(width) / (b.1 - b.0);
    let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
    // The strip: at most 1 440 pixels wide, panels of 120 to 360.
    let panels = count.max(1) as u32;
    let panel = (1440 / panels).clamp(120, width);
    let ps = f64::from(panel) / (b.1 - b.0);
    let mut strip = canvas(panel * panels, ((b.3 - b.2) * ps).ceil().max(1.0) as u32)?;
    let ones = canvases(width, height);
    let picked = if kinds.has(Kind::Anim) && count > 1 {
        animation_frames(count)
    } else {
        Vec::new()
    };
    let anim_path = dir.join("animation.png");
    let mut apng = if picked.is_empty() {
        None
    } else {
        Some(AnimationWriter::new(
            &anim_path,
            width,
            height,
            Pixels::Rgb,
            u32::try_from(picked.len())?,
            ANIMATION_DELAY_MS,
        )?)
    };
    let mut glb = kinds.has(Kind::Glb).then(|| GlbWriter::new(preset, 1.0));
    let mut steps = Vec::with_capacity(count);
    // A frame at a time, in order: the check of each mesh in f64 is the
    // memory-hungry part, and one at a time keeps it so.
    let mut written = Vec::new();
    let mut library = Library::new(dir, LIBRARY);
    // The last frame: its index, vertices and skeleton.
    let mut last = None;
    let mut framer = Framer::default();
    let mut k = 0usize;
    records.visit(Place::START, |_, r| {
        let Some((f, fixed, skeleton)) = framer.push(r) else {
            return Ok(());
        };
        let _ = writeln!(
            summary,
            "{:5}  {:5.0}  {:8}  {:8}  {:9}  {:5}  {:.5}",
            f.index,
            f.age,
            skeleton.len(),
            f.vertices.len(),
            f.triangles.len(),
            euler(&f),
            worst_level_error(
                &skeleton,
                params.wrap.weights,
                &points(&f),
                f64::from_fx(frame_wrap(f.index, f.age).target)
            )
        );
        if kinds.has(Kind::Obj) || glb.is_some() {
            let header = format!("{preset} frame {}, {} L-system steps", f.index, f.age);
            let m = solid(&f, &header, "bone", rgb_of(BONE))?;
            if kinds.has(Kind::Obj) {
                library.write_once(&m)?;
                let obj_path = dir.join(numbering.name(FileSeries::FRAMES, f.index));
                write_frame_obj(&obj_path, &m, ObjStyle::PLAIN, LIBRARY)?;
                written.push(obj_path);
            }
            if let Some(glb) = &mut glb {
                glb.push_frame(&m, k as f32 * f32::from(ANIMATION_DELAY_MS) / 1000.0)?;
            }
        }
        let animated = apng.as_mut().filter(|_| picked.binary_search(&k).is_ok());
        if kinds.has(Kind::Png) || animated.is_some() {
            let mut one = ones.take()?;
            let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
            draw(&mut one, &f, (BONE, Shading::Smooth), s as f32, ox, oy);
            let rgb = picture::half_rgb(&one)?;
            let (w, h) = (one.width() / 2, one.height() / 2);
            ones.give_back(one);
            if kinds.has(Kind::Png) {
                let png_path = dir.join(numbering.name(FileSeries::BONES, f.index));
                picture::save_rgb(w, h, &rgb, &png_path)?;
                written.push(png_path);
            }
            if let Some(apng) = animated {
                apng.frame(rgb, &label(f.age))?;
            }
        }
        if kinds.has(Kind::Png) {
            let (ox, oy) = (
                (f64::from(panel) * k as f64 - b.0 * ps) as f32,
                (b.3 * ps) as f32,
            );
            draw(&mut strip, &f, (BONE, Shading::Smooth), ps as f32, ox, oy);
        }
        steps.push(f.age);
        k += 1;
        last = Some((f.index, f.vertices.len(), fixed, frame_wrap(f.index, f.age)));
        Ok(())
    })?;
    if let Some((frame, vertices, skeleton, wrap)) = last
        && (kinds.has(Kind::Png) || kinds.has(Kind::Svg))
    {
        let run = wrap_steps(&skeleton, &wrap)?;
        // The run done again is the one streamed.
        anyhow::ensure!(
            run.last().map(|s| s.vertices) == Some(vertices),
            "the shrinkwrap of frame {frame} done again differs from the stream"
        );
        let _ = writeln!(
            summary,
            "the shrinkwrap of frame {frame}: {} iterations, worst |V-V0|/V0 {:.5} after the last",
            run.len() - 1,
            run.last().map_or(0.0, |s| s.worst)
        );
        let chart = wrap_chart(&run, params.wrap.split_tolerance.to_f64(), frame);
        for (kind, name) in [(Kind::Png, "wrap.png"), (Kind::Svg, "wrap.svg")] {
            if kinds.has(kind) {
                let path = dir.join(name);
                match kind {
                    Kind::Png => write_png(&chart, &path, 900, 500)?,
                    _ => write_svg(&chart, &path, 900, 500)?,
                }
                written.push(path);
            }
        }
    }
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
    if kinds.has(Kind::Png) {
        let h = strip.height() / 2;
        let labels: Vec<_> = (0..)
            .zip(&steps)
            .map(|(n, &age)| ([n * panel, 0, panel, h], label(age)))
            .collect();
        let path = dir.join("bones.png");
        save_montage(&strip, &labels, &path)?;
        written.push(path);
    }
    let path = dir.join("summary.txt");
    write_atomic(&path, summary.as_bytes())?;
    written.push(path);
    Ok(written)
}
