//! Morphogen in the browser: the scenario crate and its one run
//! function, [`morphogen_scenario::run::run`] — the same the CLI calls, so a
//! stream here is the fixtures' bytes — compiled to WebAssembly with
//! wasm-bindgen. A run's records are turned into flat arrays (lines,
//! triangles, points) that the page hands to three.js; `docs/web.md`
//! describes the page.
//!
//! Everything the page calls is a thin `#[wasm_bindgen]` wrapper over plain
//! Rust ([`Scenario`]'s inner functions, [`geometry`]), which the native
//! tests exercise.
#![forbid(unsafe_code)]

use std::mem;

use morphogen::fx::Fx;
use morphogen::preset::Model;
use morphogen::sim::Progress;
use morphogen::stream::{Encoder, Record, Sink, SinkError};
use morphogen_scenario::Scenario as Loaded;
use serde::Serialize;
use wasm_bindgen::prelude::*;

/// The most bytes a stream may have in the page, as the CLI's default cap
/// (`--max-stream-mb 128`): past it the run stops with an error naming it.
pub const MAX_STREAM_BYTES: u64 = 128 << 20;

/// The built-in presets as a JSON list of `{name, summary, seed, model,
/// mcu}`, in `morphogen list` order.
#[wasm_bindgen]
#[must_use]
pub fn presets() -> String {
    let list: Vec<Info> = morphogen_scenario::builtins().iter().map(info).collect();
    json(&list)
}

/// `value` as JSON: plain data (structs of numbers, strings and lists,
/// no maps), which serde_json always serialises.
#[allow(
    clippy::expect_used,
    reason = "serde_json fails only on maps with non-string keys, and these types have none"
)]
fn json(value: &impl serde::Serialize) -> String {
    serde_json::to_string(value).expect("plain data serialises")
}

/// What the page shows of a scenario.
#[derive(Debug, Serialize)]
struct Info {
    name: String,
    summary: String,
    seed: u64,
    /// `curve`, `horn`, `lsystem`, `mosaic`, `surface-mosaic`, `body` or
    /// `bones`.
    model: &'static str,
    /// Whether it fits the MCU ([`morphogen::preset::Model::fits_mcu`]).
    mcu: bool,
    /// A mosaic's cell-type colours (RGB), by type index.
    colours: Vec<[i64; 3]>,
}

fn info(s: &Loaded) -> Info {
    let model = s.with_preset(|p| match p.model {
        Model::GrowthCurve(_) => "curve",
        Model::Horn(_) => "horn",
        Model::LSystem(_) => "lsystem",
        Model::Body(_) => "body",
        Model::Bones(_) => "bones",
        Model::Mosaic(m) if m.surface.is_some() => "surface-mosaic",
        Model::Mosaic(_) => "mosaic",
    });
    Info {
        name: s.name().to_string(),
        summary: s.summary().to_string(),
        seed: s.seed(),
        model,
        mcu: s.with_preset(|p| p.model.fits_mcu()),
        colours: s
            .file()
            .mosaic
            .as_ref()
            .map(|m| m.types.iter().map(|t| t.colour).collect())
            .unwrap_or_default(),
    }
}

/// One control of the page: a number of the scenario, its range and what
/// `docs/scenarios.md` says of it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Control {
    /// The dotted key, as `--set` takes it.
    pub key: String,
    /// The scenario's value.
    pub value: f64,
    /// The lowest value allowed.
    pub min: f64,
    /// The highest value allowed.
    pub max: f64,
    /// Whether only whole numbers are allowed.
    pub whole: bool,
    /// The meaning column of the key's row in `docs/scenarios.md`.
    pub doc: String,
}

/// The scenario reference, whose tables document every key.
const SCENARIOS_MD: &str = include_str!("../../../docs/scenarios.md");

