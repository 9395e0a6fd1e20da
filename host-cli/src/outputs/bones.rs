//! Bones (`long-bone`, `long-bone-random`, `bone-growth`, `bone-plate`,
//! `bone-ossification`): an OBJ and a
//! shaded PNG per wrapped frame, `model.glb` with every frame,
//! `animation.png` of the pictures (several frames), `bones.png` with
//! every frame side by side at one scale, each labelled with its L-system
//! steps (the paper's Fig. 2 and 3), `summary.txt`, which
//! checks each mesh again in f64: Euler characteristic and the worst
//! |V − V0| / V0 over its vertices, and `wrap.png`/`.svg`: how the
//! shrinkwrap of the last frame converged, iteration by iteration;
//! `plot.svg` the last frame's outline as its pictures show it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Result;
use morphogen::bones::{BonesParams, MCU_TRIANGLES, MCU_VERTICES};
use morphogen::fx::{Fx, Real};
use morphogen::shrinkwrap::{Element, Phase, Shrinkwrap, WrapParams, worst_level_error};
use morphogen::stream::Record;
use morphogen_stream_text::text::trimmed;
use nalgebra::Vector3;

use super::body::{self, Extent, Frame, Placement, Shading, canvas, canvases, draw, rgb_of, solid};
use super::chart::{Axis, Chart, Series};
use super::driver::{self, Closing, Montage, Products, Rgb};
use super::kinds::{Kinds, MeshFiles, Product, Sequence};
use super::mesh;
use super::numbered::FileSeries;
use super::picture::Canvases;
use super::plot::Drawing;
use crate::records::Records;

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
    /// The run's seed, from its header.
    seed: u64,
}

impl Framer {
    /// Takes the next record; returns the frame it ends, with its
    /// skeleton as streamed.
    fn push(&mut self, r: &Record) -> Option<BoneFrame> {
        match r {
            Record::Header(h) => self.seed = h.seed,
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
        Some(BoneFrame {
            mesh: self.frames.push(r)?,
            skeleton: std::mem::take(&mut self.fixed),
            seed: self.seed,
        })
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

/// A wrapped frame: its mesh, its skeleton as streamed, and the run's
/// seed (which draws the frame's wrap).
struct BoneFrame {
    mesh: Frame,
    skeleton: Skeleton,
    seed: u64,
}

/// Pixels across a bone's picture.
const WIDTH: u32 = 360;

/// The scale of a bones run's pictures, set by the survey.
struct Scale {
    /// Bounds of every frame (with a margin).
    b: (f64, f64, f64, f64),
    /// Pixels per unit of a picture, and its height.
    s: f64,
    height: u32,
    /// A tile of `bones.png`: its width, pixels per unit and height.
    panel: u32,
    ps: f64,
    panel_height: u32,
    /// Canvases for the pictures.
    ones: Canvases,
}

/// A bones run's products ([`driver::write`]): `frame_NNN.obj`,
/// `model.glb`, `bone_NNN.png`, `animation.png` (every frame, or 60
/// spread evenly), `bones.png` (every frame, at most 1 440 pixels across),
/// `wrap.png`/`.svg` (the last frame's shrinkwrap again) and
/// `summary.txt` (each mesh checked again in f64).
struct Bones<'a> {
    preset: &'a str,
    params: &'a BonesParams<'a>,
    count: usize,
    extent: Extent,
    summary: String,
    /// The last frame: its index, vertices, skeleton and wrap.
    last: Option<(u32, usize, Skeleton, WrapParams)>,
    /// The last frame's mesh, for its outline.
    last_mesh: Option<Frame>,
    scale: Option<Scale>,
}

impl Bones<'_> {
    /// The frame's wrap, its V0 and ΔV drawn as the run drew them.
    fn frame_wrap(&self, f: &BoneFrame) -> WrapParams {
        let seed = self.params.frame_seed(f.seed, f.mesh.index);
        self.params.frame_wrap(seed, f.mesh.age as u8)
    }

    fn scale(&self) -> Result<&Scale> {
        self.scale
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("the bones' frames are not surveyed"))
    }
}

