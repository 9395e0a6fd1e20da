//! The one writer of a model's files. A model states its products as
//! [`Products`] — frame → mesh, frame → picture with its label, frames →
//! montage tiles, frame → tables of its own, last frame → pen strokes,
//! run → charts, tables, pictures and texts — and [`write`] writes every
//! kind `--only` asks for, in two passes over the stream a frame at a
//! time: the survey (the frame count, the common scale, the tables), then
//! the files, drawn by parallel workers and handed over in order.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Result, anyhow, bail};
use morphogen::stream::Record;

use super::kinds::{Kinds, MeshFiles, MeshSeries, PictureSeries, Pixels, Product, Sequence};
use super::mesh;
use super::montage::{labelled, paste_rgb};
use super::numbered::{FileSeries, Numbering};
use super::picture;
use super::pipeline::pipeline;
use super::plot::{self, Drawing};
use super::slots::animation_frames;
use crate::records::{Place, Records};

/// A picture as drawn: RGB bytes row by row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Rgb {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Red, green and blue of each pixel, row by row.
    pub bytes: Vec<u8>,
}

/// A frame's picture, as its still, its animation frame and its tile use
/// it.
pub(crate) trait Still: Send + Sync {
    /// Its pixels.
    fn pixels(&self) -> Pixels<'_>;
}

impl Still for Rgb {
    fn pixels(&self) -> Pixels<'_> {
        Pixels::Rgb {
            size: (self.width, self.height),
            rgb: &self.bytes,
        }
    }
}

impl Rgb {
    /// The pixels of `pixmap`, every one of which is opaque.
    pub(crate) fn opaque(pixmap: &tiny_skia::Pixmap) -> Rgb {
        Rgb {
            width: pixmap.width(),
            height: pixmap.height(),
            bytes: picture::rgb_bytes(pixmap),
        }
    }

    /// A drawing at twice its size, averaged down ([`picture::half_rgb`]).
    ///
    /// # Errors
    /// When `pixmap` is less than 2 pixels wide or high.
    pub(crate) fn halved(pixmap: &tiny_skia::Pixmap) -> Result<Rgb> {
        Ok(Rgb {
            width: pixmap.width() / 2,
            height: pixmap.height() / 2,
            bytes: picture::half_rgb(pixmap)?,
        })
    }
}

/// A picture of several frames side by side ([`labelled`]), each tile
/// labelled with its frame's label.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Montage {
    /// Its file name without the extension its kind adds (`years`).
    pub name: &'static str,
    /// The frames it shows, by position in the stream, rising.
    pub frames: Vec<usize>,
    /// Each tile's size, pixels.
    pub tile: (u32, u32),
    /// Tiles a row (at least one).
    pub columns: u32,
    /// The colour where no tile is.
    pub background: [u8; 3],
}

impl Montage {
    /// The whole picture's size.
    fn size(&self) -> (u32, u32) {
        let columns = self.columns.max(1);
        let rows = (self.frames.len() as u32).div_ceil(columns).max(1);
        (self.tile.0 * columns, self.tile.1 * rows)
    }

    /// The box of tile `n`.
    fn tile_box(&self, n: usize) -> [u32; 4] {
        let (n, columns) = (n as u32, self.columns.max(1));
        let (w, h) = self.tile;
        [n % columns * w, n / columns * h, w, h]
    }
}

/// What a model makes of its stream, for [`write`]. Only the frames are
/// required; every product has a default of none.
pub(crate) trait Products: Sync {
    /// One frame (a day of a mosaic), as its records group.
    type Frame: Send + Sync;
    /// Groups records into frames.
    type Framer: Default;
    /// A frame's picture.
    type Picture: Still;
    /// What a frame's own files measure for the run's tables.
    type Measure: Send;

    /// Takes the next record; returns the frame it ends, if any.
    ///
    /// # Errors
    /// When the records do not make frames.
    fn push(framer: &mut Self::Framer, record: &Record) -> Result<Option<Self::Frame>>;

    /// Checks that the stream did not end inside a frame.
    ///
    /// # Errors
    /// When it did.
    fn end(_framer: &Self::Framer) -> Result<()> {
        Ok(())
    }

    /// The first pass: learns from each frame, in order, what the run
    /// sets (its scale, its tables), keeping what it needs.
    ///
    /// # Errors
    /// When the frame cannot be measured.
    fn survey(&mut self, frame: Self::Frame) -> Result<()>;