/// The meaning `docs/scenarios.md` gives `key` (`horn.modules[2].bend` is
/// the row `modules[i].bend` of the `[horn]` section), or "".
#[must_use]
pub fn doc(key: &str) -> String {
    let Some((table, rest)) = key.split_once('.') else {
        return String::new();
    };
    // `modules[2].bend` → `modules[i].bend`.
    let mut generic = String::new();
    let mut digits = false;
    for c in rest.chars() {
        if c.is_ascii_digit() {
            if !digits {
                generic.push('i');
            }
            digits = true;
        } else {
            digits = false;
            generic.push(c);
        }
    }
    let heading = format!("## `[{table}]`");
    let Some(start) = SCENARIOS_MD.find(&heading) else {
        return String::new();
    };
    let section = &SCENARIOS_MD[start + heading.len()..];
    let section = &section[..section.find("\n## ").unwrap_or(section.len())];
    for row in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = row.trim_matches('|').split(" | ").collect();
        let keys = cells[0].split(", ").map(|k| k.trim().trim_matches('`'));
        if keys.into_iter().any(|k| k == generic || k == rest) {
            return cells.last().map_or(String::new(), |c| c.trim().to_string());
        }
    }
    String::new()
}

/// The controls of `s`: every number it checks whose key a `--set` can
/// change on its own (not one element of a list such as `domain.size[0]`),
/// each once.
#[must_use]
pub fn controls(s: &Loaded) -> Vec<Control> {
    let ranges = s.ranges();
    ranges
        .iter()
        .filter(|r| !r.key.ends_with(']'))
        .filter(|r| ranges.iter().filter(|o| o.key == r.key).count() == 1)
        .map(|r| Control {
            key: r.key.clone(),
            value: r.value,
            min: r.lo,
            max: r.hi,
            whole: r.whole,
            doc: doc(&r.key),
        })
        .collect()
}

/// The value of the file key `key` (a `--set`: `mosaic.mask`,
/// `bones.grammar`, …) that holds the opened file `name`'s `bytes` inline
/// ([`morphogen_scenario::inline_value`]: a mask as a PBM, other files as
/// text, named `name` in messages).
///
/// # Errors
/// A mask that is neither a PBM nor a PNG or is past the mask's limits, or
/// text that is not UTF-8.
#[wasm_bindgen(js_name = fileValue)]
pub fn file_value(key: &str, name: &str, bytes: &[u8]) -> Result<String, JsError> {
    morphogen_scenario::inline_value(key, name, bytes.to_vec()).map_err(js_error)
}

/// A finished run: its digest, frames and every byte of its stream.
#[wasm_bindgen]
#[derive(Debug)]
pub struct RunResult {
    digest: u64,
    frames: u32,
    stream: Vec<u8>,
}

#[wasm_bindgen]
impl RunResult {
    /// CRC-64/XZ of the stream as 16 hex digits (`stream_digest` of a
    /// fixture's `summary.toml`).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn digest(&self) -> String {
        format!("{:016x}", self.digest)
    }

    /// Frames (= records) written.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The stream's bytes, as `stream.bin` holds them.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn stream(&self) -> Vec<u8> {
        self.stream.clone()
    }
}

/// The sink of a run: the encoder, and the records of the frame being
/// written, handed to `shown` as a [`Frame`] when `due` says so (and the
/// last frame always, by [`Live::finish`]).
struct Live<'a> {
    encoder: Encoder<Vec<u8>>,
    past_cap: bool,
    start: (u32, Fx),
    records: Vec<Record>,
    /// The last whole frame, when it was not shown.
    unshown: Option<((u32, Fx), Vec<Record>)>,
    /// The mesh (vertices and triangles) of the last frame that had one: a
    /// surface mosaic streams it once, in its first frame, and it is drawn
    /// under the cells of every later frame.
    mesh: Vec<Record>,
    due: &'a mut dyn FnMut() -> bool,
    shown: &'a mut dyn FnMut(Frame),
}

impl Sink for Live<'_> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        self.encoder.record(record)?;
        if self.encoder.bytes() > MAX_STREAM_BYTES {
            self.past_cap = true;
            return Err(SinkError::Write);
        }
        match record {
            Record::FrameStart { frame, time } => {
                self.start = (*frame, *time);
                self.records.clear();
            }
            Record::FrameEnd { .. } => {
                let records = self.with_mesh();
                if (self.due)() {
                    self.unshown = None;
                    (self.shown)(geometry(self.start.0, self.start.1, &records));
                } else {
                    self.unshown = Some((self.start, records));
                }
            }
            Record::Header(_) | Record::Extent { .. } => {}
            r => self.records.push(r.clone()),
        }
        Ok(())
    }
}

