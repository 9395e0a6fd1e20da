//! The one writer of a frame model's files (horns, bodies, bones). A
//! model states its products — frame → mesh, frame → picture with its
//! label, frames → montage tiles, run → charts and tables — as a
//! [`FrameModel`]; [`write`] writes every kind `--only` asks for, in two
//! passes over the stream a frame at a time: the survey (the frame count,
//! the common scale, the tables), then the files, drawn by parallel
//! workers and written in order.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Result, anyhow};
use morphogen::stream::Record;

use super::kinds::{Kind, Kinds};
use super::mesh::{self, GlbWriter, Library, ObjStyle, write_frame_obj};
use super::montage::{paste_rgb, save_montage_rgb};
use super::numbered::{FileSeries, Numbering};
use super::picture;
use super::pipeline::pipeline;
use super::slots::{ANIMATION_DELAY_MS, OrderedAnimation, animation_frames};
use crate::records::{Place, Records};

/// A picture as saved: RGB bytes row by row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Rgb {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Red, green and blue of each pixel, row by row.
    pub bytes: Vec<u8>,
}

impl Rgb {
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

/// The meshes' files: the material library beside the frames' OBJ files
/// and the glTF scene.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MeshFiles {
    /// The material library's file name (`horn.mtl`).
    pub library: &'static str,
    /// The glTF scene's name.
    pub scene: String,
    /// Metres per model unit, for glTF.
    pub metres: f32,
}

/// A picture of several frames side by side ([`save_montage_rgb`]), each
/// tile labelled with its frame's label.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Montage {
    /// Its file name (`years.png`).
    pub name: &'static str,
    /// The frames it shows, by position in the stream, rising.
    pub frames: Vec<usize>,
    /// Each tile's size, pixels.
    pub tile: (u32, u32),
    /// Tiles a row.
    pub columns: u32,
    /// The colour where no tile is.
    pub background: [u8; 3],
}

impl Montage {
    /// The whole picture's size.
    fn size(&self) -> (u32, u32) {
        let rows = (self.frames.len() as u32).div_ceil(self.columns).max(1);
        (self.tile.0 * self.columns, self.tile.1 * rows)
    }

    /// The box of tile `n`.
    fn tile_box(&self, n: usize) -> [u32; 4] {
        let n = n as u32;
        let (w, h) = self.tile;
        [n % self.columns * w, n / self.columns * h, w, h]
    }
}

/// What a model makes of its frames, for [`write`].
pub(crate) trait FrameModel: Sync {
    /// One frame, as its records group.
    type Frame: Send + Sync;
    /// Groups records into frames.
    type Framer: Default;

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

    /// Ends the survey: every frame is seen.
    fn surveyed(&mut self) {}

    /// The frame's number in file names (`frame_NNN.obj`).
    fn index(frame: &Self::Frame) -> u32;

    /// Where the meshes go.
    fn mesh_files(&self) -> MeshFiles;

    /// The frame's mesh, for `frame_NNN.obj` and `model.glb`.
    ///
    /// # Errors
    /// When the frame is not a mesh.
    fn mesh(&self, frame: &Self::Frame) -> Result<mesh::Mesh>;

    /// The series of a picture per frame, if the model writes one.
    fn stills(&self) -> Option<FileSeries>;

    /// The size of [`FrameModel::picture`], known after the survey.
    fn picture_size(&self) -> (u32, u32);

    /// The frame's picture: its still and its `animation.png` frame.
    ///
    /// # Errors
    /// When it cannot be drawn.
    fn picture(&self, frame: &Self::Frame) -> Result<Rgb>;

    /// The frame's label in the animation and the montage.
    fn label(&self, frame: &Self::Frame) -> String;

    /// The montage, planned after the survey.
    fn montage(&self) -> Option<Montage>;

    /// The frame's tile in the montage (the `n`-th); `None` when it is
    /// its [`FrameModel::picture`].
    ///
    /// # Errors
    /// When it cannot be drawn.
    fn tile(&self, frame: &Self::Frame, n: usize) -> Result<Option<Rgb>>;

    /// The run's own files, once the frames' are written: charts,
    /// tables, summaries. `montage` is whether the montage was written.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn close(self, dir: &Path, kinds: Kinds, montage: bool) -> Result<Vec<PathBuf>>;
}

/// A frame's work for the drawing workers.
struct Job<F> {
    frame: F,
    mesh: Option<mesh::Mesh>,
    slot: Option<usize>,
    tile: Option<usize>,
}

/// The files a run's frames make together, planned after the survey.
struct Plan<'a> {
    dir: &'a Path,
    numbering: Numbering,
    library: &'static str,
    stills: Option<FileSeries>,
    /// The frames the animation shows (by position), and it.
    picked: Vec<usize>,
    animation: Option<OrderedAnimation>,
    montage: Option<(Montage, Mutex<Vec<u8>>)>,
}

