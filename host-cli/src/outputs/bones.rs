//! Bones (`long-bone`, `long-bone-random`, `bone-growth`): an OBJ and a
//! shaded PNG per wrapped frame, `model.glb` with every frame,
//! `animation.png` of the pictures (several frames), `bones.png` with
//! every frame side by side at one scale, each labelled with its L-system
//! steps (the paper's Fig. 2 and 3), and `summary.txt`, which
//! checks each mesh again in f64: Euler characteristic and the worst
//! |V − V0| / V0 over its vertices.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::bones::BonesParams;
use morphogen::fx::{Fx, Real};
use morphogen::shrinkwrap::{Element, worst_level_error};
use morphogen::stream::Record;
use nalgebra::Vector3;

use super::animation::{AnimationWriter, Pixels};
use super::body::{self, Extent, Frame, canvas, draw, rgb_of, solid};
use super::mesh::{GlbWriter, ObjStyle, write_frame_obj, write_mtl};
use super::{
    ANIMATION_DELAY_MS, Kind, Kinds, animation_frames, label_tile, picture, rgb_bytes, trimmed,
};
use crate::atomic::write_atomic;
use crate::records::{Place, Records};

/// Bone colour.
const BONE: [f32; 3] = [0.89, 0.86, 0.78];

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "bone.mtl";

/// Splits a bones stream into frames and their skeletons (the segments
/// since the frame's start, in f64), one record at a time.
#[derive(Debug, Default)]
struct Framer {
    frames: body::Framer,
    skeleton: Vec<Element<f64>>,
}

impl Framer {
    /// Takes the next record; returns the frame it ends and its skeleton.
    fn push(&mut self, r: &Record) -> Option<(Frame, Vec<Element<f64>>)> {
        match r {
            Record::FrameStart { .. } => self.skeleton.clear(),
            Record::Segment { a, b, width, .. } => {
                let v = |p: &[Fx; 3]| Vector3::from(p.map(f64::from_fx));
                self.skeleton
                    .push(Element::segment(v(a), v(b), f64::from_fx(*width)));
            }
            _ => {}
        }
        let frame = self.frames.push(r)?;
        Some((frame, std::mem::take(&mut self.skeleton)))
    }
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
    records.visit(Place::START, |_, r| {
        if let Some(f) = frames.push(r) {
            extent.include(&f);
            count += 1;
        }
        Ok(())
    })?;
    let b = extent.bounds();
    let level = f64::from_fx(params.wrap.target);
    let mut summary = format!(
        "{preset}: {count} frames, V0 = {level}\nframe  steps  elements  vertices  triangles  V-E+F  worst |V-V0|/V0\n",
    );
    let width = 360u32;
    let s = f64::from(width) / (b.1 - b.0);
    let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
    // The strip: at most 1 440 pixels wide, panels of 120 to 360.
    let panels = count.max(1) as u32;
    let panel = (1440 / panels).clamp(120, width);
    let ps = f64::from(panel) / (b.1 - b.0);
    let mut strip = canvas(panel * panels, ((b.3 - b.2) * ps).ceil().max(1.0) as u32)?;
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
    let mut framer = Framer::default();
    let mut k = 0usize;
    records.visit(Place::START, |_, r| {
        let Some((f, skeleton)) = framer.push(r) else {
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
            worst_level_error(&skeleton, &points(&f), level)
        );
        if kinds.has(Kind::Obj) || glb.is_some() {
            let header = format!("{preset} frame {}, {} L-system steps", f.index, f.age);
            let m = solid(&f, &header, "bone", rgb_of(BONE))?;
            if kinds.has(Kind::Obj) {
                if k == 0 {
                    let library = dir.join(LIBRARY);
                    write_mtl(&library, &m)?;
                    written.push(library);
                }
                let obj_path = dir.join(format!("frame_{:03}.obj", f.index));
                write_frame_obj(&obj_path, &m, ObjStyle::PLAIN, LIBRARY)?;
                written.push(obj_path);
            }
            if let Some(glb) = &mut glb {
                glb.push_frame(&m, k as f32 * f32::from(ANIMATION_DELAY_MS) / 1000.0)?;
            }
        }
        let animated = apng.as_mut().filter(|_| picked.binary_search(&k).is_ok());
        if kinds.has(Kind::Png) || animated.is_some() {
            let mut one = canvas(width, height)?;
            let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
            draw(&mut one, &f, BONE, s as f32, ox, oy);
            let one = picture::half(&one)?;
            if kinds.has(Kind::Png) {
                let png_path = dir.join(format!("bone_{:03}.png", f.index));
                picture::save(&one, &png_path)?;
                written.push(png_path);
            }
            if let Some(apng) = animated {
                apng.frame(&rgb_bytes(&one), &label(f.age))?;
            }
        }
        if kinds.has(Kind::Png) {
            let (ox, oy) = (
                (f64::from(panel) * k as f64 - b.0 * ps) as f32,
                (b.3 * ps) as f32,
            );
            draw(&mut strip, &f, BONE, ps as f32, ox, oy);
        }
        steps.push(f.age);
        k += 1;
        Ok(())
    })?;
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
        let mut half = picture::half(&strip)?;
        let h = half.height();
        for (n, &age) in steps.iter().enumerate() {
            label_tile(&mut half, [n as u32 * panel, 0, panel, h], &label(age))?;
        }
        let path = dir.join("bones.png");
        picture::save(&half, &path)?;
        written.push(path);
    }
    let path = dir.join("summary.txt");
    write_atomic(&path, summary.as_bytes())?;
    written.push(path);
    Ok(written)
}