impl Live<'_> {
    /// The frame's records, after the last mesh when the frame has surface
    /// cells but no mesh of its own (a surface mosaic's later days).
    fn with_mesh(&mut self) -> Vec<Record> {
        let records = mem::take(&mut self.records);
        let is_mesh = |r: &Record| matches!(r, Record::MeshVertex { .. } | Record::Triangle { .. });
        if records.iter().any(is_mesh) {
            self.mesh = records.iter().filter(|r| is_mesh(r)).cloned().collect();
            records
        } else if records
            .iter()
            .any(|r| matches!(r, Record::SurfaceCell { .. }))
        {
            self.mesh.iter().cloned().chain(records).collect()
        } else {
            records
        }
    }

    /// Shows the last frame if it was not, and gives the run's result.
    fn finish(self, ran: Result<(), morphogen::Error>) -> Result<RunResult, String> {
        match ran {
            Err(morphogen::Error::Sink(SinkError::Write)) if self.past_cap => {
                return Err(format!(
                    "the stream passed {} MiB and was stopped",
                    MAX_STREAM_BYTES >> 20
                ));
            }
            Err(e) => return Err(e.to_string()),
            Ok(()) => {}
        }
        if let Some(((index, time), records)) = self.unshown {
            (self.shown)(geometry(index, time, &records));
        }
        Ok(RunResult {
            digest: self.encoder.digest(),
            frames: self.encoder.frames(),
            stream: self.encoder.into_writer(),
        })
    }
}

/// Runs `s` with `seed` through [`morphogen_scenario::run::run`]: each
/// frame that ends when `due` says so goes to `shown` as a [`Frame`] (and
/// the last one always), progress to `progress`.
///
/// # Errors
/// The core's error, or the stream's cap.
pub fn run(
    s: &Loaded,
    seed: u64,
    due: &mut dyn FnMut() -> bool,
    shown: &mut dyn FnMut(Frame),
    progress: &mut dyn FnMut(Progress),
) -> Result<RunResult, String> {
    let mut live = Live {
        encoder: Encoder::new(Vec::new()),
        past_cap: false,
        start: (0, Fx::ZERO),
        records: Vec::new(),
        unshown: None,
        mesh: Vec::new(),
        due,
        shown,
    };
    let ran = s.with_preset(|p| morphogen_scenario::run::run(p, seed, &mut live, progress));
    live.finish(ran).map_err(|e| format!("{}: {e}", s.name()))
}

/// One frame as flat arrays for three.js, in model units.
#[wasm_bindgen]
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Frame {
    index: u32,
    time: f64,
    lines: Vec<f32>,
    line_colours: Vec<u16>,
    triangles: Vec<f32>,
    triangle_colours: Vec<u16>,
    points: Vec<f32>,
    point_kinds: Vec<u8>,
    chart: bool,
}

#[wasm_bindgen]
impl Frame {
    /// The frame's index.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn index(&self) -> u32 {
        self.index
    }

    /// Model time at its start (days or years).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Segments (and curves' samples joined), x y z x y z each.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn lines(&self) -> Vec<f32> {
        self.lines.clone()
    }

    /// Each segment's colour-map index (a curve's series).
    #[wasm_bindgen(getter, js_name = lineColours)]
    #[must_use]
    pub fn line_colours(&self) -> Vec<u16> {
        self.line_colours.clone()
    }

    /// Triangles of polygons, meshes and swept rings, three x y z each.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn triangles(&self) -> Vec<f32> {
        self.triangles.clone()
    }

    /// Each triangle's colour: a polygon's colour-map index, a ring's
    /// module, 0 for a mesh.
    #[wasm_bindgen(getter, js_name = triangleColours)]
    #[must_use]
    pub fn triangle_colours(&self) -> Vec<u16> {
        self.triangle_colours.clone()
    }

    /// Cells (a plane mosaic's at z = 0) and loose points, x y z each.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn points(&self) -> Vec<f32> {
        self.points.clone()
    }

    /// Each point's cell type (255 for a loose point).
    #[wasm_bindgen(getter, js_name = pointKinds)]
    #[must_use]
    pub fn point_kinds(&self) -> Vec<u8> {
        self.point_kinds.clone()
    }

    /// Whether only curve samples are drawn (a chart, to be stretched).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn chart(&self) -> bool {
        self.chart
    }
}

