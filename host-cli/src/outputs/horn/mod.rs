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

use anyhow::{Context, Result};
use morphogen::horn::HornParams;
use morphogen::stream::Record;
use morphogen_stream_text::text::trimmed;
use tiny_skia::Pixmap;

use super::chart::{Axis, Chart, Series};
use super::driver::{self, Closing, Montage, Products, Rgb, Still};
use super::kinds::{Kinds, MeshFiles, Product, Sequence};
use super::numbered::FileSeries;
use super::plot::Drawing;
use super::{mesh, tip_bend};
use crate::records::Records;

mod frames;
mod shape;
mod view;

pub use frames::{Frame, Framer, P3, Ring, frames};
pub use shape::{Mesh, Triangle, mesh, solid};
use view::{Fit, background, centre_line, drawing, whole_picture};

/// The material library of the frames' OBJ files.
const LIBRARY: &str = "horn.mtl";

/// A frame's label: its time in years.
fn label(frame: &Frame) -> String {
    format!("year {}", trimmed(frame.years, 2))
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

    fn animation(&self, frames: usize) -> Result<Option<Sequence>> {
        Ok(Some(Sequence {
            size: (400, 400),
            palette: None,
            frames,
        }))
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
        if kinds.wants(Product::Picture) {
            let drawn = whole_picture(&last, self.j, (1200, 900))?;
            written.extend(kinds.picture(Product::Picture, &drawn.pixels(), dir, "horn")?);
        }
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
    use super::shape::centroid;
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
