//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model has a module; [`write()`] picks it by the preset's
//! model. Writers read their records in passes over a [`Records`] source
//! (the stream file, read back frame by frame), one frame or day at a
//! time, so their memory is that of a frame and a picture, never that of
//! the stream.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, mpsc};

use anyhow::{Result, anyhow, bail};
use morphogen::preset::{Model, Preset};
use morphogen_scenario::Scenario;
use tiny_skia::Pixmap;

use self::animation::{AnimationWriter, Pixels};
use crate::records::Records;

pub mod animation;
pub mod body;
pub mod bones;
pub mod chart;
pub mod curve;
pub mod fill;
pub mod horn;
pub mod mesh;
pub mod mosaic;
pub mod normals;
pub mod numbered;
pub mod picture;
pub mod plant;
pub mod raster;
pub mod shell;
pub mod surface;
pub mod text;
pub mod tip_bend;
mod vector;

/// A kind of output file `run --only` selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Still pictures and chart bitmaps (`*.png` but `animation.png`).
    Png,
    /// Wavefront meshes (`*.obj`, with their `.mtl`).
    Obj,
    /// The binary glTF scene `model.glb`.
    Glb,
    /// The animated PNG `animation.png`.
    Anim,
    /// Charts as SVG.
    Svg,
    /// Tables (`*.csv`).
    Csv,
    /// `records.jsonl`.
    Jsonl,
}

impl Kind {
    /// Every kind, in the order `--only` lists them.
    pub const ALL: [Kind; 7] = [
        Kind::Png,
        Kind::Obj,
        Kind::Glb,
        Kind::Anim,
        Kind::Svg,
        Kind::Csv,
        Kind::Jsonl,
    ];

    /// The name `--only` knows it by.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Png => "png",
            Kind::Obj => "obj",
            Kind::Glb => "glb",
            Kind::Anim => "anim",
            Kind::Svg => "svg",
            Kind::Csv => "csv",
            Kind::Jsonl => "jsonl",
        }
    }

    const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// The kinds of output file a run writes (`stream.bin` always, and the
/// small text summaries `summary.txt` and `mask.pbm` with any kind).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Kinds(u8);

impl fmt::Debug for Kinds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Kind::ALL
            .iter()
            .filter(|k| self.has(**k))
            .map(|k| k.name())
            .collect();
        write!(f, "Kinds({})", names.join(","))
    }
}

impl Kinds {
    /// Every kind: a run without `--only`.
    pub const ALL: Kinds = Kinds(0x7f);

    /// Files of `kind` only.
    #[must_use]
    pub const fn only(kind: Kind) -> Kinds {
        Kinds(kind.bit())
    }

    /// The kinds of a comma-separated list (`png,obj`).
    ///
    /// # Errors
    /// When a name is not a kind's (the error lists the allowed ones) or
    /// the list is empty.
    pub fn parse(list: &str) -> Result<Kinds> {
        let mut bits = 0u8;
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let Some(kind) = Kind::ALL.iter().find(|k| k.name() == name) else {
                let allowed: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
                bail!(
                    "--only: unknown output kind '{name}' (allowed: {})",
                    allowed.join(", ")
                );
            };
            bits |= kind.bit();
        }
        if bits == 0 {
            bail!("--only needs at least one output kind");
        }
        Ok(Kinds(bits))
    }

    /// Whether files of `kind` are written.
    #[must_use]
    pub const fn has(self, kind: Kind) -> bool {
        self.0 & kind.bit() != 0
    }
}

/// Writes `chart` as `STEM.png` and `STEM.svg` (those `kinds` asks for),
/// `width` × `height` pixels, and adds their paths to `written`.
///
/// # Errors
/// A file that cannot be written, or a chart that cannot be drawn.
pub fn write_chart(
    chart: &chart::Chart,
    dir: &Path,
    stem: &str,
    (width, height): (u32, u32),
    kinds: Kinds,
    written: &mut Vec<PathBuf>,
) -> Result<()> {
    if kinds.has(Kind::Png) {
        let path = dir.join(format!("{stem}.png"));
        chart::write_png(chart, &path, width, height)?;
        written.push(path);
    }
    if kinds.has(Kind::Svg) {
        let path = dir.join(format!("{stem}.svg"));
        chart::write_svg(chart, &path, width, height)?;
        written.push(path);
    }
    Ok(())
}