/// A 16.16 value as `f32` (exact below 2^8 in magnitude, the nearest
/// above: a picture, not a stream).
#[allow(clippy::cast_precision_loss)]
fn f(v: Fx) -> f32 {
    v.to_bits() as f32 / 65_536.0
}

fn p3(p: &[Fx; 3]) -> [f32; 3] {
    [f(p[0]), f(p[1]), f(p[2])]
}

/// Points a [`Record::Polygon`] or [`Record::Ring`] still announces.
enum Run {
    Polygon(u16, usize),
    Ring(u16, usize),
}

/// A frame's records as flat arrays: polygons fanned, consecutive rings of
/// one module with as many points joined into a band (as
/// `morphogen horn`'s mesh), mesh triangles by their vertices' ids, curve
/// samples of a series joined in order (docs/stream-format.md).
#[must_use]
pub fn geometry(index: u32, time: Fx, records: &[Record]) -> Frame {
    let mut g = Frame {
        index,
        time: f64::from(time.to_bits()) / 65_536.0,
        chart: records.iter().all(|r| matches!(r, Record::Sample { .. })),
        ..Frame::default()
    };
    let mut run: Option<Run> = None;
    let mut run_points: Vec<[f32; 3]> = Vec::new();
    let mut last_ring: Option<(u16, Vec<[f32; 3]>)> = None;
    let mut vertices: Vec<[f32; 3]> = Vec::new();
    let mut samples: Vec<Option<[f32; 2]>> = Vec::new();
    for r in records {
        match r {
            Record::Point { p } => {
                let Some(open) = &mut run else {
                    g.points.extend(p3(p));
                    g.point_kinds.push(255);
                    continue;
                };
                run_points.push(p3(p));
                let (Run::Polygon(_, left) | Run::Ring(_, left)) = open;
                *left -= 1;
                if *left > 0 {
                    continue;
                }
                match run.take() {
                    Some(Run::Polygon(colour, _)) => {
                        for i in 1..run_points.len().saturating_sub(1) {
                            g.triangle([run_points[0], run_points[i], run_points[i + 1]], colour);
                        }
                    }
                    Some(Run::Ring(module, _)) => {
                        if let Some((m, prev)) = &last_ring
                            && *m == module
                            && prev.len() == run_points.len()
                        {
                            let n = prev.len();
                            for i in 0..n {
                                let j = (i + 1) % n;
                                g.triangle([prev[i], prev[j], run_points[i]], module);
                                g.triangle([prev[j], run_points[j], run_points[i]], module);
                            }
                        }
                        last_ring = Some((module, run_points.clone()));
                    }
                    None => {}
                }
                run_points.clear();
            }
            Record::Polygon {
                vertices: n,
                colour,
            } if *n > 0 => run = Some(Run::Polygon(*colour, usize::from(*n))),
            Record::Ring { module, points, .. } if *points > 0 => {
                run = Some(Run::Ring(*module, usize::from(*points)));
            }
            Record::Segment { a, b, colour, .. } => {
                g.lines.extend(p3(a));
                g.lines.extend(p3(b));
                g.line_colours.push(*colour);
            }
            Record::MeshVertex { id, p } => {
                let id = *id as usize;
                if vertices.len() <= id {
                    vertices.resize(id + 1, [0.0; 3]);
                }
                vertices[id] = p3(p);
            }
            Record::Triangle { v } => {
                let corner = |i: u32| vertices.get(i as usize).copied();
                if let (Some(a), Some(b), Some(c)) = (corner(v[0]), corner(v[1]), corner(v[2])) {
                    g.triangle([a, b, c], 0);
                }
            }
            Record::Cell { kind, p, .. } => {
                g.points.extend([f(p[0]), f(p[1]), 0.0]);
                g.point_kinds.push(*kind);
            }
            Record::SurfaceCell { kind, p, .. } => {
                g.points.extend(p3(p));
                g.point_kinds.push(*kind);
            }
            Record::Sample { series, x, y } => {
                let s = usize::from(*series);
                if samples.len() <= s {
                    samples.resize(s + 1, None);
                }
                let here = [f(*x), f(*y)];
                if let Some(before) = samples[s] {
                    g.lines
                        .extend([before[0], before[1], 0.0, here[0], here[1], 0.0]);
                    g.line_colours.push(*series);
                }
                samples[s] = Some(here);
            }
            _ => {}
        }
    }
    g
}