    /// Ends the survey: every frame is seen, and what the framer gathered
    /// besides (a mosaic's mesh) is handed over.
    fn surveyed(&mut self, _framer: Self::Framer) {}

    /// The frame's number in file names (`frame_NNN.obj`, `day_NN.png`).
    fn index(frame: &Self::Frame) -> i64;

    /// How the numbered files of `count` frames are named.
    fn numbering(&self, count: usize) -> Numbering {
        Numbering::frames(count)
    }

    /// Where the frames' meshes go, if the model makes them.
    fn mesh_files(&self) -> Option<MeshFiles> {
        None
    }

    /// The frame's mesh, for `frame_NNN.obj` and `model.glb`.
    ///
    /// # Errors
    /// When the frame is not a mesh.
    fn mesh(&self, _frame: &Self::Frame) -> Result<Option<mesh::Mesh>> {
        Ok(None)
    }

    /// The series of a picture per frame, if the model writes one.
    fn stills(&self) -> Option<FileSeries> {
        None
    }

    /// The sequence of `frames` of the frames' pictures (an animation),
    /// if the model shows one.
    ///
    /// # Errors
    /// When the run is not surveyed.
    fn animation(&self, _frames: usize) -> Result<Option<Sequence>> {
        Ok(None)
    }

    /// The frame's picture: its still, its `animation.png` frame, its
    /// tile, and what its own files are drawn from.
    ///
    /// # Errors
    /// When it cannot be drawn, or the model draws no picture of a frame.
    fn picture(&self, _frame: &Self::Frame) -> Result<Self::Picture> {
        bail!("this model draws no picture of a frame")
    }

    /// The frame's label in the animation and the montage.
    fn label(&self, _frame: &Self::Frame) -> String {
        String::new()
    }

    /// The montage, planned after the survey.
    fn montage(&self) -> Option<Montage> {
        None
    }

    /// The frame's tile in the montage (the `n`-th); `None` when it is
    /// its [`Products::picture`].
    ///
    /// # Errors
    /// When it cannot be drawn.
    fn tile(&self, _frame: &Self::Frame, _n: usize) -> Result<Option<Rgb>> {
        Ok(None)
    }

    /// Whether every frame has files of its own ([`Products::frame_files`]),
    /// and whether those need its picture.
    fn frame_work(&self) -> (bool, bool) {
        (false, false)
    }

    /// The frame's own files besides its mesh and its still (a table of
    /// its cells, a second picture), the frame at `position`, its
    /// `picture` if drawn (its last use); returns their paths and what
    /// they measure.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn frame_files(
        &self,
        _frame: &Self::Frame,
        _position: usize,
        _picture: Option<Self::Picture>,
        _numbering: Numbering,
    ) -> Result<(Vec<PathBuf>, Option<Self::Measure>)> {
        Ok((Vec::new(), None))
    }

    /// The last frame as pen strokes, for `plot.svg`, if the model draws
    /// one.
    ///
    /// # Errors
    /// When the strokes cannot be found.
    fn plot(&self) -> Result<Option<Drawing>> {
        Ok(None)
    }

    /// The run's own files, once the frames' are written: charts,
    /// tables, summaries.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn close(self, dir: &Path, kinds: Kinds, run: Closing<Self::Measure>) -> Result<Vec<PathBuf>>;
}

/// What the frames' files leave for [`Products::close`].
#[derive(Debug)]
pub(crate) struct Closing<M> {
    /// Whether the montage was written.
    pub montage: bool,
    /// What each frame's own files measured: the frame's position, its
    /// measure.
    pub measures: Vec<(usize, M)>,
}

/// A frame's work for the drawing workers.
struct Job<F> {
    frame: F,
    position: usize,
    mesh: Option<mesh::Mesh>,
    slot: Option<usize>,
    tile: Option<usize>,
}

/// What a frame's work returns: its files, its label if it is a tile,
/// and its measure.
type Done<M> = (Vec<PathBuf>, Option<String>, Option<(usize, M)>);