impl<'a> Plan<'a> {
    /// The plan for `count` frames of `model`, those files of `kinds`.
    fn new<M: FrameModel>(model: &M, count: usize, dir: &'a Path, kinds: Kinds) -> Result<Self> {
        let picked = if kinds.has(Kind::Anim) && count > 1 {
            animation_frames(count)
        } else {
            Vec::new()
        };
        let animation = if picked.is_empty() {
            None
        } else {
            let (w, h) = model.picture_size();
            let path = dir.join(ANIMATION);
            Some(OrderedAnimation::new(&path, w, h, picked.len())?)
        };
        let montage = model.montage().filter(|_| kinds.has(Kind::Png)).map(|m| {
            let (w, h) = m.size();
            let rgb = m.background.repeat((w * h) as usize);
            (m, Mutex::new(rgb))
        });
        Ok(Plan {
            dir,
            numbering: Numbering::frames(count),
            library: model.mesh_files().library,
            stills: model.stills().filter(|_| kinds.has(Kind::Png)),
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
        let work = mesh.is_some() || self.stills.is_some() || slot.is_some() || tile.is_some();
        work.then_some(Job {
            frame,
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
            let path = self.dir.join(montage.name);
            save_montage_rgb(rgb, montage.size(), &labels, &path)?;
            written.push(path);
        }
        if let Some(animation) = self.animation {
            animation.finish()?;
            written.push(self.dir.join(ANIMATION));
        }
        Ok(written)
    }
}

/// The animation's file name.
const ANIMATION: &str = "animation.png";

/// Writes `model`'s files of `kinds` from `records` into `dir`; returns
/// their paths.
///
/// # Errors
/// A malformed stream, unreadable records, or a file that cannot be
/// written.
pub(crate) fn write<M: FrameModel, R: Records + ?Sized>(
    mut model: M,
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let count = survey(&mut model, records)?;
    let plan = Plan::new(&model, count, dir, kinds)?;
    let files = model.mesh_files();
    let mut glb = kinds
        .has(Kind::Glb)
        .then(|| GlbWriter::new(&files.scene, files.metres));
    let mut library = Library::new(dir, files.library);
    let (model_ref, plan_ref) = (&model, &plan);
    let done: Vec<(Vec<PathBuf>, Option<String>)> = pipeline(
        |send| {
            let mut framer = M::Framer::default();
            let mut position = 0usize;
            records.visit(Place::START, |_, r| {
                let Some(frame) = M::push(&mut framer, r)? else {
                    return Ok(());
                };
                let meshes = kinds.has(Kind::Obj) || glb.is_some();
                let mesh = meshes.then(|| model_ref.mesh(&frame)).transpose()?;
                if let (Some(glb), Some(m)) = (&mut glb, &mesh) {
                    let seconds = position as f32 * f32::from(ANIMATION_DELAY_MS) / 1000.0;
                    glb.push_frame(m, seconds)?;
                }
                let mesh = mesh.filter(|_| kinds.has(Kind::Obj));
                if let Some(m) = &mesh {
                    library.write_once(m)?;
                }
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
    let (paths, labels): (Vec<_>, Vec<_>) = done.into_iter().unzip();
    let mut written: Vec<PathBuf> = paths.into_iter().flatten().collect();
    written.extend(library.written());
    if let Some(glb) = glb {
        let path = dir.join("model.glb");
        glb.write(&path)?;
        written.push(path);
    }
    let montage = plan.montage.is_some();
    written.extend(plan.finish(labels.into_iter().flatten().collect())?);
    written.extend(model.close(dir, kinds, montage)?);
    Ok(written)
}

/// The first pass: every frame surveyed; returns how many there are.
fn survey<M: FrameModel, R: Records + ?Sized>(model: &mut M, records: &R) -> Result<usize> {
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
    model.surveyed();
    Ok(count)
}

/// One frame's files (its OBJ and still), its animation frame and its
/// montage tile; returns the files' paths and, for a tile, its label.
fn frame_files<M: FrameModel>(
    model: &M,
    plan: &Plan<'_>,
    job: Job<M::Frame>,
) -> Result<(Vec<PathBuf>, Option<String>)> {
    let index = M::index(&job.frame);
    let mut paths = Vec::with_capacity(2);
    if let Some(m) = &job.mesh {
        let path = plan
            .dir
            .join(plan.numbering.name(FileSeries::FRAMES, index));
        write_frame_obj(&path, m, ObjStyle::PLAIN, plan.library)?;
        paths.push(path);
    }
    let tile = match (&plan.montage, job.tile) {
        (Some(_), Some(n)) => Some((n, model.tile(&job.frame, n)?)),
        _ => None,
    };
    let animated = plan.animation.as_ref().zip(job.slot);
    let shown_as_tile = matches!(tile, Some((_, None)));
    let picture = if plan.stills.is_some() || animated.is_some() || shown_as_tile {
        Some(model.picture(&job.frame)?)
    } else {
        None
    };
    if let (Some(series), Some(p)) = (plan.stills, &picture) {
        let path = plan.dir.join(plan.numbering.name(series, index));
        picture::save_rgb(p.width, p.height, &p.bytes, &path)?;
        paths.push(path);
    }
    let label = model.label(&job.frame);
    if let (Some((n, own)), Some((montage, rgb))) = (tile, &plan.montage) {
        let drawn = own.as_ref().or(picture.as_ref());
        let drawn = drawn.ok_or_else(|| anyhow!("a montage tile was not drawn"))?;
        let mut rgb = rgb.lock().map_err(|_| anyhow!("a drawing stopped"))?;
        let (width, _) = montage.size();
        paste_rgb(&mut rgb, width, montage.tile_box(n), &drawn.bytes)?;
    }
    if let (Some((animation, slot)), Some(p)) = (animated, picture) {
        animation.frame(slot, p.bytes, label.clone())?;
    }
    Ok((paths, job.tile.map(|_| label)))
}