/// The most frames an `animation.png` shows: a run with more frames is
/// subsampled evenly (first and last kept), each frame labelled with its
/// own time.
pub const MAX_ANIMATION_FRAMES: usize = 60;

/// Milliseconds each animation frame is shown.
pub const ANIMATION_DELAY_MS: u16 = 200;

/// Which of `count` frames (by position) an animation shows, rising: all
/// of them, or [`MAX_ANIMATION_FRAMES`] spread evenly from the first to
/// the last.
#[must_use]
pub fn animation_frames(count: usize) -> Vec<usize> {
    if count <= MAX_ANIMATION_FRAMES {
        return (0..count).collect();
    }
    let slots = MAX_ANIMATION_FRAMES - 1;
    (0..=slots).map(|i| i * (count - 1) / slots).collect()
}

/// A picture's pixels as RGB bytes (every pixel opaque).
#[must_use]
pub fn rgb_bytes(pixmap: &Pixmap) -> Vec<u8> {
    // Opaque premultiplied pixels are their own RGB.
    let mut rgb = vec![0; 3 * pixmap.pixels().len()];
    let (fours, rest) = pixmap.data().as_chunks::<16>();
    let (out, out_rest) = rgb.as_chunks_mut::<12>();
    for (out, four) in out.iter_mut().zip(fours) {
        let words: [u32; 4] = std::array::from_fn(|k| {
            u32::from_le_bytes([
                four[4 * k],
                four[4 * k + 1],
                four[4 * k + 2],
                four[4 * k + 3],
            ])
        });
        *out = pack_rgb(words);
    }
    let pixels = rest.as_chunks::<4>().0;
    for (out, rgba) in out_rest.as_chunks_mut::<3>().0.iter_mut().zip(pixels) {
        *out = [rgba[0], rgba[1], rgba[2]];
    }
    rgb
}

/// The low three bytes of each of four little-endian words (a pixel's
/// red, green, blue; the high byte is dropped), packed into 12 bytes with
/// three word stores instead of twelve byte stores.
#[must_use]
pub(crate) fn pack_rgb([a, b, c, d]: [u32; 4]) -> [u8; 12] {
    let words = [
        (a & 0x00ff_ffff) | b << 24,
        (b >> 8 & 0xffff) | c << 16,
        (c >> 16 & 0xff) | d << 8,
    ];
    let mut out = [0; 12];
    for (bytes, word) in out.as_chunks_mut::<4>().0.iter_mut().zip(words) {
        *bytes = word.to_le_bytes();
    }
    out
}

/// `depth` as an integer that orders as [`f64::total_cmp`] does: sorting
/// `(depth_key(depth), position)` pairs unstably is the stable sort by
/// depth, on 16-byte items however large the things sorted.
#[must_use]
pub(crate) fn depth_key(depth: f64) -> i64 {
    let bits = depth.to_bits() as i64;
    bits ^ ((((bits >> 63) as u64) >> 1) as i64)
}