impl Products for Bones<'_> {
    type Frame = BoneFrame;
    type Framer = Framer;
    type Picture = Rgb;
    type Measure = ();

    fn push(framer: &mut Framer, record: &Record) -> Result<Option<BoneFrame>> {
        Ok(framer.push(record))
    }

    fn survey(&mut self, f: BoneFrame) -> Result<()> {
        let wrap = self.frame_wrap(&f);
        let skeleton: Vec<Element<f64>> = f.skeleton.iter().map(in_f64).collect();
        let m = &f.mesh;
        let worst = worst_level_error(
            &skeleton,
            self.params.wrap.weights,
            &points(m),
            f64::from_fx(wrap.target),
        );
        writeln!(
            self.summary,
            "{:5}  {:5.0}  {:8}  {:8}  {:9}  {:5}  {:.5}",
            m.index,
            m.age,
            skeleton.len(),
            m.vertices.len(),
            m.triangles.len(),
            euler(m),
            worst
        )?;
        self.extent.include(m);
        self.count += 1;
        self.last = Some((m.index, m.vertices.len(), f.skeleton, wrap));
        self.last_mesh = Some(f.mesh);
        Ok(())
    }

    fn surveyed(&mut self, _framer: Framer) {
        let b = self.extent.bounds();
        let s = f64::from(WIDTH) / (b.1 - b.0);
        let height = ((b.3 - b.2) * s).ceil().max(1.0) as u32;
        // The strip: at most 1 440 pixels wide, panels of 120 to 360.
        let panel = (1440 / self.count.max(1) as u32).clamp(120, WIDTH);
        let ps = f64::from(panel) / (b.1 - b.0);
        self.scale = Some(Scale {
            b,
            s,
            height,
            panel,
            ps,
            panel_height: ((b.3 - b.2) * ps).ceil().max(1.0) as u32,
            ones: canvases(WIDTH, height),
        });
    }

    fn index(f: &BoneFrame) -> i64 {
        i64::from(f.mesh.index)
    }

    fn mesh_files(&self) -> Option<MeshFiles> {
        Some(MeshFiles {
            library: LIBRARY,
            scene: self.preset.into(),
            metres: 1.0,
        })
    }

    fn mesh(&self, f: &BoneFrame) -> Result<Option<mesh::Mesh>> {
        let m = &f.mesh;
        let header = format!(
            "{} frame {}, {} L-system steps",
            self.preset, m.index, m.age
        );
        solid(m, &header, "bone", rgb_of(BONE)).map(Some)
    }

    fn stills(&self) -> Option<FileSeries> {
        Some(FileSeries::BONES)
    }

    fn animation(&self, frames: usize) -> Result<Option<Sequence>> {
        let height = self.scale()?.height;
        Ok(Some(Sequence {
            size: (WIDTH, height),
            palette: None,
            frames,
        }))
    }
    fn picture(&self, f: &BoneFrame) -> Result<Rgb> {
        let Scale { b, s, ones, .. } = self.scale()?;
        let mut one = ones.take()?;
        let (ox, oy) = ((-b.0 * s) as f32, (b.3 * s) as f32);
        draw(
            &mut one,
            &f.mesh,
            (BONE, Shading::Smooth),
            Placement::new(*s as f32, ox, oy),
        );
        let rgb = Rgb::halved(&one);
        ones.give_back(one);
        rgb
    }

    fn label(&self, f: &BoneFrame) -> String {
        label(f.mesh.age)
    }

    fn montage(&self) -> Option<Montage> {
        let scale = self.scale.as_ref()?;
        Some(Montage {
            name: "bones",
            frames: (0..self.count).collect(),
            tile: (scale.panel, scale.panel_height),
            columns: self.count.max(1) as u32,
            background: body::BACKGROUND,
        })
    }

    fn tile(&self, f: &BoneFrame, n: usize) -> Result<Option<Rgb>> {
        let scale = self.scale()?;
        let (b, ps, panel) = (scale.b, scale.ps, scale.panel);
        let mut p = canvas(panel, scale.panel_height)?;
        let at = Placement {
            left: (panel as usize * n) as f32,
            ..Placement::new(
                ps as f32,
                (f64::from(panel) * n as f64 - b.0 * ps) as f32,
                (b.3 * ps) as f32,
            )
        };
        draw(&mut p, &f.mesh, (BONE, Shading::Smooth), at);
        Rgb::halved(&p).map(Some)
    }

    fn plot(&self) -> Result<Option<Drawing>> {
        Ok(self.last_mesh.as_ref().map(body::outline))
    }

    fn close(mut self, dir: &Path, kinds: Kinds, _run: Closing<()>) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        if let Some((frame, vertices, skeleton, wrap)) = self.last.take()
            && kinds.wants(Product::Chart)
        {
            let run = wrap_steps(&skeleton, &wrap)?;
            // The run done again is the one streamed.
            anyhow::ensure!(
                run.last().map(|s| s.vertices) == Some(vertices),
                "the shrinkwrap of frame {frame} done again differs from the stream"
            );
            writeln!(
                self.summary,
                "the shrinkwrap of frame {frame}: {} iterations, worst |V-V0|/V0 {:.5} after the last",
                run.len() - 1,
                run.last().map_or(0.0, |s| s.worst)
            )?;
            let chart = wrap_chart(&run, self.params.wrap.split_tolerance.to_f64(), frame);
            written.extend(kinds.chart(&chart, dir, "wrap", (900, 500))?);
        }
        let level = f64::from_fx(self.params.wrap.target);
        let levels = match self.params.wrap.target_max {
            None => format!("{level}"),
            Some(top) => format!("{level} to {} (drawn per frame)", f64::from_fx(top)),
        };
        let head = format!(
            "{}: {} frames, V0 = {levels}\nframe  steps  elements  vertices  triangles  V-E+F  worst |V-V0|/V0\n",
            self.preset, self.count
        );
        written.extend(kinds.text(&(head + &self.summary), dir, "summary")?);
        Ok(written)
    }
}

/// Writes (those of `kinds`) a bones run's files (`Bones`).
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
    let bones = Bones {
        preset,
        params,
        count: 0,
        extent: Extent::new(),
        summary: String::new(),
        last: None,
        last_mesh: None,
        scale: None,
    };
    driver::write(bones, records, dir, kinds)
}