impl Frame {
    fn triangle(&mut self, corners: [[f32; 3]; 3], colour: u16) {
        for c in corners {
            self.triangles.extend(c);
        }
        self.triangle_colours.push(colour);
    }
}

fn js_error(message: String) -> JsError {
    JsError::new(&message)
}

/// A scenario loaded in the page: a built-in preset or a TOML file, with
/// the parameter changes applied.
#[wasm_bindgen]
#[derive(Debug)]
pub struct Scenario {
    inner: Loaded,
}

#[wasm_bindgen]
impl Scenario {
    /// The built-in preset `name`.
    ///
    /// # Errors
    /// An unknown name, with the closest preset's.
    pub fn preset(name: &str) -> Result<Scenario, JsError> {
        morphogen_scenario::builtin(name)
            .map(|inner| Scenario { inner })
            .ok_or_else(|| {
                let close = morphogen_scenario::closest_builtin(name)
                    .map(|c| format!(" (did you mean {c}?)"))
                    .unwrap_or_default();
                js_error(format!("no preset named {name}{close}"))
            })
    }

    /// A scenario from the text of a TOML file whose named files are all
    /// inline (as `morphogen` writes a scenario out).
    ///
    /// # Errors
    /// Its first bad value, with its line and key.
    #[wasm_bindgen(js_name = fromToml)]
    pub fn from_toml(text: &str) -> Result<Scenario, JsError> {
        Loaded::from_text("scenario.toml", text)
            .map(|inner| Scenario { inner })
            .map_err(|e| js_error(e.to_string()))
    }

    /// The same scenario with `keys[i] = values[i]` set (dotted keys, as
    /// `--set`).
    ///
    /// # Errors
    /// The first bad value.
    #[wasm_bindgen(js_name = withSets)]
    pub fn with_sets(&self, keys: Vec<String>, values: Vec<String>) -> Result<Scenario, JsError> {
        let sets: Vec<(String, String)> = keys.into_iter().zip(values).collect();
        self.inner
            .clone_with_sets(&sets)
            .map(|inner| Scenario { inner })
            .map_err(|e| js_error(e.to_string()))
    }

    /// `{name, summary, seed, model, mcu, colours}` as JSON.
    #[must_use]
    pub fn info(&self) -> String {
        json(&info(&self.inner))
    }

    /// The [`controls`] as a JSON list of `{key, value, min, max, whole,
    /// doc}`.
    #[must_use]
    pub fn controls(&self) -> String {
        json(&controls(&self.inner))
    }

    /// The scenario as one TOML file, the changes applied and every named
    /// file inline.
    #[must_use]
    pub fn toml(&self) -> String {
        self.inner.self_contained()
    }

    /// Runs with `seed`, showing nothing: the digest, frames and stream;
    /// `on_progress(done, total)`, when given, is called at most every
    /// `every_ms` milliseconds (and at the end), as [`Scenario::run`] does.
    ///
    /// # Errors
    /// The core's error, or the stream's cap.
    pub fn digest(
        &self,
        seed: u64,
        every_ms: Option<f64>,
        on_progress: Option<js_sys::Function>,
    ) -> Result<RunResult, JsError> {
        let mut progress = throttled(every_ms.unwrap_or(0.0), on_progress);
        run(&self.inner, seed, &mut || false, &mut |_| {}, &mut progress).map_err(js_error)
    }