/// `x` with at most `decimals` decimals, trailing zeros cut (`2.5`,
/// `3`, `0.08`): a frame label's number.
#[must_use]
pub fn trimmed(x: f64, decimals: usize) -> String {
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

/// Writes `pixmap`, a montage drawn at twice its size (opaque), as an
/// RGB PNG of half that size at `path` ([`picture::half_rgb`]), each
/// label drawn ([`animation::draw_label`]) into the top-left corner of
/// its tile `[x, y, width, height]` of the halved picture.
///
/// # Errors
/// When `pixmap` is less than 2 pixels wide or high, a tile is not
/// inside the halved picture, or the file cannot be written.
pub fn save_montage(pixmap: &Pixmap, labels: &[([u32; 4], String)], path: &Path) -> Result<()> {
    let rgb = picture::half_rgb(pixmap)?;
    save_montage_rgb(rgb, (pixmap.width() / 2, pixmap.height() / 2), labels, path)
}

/// [`save_montage`] of a montage already halved: `rgb`, `pw × ph` RGB
/// pixels row by row.
///
/// # Errors
/// As [`save_montage`].
pub fn save_montage_rgb(
    mut rgb: Vec<u8>,
    (pw, ph): (u32, u32),
    labels: &[([u32; 4], String)],
    path: &Path,
) -> Result<()> {
    for &([x, y, w, h], ref label) in labels {
        if x.checked_add(w).is_none_or(|r| r > pw) || y.checked_add(h).is_none_or(|b| b > ph) {
            bail!("the tile {x},{y} {w}×{h} is outside the {pw}×{ph} picture");
        }
        let origin = [x as usize, y as usize];
        animation::Label::new(w, h, label)?.draw(&mut rgb, pw as usize, origin, Pixels::Rgb);
    }
    picture::save_rgb(pw, ph, &rgb, path)
}

/// Copies `tile`, RGB bytes row by row, into the box `[x, y, w, h]` of
/// `rgb`, a picture `width` RGB pixels wide.
///
/// # Errors
/// When the box is not inside the picture or `tile` is not `w × h`.
pub fn paste_rgb(rgb: &mut [u8], width: u32, [x, y, w, h]: [u32; 4], tile: &[u8]) -> Result<()> {
    let (stride, x, w, h) = (
        3 * width as usize,
        3 * x as usize,
        3 * w as usize,
        h as usize,
    );
    if tile.len() != w * h || x + w > stride || rgb.len() / stride.max(1) < y as usize + h {
        bail!("the tile does not fit the picture");
    }
    let rows = rgb.chunks_exact_mut(stride).skip(y as usize);
    for (row, from) in rows.zip(tile.chunks_exact(w)) {
        row[x..x + w].copy_from_slice(from);
    }
    Ok(())
}

/// An `animation.png` fed by parallel workers: frame `k` may arrive
/// before frame `k − 1` and waits (as its RGB bytes) until the frames
/// before it are written, so only the frames in flight are held.
pub(crate) struct OrderedAnimation {
    state: Mutex<OrderedState>,
}

struct OrderedState {
    writer: Option<AnimationWriter>,
    next: usize,
    waiting: BTreeMap<usize, (Vec<u8>, String)>,
}

impl OrderedAnimation {
    /// An animation of `frames` frames of `width × height` RGB pixels at
    /// `path`.
    pub(crate) fn new(path: &Path, width: u32, height: u32, frames: usize) -> Result<Self> {
        let frames = u32::try_from(frames)?;
        let writer =
            AnimationWriter::new(path, width, height, Pixels::Rgb, frames, ANIMATION_DELAY_MS)?;
        Ok(Self::writing(writer))
    }

    fn writing(writer: AnimationWriter) -> Self {
        OrderedAnimation {
            state: Mutex::new(OrderedState {
                writer: Some(writer),
                next: 0,
                waiting: BTreeMap::new(),
            }),
        }
    }

    /// [`OrderedAnimation::new`] for frames of indices into `palette`
    /// ([`AnimationWriter::indexed`]); `None` when `palette` has more
    /// colours than an indexed animation's labels leave room for.
    pub(crate) fn indexed(
        path: &Path,
        (width, height): (u32, u32),
        palette: &[[u8; 3]],
        frames: usize,
    ) -> Result<Option<Self>> {
        if palette.len() > animation::LabelPalette::MAX_COLOURS {
            return Ok(None);
        }
        let frames = u32::try_from(frames)?;
        let writer =
            AnimationWriter::indexed(path, width, height, palette, frames, ANIMATION_DELAY_MS)?;
        Ok(Some(Self::writing(writer)))
    }

    /// Hands over frame `slot` (0-based among the animation's frames):
    /// its RGB bytes, or its indices for [`OrderedAnimation::indexed`].
    pub(crate) fn frame(&self, slot: usize, rgb: Vec<u8>, label: String) -> Result<()> {
        let mut state = self
            .state
            .lock()
            .map_err(|_| anyhow!("an animation writer stopped"))?;
        state.waiting.insert(slot, (rgb, label));
        loop {
            let next = state.next;
            let Some((rgb, label)) = state.waiting.remove(&next) else {
                return Ok(());
            };
            let writer = state
                .writer
                .as_mut()
                .ok_or_else(|| anyhow!("the animation is finished"))?;
            writer.frame(rgb, &label)?;
            state.next += 1;
        }
    }

    /// Ends the file.
    pub(crate) fn finish(self) -> Result<()> {
        let state = self
            .state
            .into_inner()
            .map_err(|_| anyhow!("an animation writer stopped"))?;
        if !state.waiting.is_empty() {
            bail!("animation frames are missing");
        }
        state
            .writer
            .ok_or_else(|| anyhow!("the animation is finished"))?
            .finish()
    }
}

/// Writes the files natural to `scenario`'s model into `dir`, of the
/// `kinds` given; returns their paths.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    scenario: &Scenario,
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let names: Vec<&str> = scenario.file().mosaic.as_ref().map_or_else(Vec::new, |m| {
        m.types.iter().map(|t| t.name.as_str()).collect()
    });
    scenario.with_preset(|preset| write_preset(preset, &names, records, dir, kinds))
}