/// The files a run's frames make together, planned after the survey.
struct Plan<'a> {
    dir: &'a Path,
    kinds: Kinds,
    numbering: Numbering,
    /// Where the frames' meshes go, when each frame has files of its own.
    meshes: Option<MeshFiles>,
    stills: Option<FileSeries>,
    /// Whether every frame has files of its own, and whether those need
    /// its picture.
    frame_work: (bool, bool),
    /// The frames the animation shows (by position), and what takes them.
    picked: Vec<usize>,
    animation: Vec<Box<dyn PictureSeries>>,
    montage: Option<(Montage, Mutex<Vec<u8>>)>,
}

impl<'a> Plan<'a> {
    /// The plan for `count` frames of `model`, those files of `kinds`.
    fn new<M: Products>(model: &M, count: usize, dir: &'a Path, kinds: Kinds) -> Result<Self> {
        let mut picked = if kinds.wants(Product::Animation) && count > 1 {
            animation_frames(count)
        } else {
            Vec::new()
        };
        let sequence = match picked.len() {
            0 => None,
            frames => model.animation(frames)?,
        };
        let animation = match sequence {
            Some(sequence) => kinds.animations(dir, &sequence)?,
            None => Vec::new(),
        };
        if animation.is_empty() {
            picked.clear();
        }
        let pictures = kinds.wants(Product::FramePicture);
        let montage = model.montage().filter(|_| pictures).map(|m| {
            let (w, h) = m.size();
            let rgb = m.background.repeat((w * h) as usize);
            (m, Mutex::new(rgb))
        });
        Ok(Plan {
            dir,
            kinds,
            numbering: model.numbering(count),
            meshes: model
                .mesh_files()
                .filter(|_| kinds.wants(Product::FrameMesh)),
            stills: model.stills().filter(|_| pictures),
            frame_work: model.frame_work(),
            picked,
            animation,
            montage,
        })
    }

    /// The work on the frame at `position`, if any.
    fn job<F>(&self, frame: F, position: usize, mesh: Option<mesh::Mesh>) -> Option<Job<F>> {
        let slot = self.picked.binary_search(&position).ok();
        let tile = self
            .montage
            .as_ref()
            .and_then(|(m, _)| m.frames.binary_search(&position).ok());
        let work = mesh.is_some()
            || self.stills.is_some()
            || self.frame_work.0
            || slot.is_some()
            || tile.is_some();
        work.then_some(Job {
            frame,
            position,
            mesh,
            slot,
            tile,
        })
    }

    /// Ends the montage and the animation, the frames' labels in the
    /// montage's order; returns their paths.
    fn finish(self, labels: Vec<String>) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        if let Some((montage, rgb)) = self.montage {
            let rgb = rgb.into_inner().map_err(|_| anyhow!("a drawing stopped"))?;
            let boxes = (0..labels.len()).map(|n| montage.tile_box(n));
            let labels: Vec<_> = boxes.zip(labels).collect();
            let size = montage.size();
            let rgb = labelled(rgb, size, &labels)?;
            let pixels = Pixels::Rgb { size, rgb: &rgb };
            let (kinds, dir) = (self.kinds, self.dir);
            written.extend(kinds.picture(Product::FramePicture, &pixels, dir, montage.name)?);
        }
        for animation in self.animation {
            written.extend(animation.finish()?);
        }
        Ok(written)
    }
}

/// Writes `model`'s files of `kinds` from `records` into `dir`; returns
/// their paths.
///
/// # Errors
/// A malformed stream, unreadable records, or a file that cannot be
/// written.
pub(crate) fn write<M: Products, R: Records + ?Sized>(
    mut model: M,
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let count = survey(&mut model, records)?;
    let plan = Plan::new(&model, count, dir, kinds)?;
    let files = model
        .mesh_files()
        .filter(|_| kinds.wants(Product::FrameMesh) || kinds.wants(Product::FrameMeshes));
    let mut series: Vec<Box<dyn MeshSeries>> = files
        .iter()
        .flat_map(|f| {
            kinds
                .formats(Product::FrameMeshes)
                .filter_map(|k| k.frame_meshes(dir, f))
        })
        .collect();
    let (model_ref, plan_ref) = (&model, &plan);
    let done: Vec<Done<M::Measure>> = pipeline(
        |send| {
            let mut framer = M::Framer::default();
            let mut position = 0usize;
            records.visit(Place::START, |_, r| {
                let Some(frame) = M::push(&mut framer, r)? else {
                    return Ok(());
                };
                let mesh = match &files {
                    Some(_) => model_ref.mesh(&frame)?,
                    None => None,
                };
                if let Some(m) = &mesh {
                    for s in &mut series {
                        s.push(m, position)?;
                    }
                }
                let mesh = mesh.filter(|_| plan_ref.meshes.is_some());
                let job = plan_ref.job(frame, position, mesh);
                position += 1;
                match job {
                    Some(job) => send(job),
                    None => Ok(()),
                }
            })?;
            M::end(&framer)
        },
        |job: Job<M::Frame>| frame_files(model_ref, plan_ref, job),
    )?;
    let mut written = Vec::new();
    let mut labels = Vec::new();
    let mut measures = Vec::new();
    for (paths, label, measure) in done {
        written.extend(paths);
        labels.extend(label);
        measures.extend(measure);
    }
    for s in series {
        written.extend(s.finish()?);
    }
    let closing = Closing {
        montage: plan.montage.is_some(),
        measures,
    };
    written.extend(plan.finish(labels)?);
    if kinds.wants(Product::Drawing) {
        match model.plot()? {
            Some(drawing) => written.extend(kinds.drawing(&drawing, dir)?),
            None => eprintln!("note: no {}: this model draws no strokes", plot::FILE),
        }
    }
    written.extend(model.close(dir, kinds, closing)?);
    Ok(written)
}