    /// Runs with `seed`, calling `on_frame(frame)` with a whole [`Frame`]
    /// at most every `every_ms` milliseconds (and with the last frame), and
    /// `on_progress(done, total)` as often.
    ///
    /// # Errors
    /// The core's error, or the stream's cap.
    pub fn run(
        &self,
        seed: u64,
        every_ms: f64,
        on_frame: &js_sys::Function,
        on_progress: &js_sys::Function,
    ) -> Result<RunResult, JsError> {
        let mut frame_at = f64::NEG_INFINITY;
        let mut due = || {
            let now = js_sys::Date::now();
            let due = now - frame_at >= every_ms;
            if due {
                frame_at = now;
            }
            due
        };
        let mut shown = |frame: Frame| {
            // A callback that throws only loses a picture.
            let _ = on_frame.call1(&JsValue::NULL, &JsValue::from(frame));
        };
        let mut progress = throttled(every_ms, Some(on_progress.clone()));
        run(&self.inner, seed, &mut due, &mut shown, &mut progress).map_err(js_error)
    }
}

/// `on_progress(done, total)` at most every `every_ms` milliseconds and at
/// the end; nothing without a callback.
fn throttled(every_ms: f64, on_progress: Option<js_sys::Function>) -> impl FnMut(Progress) {
    let mut progress_at = f64::NEG_INFINITY;
    move |p: Progress| {
        let Some(on_progress) = &on_progress else {
            return;
        };
        let now = js_sys::Date::now();
        if now - progress_at >= every_ms || p.finished() {
            progress_at = now;
            // A callback that throws only loses a report.
            let _ = on_progress.call2(
                &JsValue::NULL,
                &JsValue::from(p.done),
                &JsValue::from(p.total),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture_digest(name: &str) -> (u64, String) {
        let path = format!(
            "{}/../../fixtures/{name}/summary.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(path).expect("fixture summary");
        let field = |k: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(&format!("{k} = ")))
                .expect("field")
                .trim_matches('"')
                .to_string()
        };
        (field("seed").parse().expect("seed"), field("stream_digest"))
    }

    #[test]
    fn digests_and_frames_match_the_fixtures() {
        for name in ["growth-curve", "ram-horn", "abop-2d-plant", "croton-mcu"] {
            let s = morphogen_scenario::builtin(name).expect("preset");
            let (seed, want) = fixture_digest(name);
            let mut frames = Vec::new();
            let run =
                run(&s, seed, &mut || true, &mut |f| frames.push(f), &mut |_| {}).expect("runs");
            assert_eq!(format!("{:016x}", run.digest), want, "{name}");
            assert_eq!(
                morphogen::stream::StreamDigest::of(&run.stream),
                run.digest,
                "{name}"
            );
            assert!(!frames.is_empty(), "{name}");
            assert_eq!(
                frames.iter().map(|f| f.index).collect::<Vec<_>>(),
                (0..frames.len() as u32).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn only_the_last_frame_when_none_is_due() {
        let s = morphogen_scenario::builtin("ram-horn").expect("preset");
        let mut frames = Vec::new();
        run(&s, 1, &mut || false, &mut |f| frames.push(f), &mut |_| {}).expect("runs");
        assert_eq!(frames.len(), 1);
        let last = &frames[0];
        assert_eq!(last.index, 15);
        // 16 rings of 24 points... at least one band of two triangles per
        // pair of points, and no loose point.
        assert!(last.triangles.len() >= 9 * 2 * 3);
        assert_eq!(last.triangles.len(), last.triangle_colours.len() * 9);
        assert!(last.points.is_empty());
    }

    #[test]
    fn geometry_of_each_kind() {
        let x = |v: i32| Fx::from_int(v);
        let p = |a, b, c| Record::Point {
            p: [x(a), x(b), x(c)],
        };
        let records = [
            Record::Polygon {
                vertices: 4,
                colour: 3,
            },
            p(0, 0, 0),
            p(1, 0, 0),
            p(1, 1, 0),
            p(0, 1, 0),
            Record::Cell {
                id: 0,
                kind: 2,
                p: [x(5), x(6)],
            },
            Record::Segment {
                a: [x(0); 3],
                b: [x(1); 3],
                width: x(1),
                colour: 7,
            },
            p(9, 9, 9),
        ];
        let g = geometry(4, x(2), &records);
        assert_eq!((g.index, g.time), (4, 2.0));
        assert_eq!(g.triangle_colours, [3, 3]);
        assert_eq!(&g.triangles[9..18], &[0., 0., 0., 1., 1., 0., 0., 1., 0.]);
        assert_eq!(g.points, [5., 6., 0., 9., 9., 9.]);
        assert_eq!(g.point_kinds, [2, 255]);
        assert_eq!(g.line_colours, [7]);
        assert!(!g.chart);
        let samples = [0, 1, 2].map(|i| Record::Sample {
            series: 1,
            x: x(i),
            y: x(i * i),
        });
        let chart = geometry(0, x(0), &samples);
        assert!(chart.chart);
        assert_eq!(
            chart.lines,
            [0., 0., 0., 1., 1., 0., 1., 1., 0., 2., 4., 0.]
        );
    }

    #[test]
    fn controls_carry_ranges_and_docs() {
        let horn = morphogen_scenario::builtin("ram-horn").expect("preset");
        let c = controls(&horn);
        let years = c.iter().find(|c| c.key == "horn.years").expect("years");
        assert!(years.whole && years.min == 1.0 && years.value >= 1.0);
        assert_eq!(years.doc, "years shown");
        let bend = c
            .iter()
            .find(|c| c.key == "horn.modules[0].bend")
            .expect("bend");
        assert_eq!((bend.min, bend.max, bend.whole), (-3600.0, 3600.0, false));
        assert_eq!(bend.doc, "α(T)");
        // Every control's value is allowed, and setting its bound is too.
        for c in &c {
            assert!(c.min <= c.value && c.value <= c.max, "{c:?}");
        }
        let changed = horn
            .clone_with_sets(&[("horn.years".into(), "2".into())])
            .expect("a value in range");
        assert_ne!(digest(&changed), digest(&horn));
    }

    /// The digest of `s`'s run with seed 1.
    fn digest(s: &Loaded) -> u64 {
        run(s, 1, &mut || false, &mut |_| {}, &mut |_| {})
            .expect("runs")
            .digest
    }

    #[test]
    fn a_mask_file_changes_a_mosaic() {
        let croton = morphogen_scenario::builtin("croton-mcu").expect("preset");
        let pbm = b"P1\n4 2\n1 1 0 0\n1 1 0 0\n";
        let value =
            morphogen_scenario::inline_value("mosaic.mask", "m.pbm", pbm.to_vec()).expect("a PBM");
        assert!(value.starts_with("{ text = "), "{value}");
        let masked = croton
            .clone_with_sets(&[("mosaic.mask".into(), value)])
            .expect("a mask in range");
        assert_ne!(digest(&masked), digest(&croton));
    }

    #[test]
    fn a_grammar_file_replaces_a_skeleton() {
        let long_bone = morphogen_scenario::builtin("long-bone").expect("preset");
        let text = include_bytes!("../../../examples/wishbone.lsys");
        let value =
            morphogen_scenario::inline_value("bones.grammar", "wishbone.lsys", text.to_vec())
                .expect("UTF-8");
        let wishbone = long_bone
            .clone_with_sets(&[("bones.grammar".into(), value)])
            .expect("a skeleton grammar");
        assert_ne!(digest(&wishbone), digest(&long_bone));
    }

    #[test]
    fn every_preset_has_info_and_controls() {
        let list: Vec<serde_json::Value> =
            serde_json::from_str(&presets()).expect("presets is JSON");
        assert_eq!(list.len(), morphogen_scenario::builtins().len());
        // Every model, the L-system's from its grammar's constants.
        for s in morphogen_scenario::builtins() {
            assert!(!controls(&s).is_empty(), "{}", s.name());
        }
        let shrub = morphogen_scenario::builtin("abop-shrub").expect("preset");
        let c = controls(&shrub);
        let delta = c.iter().find(|c| c.key == "lsystem.delta").expect("delta");
        assert_eq!((delta.value, delta.whole), (22.5, false));
        assert_eq!(delta.doc, "δ: the turn angle");
        let n = c.iter().find(|c| c.key == "lsystem.n").expect("n");
        assert_eq!((n.value, n.min, n.max, n.whole), (7.0, 0.0, 255.0, true));
        let changed = shrub
            .clone_with_sets(&[("lsystem.delta".into(), "30".into())])
            .expect("a value in range");
        assert_ne!(digest(&changed), digest(&shrub));
    }
}