/// The inks of the main pictures, for a rig preview in their colours
/// (`--rig WxH`): a mosaic's type colours, an L-system's colour ramp;
/// `None` for the models whose pictures are shaded (the rig keeps its own
/// palette).
#[must_use]
pub fn rig_inks(scenario: &Scenario) -> Option<Vec<[u8; 3]>> {
    scenario.with_preset(|preset| match preset.model {
        Model::Mosaic(p) => Some(p.types.iter().map(|t| t.colour).collect()),
        Model::LSystem(_) => Some((0..=plant::LAST_COLOUR).map(plant::palette).collect()),
        Model::GrowthCurve(_) | Model::Horn(_) | Model::Body(_) | Model::Bones(_) => None,
    })
}

/// [`write`] for the run `preset`, its mosaic's types named `names`.
fn write_preset<R: Records + ?Sized>(
    preset: &Preset<'_>,
    names: &[&str],
    records: &R,
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    match preset.model {
        Model::GrowthCurve(_) => curve::write(records, dir, kinds),
        Model::Horn(p) => horn::write(records, dir, p, kinds),
        Model::LSystem(_) => plant::write(records, dir, kinds),
        Model::Body(p) => {
            let binding = morphogen::body::binding_summary::<
                { morphogen_scenario::body_files::USER_CYLINDERS },
            >(p.model, p.table)
            .ok();
            body::write(preset.name, records, dir, binding, Some(p.table), kinds)
        }
        Model::Bones(p) => bones::write(preset.name, p, records, dir, kinds),
        Model::Mosaic(p) if p.surface.is_some() => shell::write(p, names, records, dir, kinds),
        Model::Mosaic(p) => mosaic::write(p, names, records, dir, kinds),
    }
}