/// The first pass: every frame surveyed; returns how many there are.
fn survey<M: Products, R: Records + ?Sized>(model: &mut M, records: &R) -> Result<usize> {
    let mut framer = M::Framer::default();
    let mut count = 0usize;
    records.visit(Place::START, |_, r| {
        if let Some(frame) = M::push(&mut framer, r)? {
            model.survey(frame)?;
            count += 1;
        }
        Ok(())
    })?;
    M::end(&framer)?;
    model.surveyed(framer);
    Ok(count)
}

/// One frame's files (its OBJ, its still and its own), its animation
/// frame and its montage tile; returns the files' paths, its label if it
/// is a tile, and its measure.
fn frame_files<M: Products>(
    model: &M,
    plan: &Plan<'_>,
    job: Job<M::Frame>,
) -> Result<Done<M::Measure>> {
    let index = M::index(&job.frame);
    let (kinds, dir) = (plan.kinds, plan.dir);
    let mut paths = Vec::with_capacity(2);
    if let (Some(m), Some(files)) = (&job.mesh, &plan.meshes) {
        let name = plan.numbering.stem(FileSeries::FRAMES, index);
        for k in kinds.formats(Product::FrameMesh) {
            paths.extend(k.frame_mesh(m, dir, &name, files)?);
        }
    }
    let tile = match (&plan.montage, job.tile) {
        (Some(_), Some(n)) => Some((n, model.tile(&job.frame, n)?)),
        _ => None,
    };
    let animated = job.slot.filter(|_| !plan.animation.is_empty());
    let shown_as_tile = matches!(tile, Some((_, None)));
    let (files, pictured) = plan.frame_work;
    let picture = if plan.stills.is_some() || animated.is_some() || shown_as_tile || pictured {
        Some(model.picture(&job.frame)?)
    } else {
        None
    };
    if let (Some(series), Some(p)) = (plan.stills, &picture) {
        let stem = plan.numbering.stem(series, index);
        paths.extend(kinds.picture(Product::FramePicture, &p.pixels(), dir, &stem)?);
    }
    let label = model.label(&job.frame);
    if let (Some((n, own)), Some((montage, rgb))) = (tile, &plan.montage) {
        let drawn = match (&own, &picture) {
            (Some(own), _) => own.pixels().rgb(),
            (None, Some(p)) => p.pixels().rgb(),
            (None, None) => bail!("a montage tile was not drawn"),
        };
        let mut rgb = rgb.lock().map_err(|_| anyhow!("a drawing stopped"))?;
        let (width, _) = montage.size();
        paste_rgb(&mut rgb, width, montage.tile_box(n), &drawn)?;
    }
    if let (Some(slot), Some(p)) = (animated, &picture) {
        for animation in &plan.animation {
            animation.frame(slot, &p.pixels(), &label)?;
        }
    }
    let measure = if files {
        let (own, measure) =
            model.frame_files(&job.frame, job.position, picture, plan.numbering)?;
        paths.extend(own);
        measure.map(|m| (job.position, m))
    } else {
        None
    };
    Ok((paths, job.tile.map(|_| label), measure))
}
