//! Bones (`long-bone`, `long-bone-random`, `bone-growth`): an OBJ and a
//! shaded PNG per wrapped frame, `bones.png` with every frame side by side
//! at one scale (the paper's Fig. 2 and 3), and `summary.txt`, which
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

use super::body::{Frame, bounds, canvas, draw, frames, obj, save};
use crate::atomic::write_atomic;

/// Bone colour.
const BONE: [f32; 3] = [0.89, 0.86, 0.78];

/// The skeleton elements of each frame, in f64.
fn skeletons(records: &[Record]) -> Vec<Vec<Element<f64>>> {
    let mut out = Vec::new();
    for r in records {
        match r {
            Record::FrameStart { .. } => out.push(Vec::new()),
            Record::Segment { a, b, width, .. } => {
                if let Some(s) = out.last_mut() {
                    let v = |p: &[Fx; 3]| Vector3::from(p.map(f64::from_fx));
                    s.push(Element::segment(v(a), v(b), f64::from_fx(*width)));
                }
            }
            _ => {}
        }
    }
    out
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

/// Writes `frame_NNN.obj`, `bone_NNN.png`, `bones.png` and `summary.txt`.
///
/// # Errors
/// When a file cannot be written.
pub fn write(
    preset: &str,
    params: &BonesParams,
    records: &[Record],
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let frames = frames(records);
    let skeletons = skeletons(records);
    let level = f64::from_fx(params.wrap.target);
    let all: Vec<&Frame> = frames.iter().collect();
    let b = bounds(&all);
    let mut written = Vec::new();
    let mut summary = format!(
        "{preset}: {} frames, V0 = {level}\nframe  steps  elements  vertices  triangles  V-E+F  worst |V-V0|/V0\n",
        frames.len()
    );
    let width = 360u32;
    let s = f64::from(width) / (b.1 - b.0);
    let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
    // The strip: at most 1 440 pixels wide, panels of 120 to 360.
    let count = frames.len().max(1) as u32;
    let panel = (1440 / count).clamp(120, width);
    let ps = f64::from(panel) / (b.1 - b.0);
    let mut strip = canvas(panel * count, ((b.3 - b.2) * ps).ceil().max(1.0) as u32)?;
    for (k, (f, skeleton)) in frames.iter().zip(&skeletons).enumerate() {
        let _ = writeln!(
            summary,
            "{:5}  {:5.0}  {:8}  {:8}  {:9}  {:5}  {:.5}",
            f.index,
            f.age,
            skeleton.len(),
            f.vertices.len(),
            f.triangles.len(),
            euler(f),
            worst_level_error(skeleton, &points(f), level)
        );
        let obj_path = dir.join(format!("frame_{:03}.obj", f.index));
        let header = format!("{preset} frame {}, {} L-system steps", f.index, f.age);
        obj(f, &header, "bone", &obj_path)?;
        let mut one = canvas(width, height)?;
        let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
        draw(&mut one, f, BONE, s as f32, ox, oy);
        let png_path = dir.join(format!("bone_{:03}.png", f.index));
        save(&one, &png_path)?;
        let (ox, oy) = (
            (f64::from(panel) * k as f64 - b.0 * ps) as f32,
            (b.3 * ps) as f32,
        );
        draw(&mut strip, f, BONE, ps as f32, ox, oy);
        written.push(obj_path);
        written.push(png_path);
    }
    let path = dir.join("bones.png");
    save(&strip, &path)?;
    written.push(path);
    let path = dir.join("summary.txt");
    write_atomic(&path, summary.as_bytes())?;
    written.push(path);
    Ok(written)
}