/// Runs `work` on every item `produce` hands to its sender, on rayon's
/// number of threads, while `produce` goes on reading: at most two items
/// a thread are in hand at once. Returns the results in the order the
/// items were handed over, or the first error (of `produce`, else of the
/// first item that failed).
pub(crate) fn pipeline<T, R>(
    produce: impl FnOnce(&mut dyn FnMut(T) -> Result<()>) -> Result<()>,
    work: impl Fn(T) -> Result<R> + Sync,
) -> Result<Vec<R>>
where
    T: Send,
    R: Send,
{
    let threads = rayon::current_num_threads().max(1);
    let (jobs, queue) = mpsc::sync_channel::<(usize, T)>(threads);
    // Shared by the workers: when the last one stops, sending fails.
    let queue = Arc::new(Mutex::new(queue));
    let (done, results) = mpsc::channel::<(usize, Result<R>)>();
    let work = &work;
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let queue = Arc::clone(&queue);
            let done = done.clone();
            scope.spawn(move || {
                loop {
                    let job = match queue.lock() {
                        Ok(queue) => queue.recv(),
                        Err(_) => return,
                    };
                    let Ok((i, item)) = job else { return };
                    if done.send((i, work(item))).is_err() {
                        return;
                    }
                }
            });
        }
        drop(queue);
        drop(done);
        let mut handed = 0usize;
        let produced = produce(&mut |item| {
            jobs.send((handed, item))
                .map_err(|_| anyhow!("the output writers stopped"))?;
            handed += 1;
            Ok(())
        });
        drop(jobs);
        let mut slots: Vec<Option<Result<R>>> = Vec::new();
        slots.resize_with(handed, || None);
        for (i, result) in results {
            if let Some(slot) = slots.get_mut(i) {
                *slot = Some(result);
            }
        }
        produced?;
        slots
            .into_iter()
            .map(|slot| slot.unwrap_or_else(|| Err(anyhow!("an output writer stopped"))))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_montage_is_its_tiles_halved_and_labelled_each_as_a_picture_of_its_own() {
        // Two 160×120 tiles side by side, drawn at twice their size.
        let mut pixmap = Pixmap::new(640, 240).unwrap();
        for (k, p) in pixmap.pixels_mut().iter_mut().enumerate() {
            let v = (k % 640 / 5 + k / 640 / 7) as u8;
            *p = tiny_skia::PremultipliedColorU8::from_rgba(v, 255 - v, v / 2, 255).unwrap();
        }
        let labels = [
            ([0, 0, 160, 120], "day 3".to_string()),
            ([160, 0, 160, 120], "age 6.0 months".to_string()),
        ];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.png");
        save_montage(&pixmap, &labels, &path).unwrap();
        let whole = picture::half_rgb(&pixmap).unwrap();
        let montage = Pixmap::load_png(&path).unwrap();
        for ([x, _, w, h], label) in &labels {
            let (x, w) = (*x as usize, *w as usize);
            let mut tile: Vec<u8> = whole
                .chunks_exact(320 * 3)
                .flat_map(|row| row[x * 3..(x + w) * 3].to_vec())
                .collect();
            animation::draw_label(&mut tile, w as u32, *h, Pixels::Rgb, label).unwrap();
            let shown: Vec<u8> = montage
                .pixels()
                .chunks_exact(320)
                .flat_map(|row| {
                    row[x..x + w]
                        .iter()
                        .flat_map(|p| [p.red(), p.green(), p.blue()])
                })
                .collect();
            assert_eq!(shown, tile, "{label}");
        }
        let outside = [([200, 0, 160, 120], "x".to_string())];
        let e = save_montage(&pixmap, &outside, &path)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "the tile 200,0 160×120 is outside the 320×120 picture");
    }

    #[test]
    fn rgb_bytes_drop_alpha_four_pixels_at_a_time_and_after() {
        // 7 pixels: one packed group of four, three left over.
        let mut pixmap = Pixmap::new(7, 1).unwrap();
        let rgba: Vec<u8> = (0..28u8).map(|b| b.wrapping_mul(37)).collect();
        pixmap.data_mut().copy_from_slice(&rgba);
        let want: Vec<u8> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(rgb_bytes(&pixmap), want);
        assert_eq!(
            pack_rgb([0xff03_0201, 0xee06_0504, 0xdd09_0807, 0xcc0c_0b0a]),
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]
        );
    }

    #[test]
    fn kinds_parse_and_name_the_allowed_ones() {
        let k = Kinds::parse("png,glb").unwrap();
        assert!(k.has(Kind::Png) && k.has(Kind::Glb) && !k.has(Kind::Obj));
        let e = Kinds::parse("png,gif").unwrap_err().to_string();
        assert!(
            e.contains("'gif'") && e.contains("png, obj, glb, anim, svg, csv, jsonl"),
            "{e}"
        );
        assert!(Kind::ALL.iter().all(|k| Kinds::ALL.has(*k)));
    }

    #[test]
    fn animations_keep_at_most_sixty_frames_first_and_last() {
        assert_eq!(animation_frames(3), vec![0, 1, 2]);
        let many = animation_frames(97);
        assert_eq!(many.len(), MAX_ANIMATION_FRAMES);
        assert_eq!((many[0], many[59]), (0, 96));
        assert!(many.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn the_pipeline_keeps_the_order_and_reports_the_first_error() {
        let squares = pipeline(
            |send| (0..100u64).try_for_each(send),
            |i| {
                std::thread::sleep(std::time::Duration::from_micros((100 - i) * 10));
                Ok(i * i)
            },
        )
        .unwrap();
        assert_eq!(squares, (0..100u64).map(|i| i * i).collect::<Vec<_>>());
        let failed = pipeline(
            |send| (0..10u64).try_for_each(send),
            |i| {
                if i % 4 == 3 {
                    Err(anyhow!("item {i}"))
                } else {
                    Ok(i)
                }
            },
        );
        assert_eq!(failed.unwrap_err().to_string(), "item 3");
        let stopped = pipeline::<u64, u64>(
            |send| {
                send(1)?;
                Err(anyhow!("unreadable"))
            },
            Ok,
        );
        assert_eq!(stopped.unwrap_err().to_string(), "unreadable");
    }
}
