//! One face for every model: a [`Model`] is a model's validated parameters,
//! a [`Preset`] names one with a seed, the [`Runner`] holds whichever one is
//! running in one place (a `static` on the MCU), and [`drive`] is the one
//! run loop (header, then steps).
//!
//! The core holds no preset data: built-in presets are the scenario files
//! in `scenarios/` (read by the host at run time, and turned into
//! `static` [`Preset`]s at the firmware's build time).
//!
//! A preset written in Rust, run by the [`Runner`] into an [`Encoder`]
//! (on a device, over a UART; `docs/embedding.md` says when to drive a
//! model directly instead, in a fraction of the Runner's flash and RAM):
//!
//! ```
//! use morphogen::fx::Fx;
//! use morphogen::growth::Sigmoid;
//! use morphogen::growth_curve::Params;
//! use morphogen::preset::{self, Model, Preset, Runner};
//! use morphogen::stream::Encoder;
//!
//! // The horn paper's seasonal growth (Sec. 2) over a year, sampled daily:
//! // the built-in `growth-curve` preset's parameters.
//! static GROWTH_CURVE: Preset<'static> = Preset {
//!     name: "growth-curve",
//!     summary: "",
//!     default_seed: 0,
//!     model: Model::GrowthCurve(Params {
//!         growth: Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), 365),
//!         days: 365,
//!     }),
//! };
//! let mut runner = Runner::new(); // a `static` on a device
//! let mut encoder = Encoder::new(Vec::new());
//! let mut steps = 0;
//! preset::run(&GROWTH_CURVE, 0, &mut runner, &mut encoder, &mut |p| steps = p.done).unwrap();
//! assert_eq!(steps, 366); // days 0 to 365, a step each
//! // The stream of fixtures/growth-curve/summary.toml, byte for byte.
//! assert_eq!(encoder.digest(), 0x3796_d9cd_8193_fce1);
//! ```
//!
//! [`Encoder`]: crate::stream::Encoder

use crate::Error;
use crate::body::{self, Body, BodyParams};
use crate::bones::{Bones, BonesParams, MCU_TRIANGLES, MCU_VERTICES};
use crate::growth_curve::{self, GrowthCurve};
use crate::horn::{Horn, HornParams};
use crate::lsys::LSystem;
#[cfg(feature = "surface-runner")]
use crate::mosaic::SurfaceMosaic;
use crate::mosaic::{
    self, McuMeshStore, McuStore, McuSurfaceStore, Mosaic, Params as MosaicParams,
};
use crate::sim::{Progress, Simulation, Start};
use crate::stream::{FORMAT_VERSION, Header, PresetName, Record, Sink, params_digest};

/// A model and its parameters: what a scenario file describes, checked.
/// Exhaustive: a new model fails to compile wherever one is matched
/// without it.
#[derive(Clone, Copy, Debug)]
pub enum Model<'a> {
    /// The seasonal growth curve (horn paper, Sec. 2).
    GrowthCurve(growth_curve::Params),
    /// A horn from positioners (horn paper).
    Horn(&'a HornParams<'a>),
    /// An L-system grammar (its text: `docs/lsystems.md`), derived
    /// streaming.
    LSystem(&'a str),
    /// A clonal mosaic (MClone).
    Mosaic(&'a MosaicParams<'a>),
    /// A body grown by its table (growth paper).
    Body(&'a BodyParams<'a>),
    /// A bone: an L-system skeleton shrinkwrapped (bones paper).
    Bones(&'a BonesParams<'a>),
}

impl Model<'_> {
    /// The parameter digest the stream header carries (CRC-64/XZ of the
    /// parameters' postcard bytes; an L-system's is its grammar text's).
    #[must_use]
    pub fn params_digest(&self) -> u64 {
        match self {
            Model::GrowthCurve(p) => params_digest(p),
            Model::Horn(p) => params_digest(*p),
            Model::LSystem(grammar) => params_digest(*grammar),
            Model::Mosaic(p) => params_digest(*p),
            Model::Body(p) => params_digest(*p),
            Model::Bones(p) => params_digest(*p),
        }
    }

    /// Whether a run fits the [`Runner`]'s fixed capacity (the MCU's
    /// memory): a mosaic fits when its expected peak cell count
    /// ([`mosaic::expected_peak_cells`]) fits the inline store and it needs
    /// no velocities ([`mosaic::Params::momentum`] 0); on a surface, also
    /// when its mesh fits [`McuMeshStore`] and it has no anisotropy field;
    /// a body when its cylinders fit [`body::MAX_CYLINDERS`], bones when
    /// their grammar streams (not context-sensitive); every other model's state
    /// is bounded by its type (a run that exceeds a limit stops with an
    /// error naming it).
    #[must_use]
    pub fn fits_mcu(&self) -> bool {
        match self {
            Model::Mosaic(p) => {
                let peak = mosaic::expected_peak_cells(p);
                p.momentum == crate::fx::Fx::ZERO
                    && match p.surface {
                        None => peak <= McuStore::CAPACITY as u64,
                        Some(s) => {
                            let (vertices, faces) = s.counts();
                            p.anisotropy.is_none()
                                && vertices <= McuMeshStore::VERTICES
                                && faces <= McuMeshStore::FACES
                                && peak <= McuSurfaceStore::CAPACITY as u64
                        }
                    }
            }
            Model::Body(p) => p.model.cylinders.len() <= body::MAX_CYLINDERS,
            // The MCU derives skeletons streaming: context-free, at most
            // a default `Streaming`'s 32 steps.
            Model::Bones(p) => {
                let mut grammar = crate::lsys::Grammar::new();
                grammar.parse(p.grammar).is_ok() && !grammar.needs_buffer()
            }
            Model::GrowthCurve(_) | Model::Horn(_) | Model::LSystem(_) => true,
        }
    }
}

/// A named scenario: a model with its parameters and a default seed.
#[derive(Clone, Copy, Debug)]
pub struct Preset<'a> {
    /// The name used on the command line and in stream headers.
    pub name: &'a str,
    /// One line for `morphogen list`.
    pub summary: &'a str,
    /// The seed used when none is given.
    pub default_seed: u64,
    /// The model and its parameters.
    pub model: Model<'a>,
}

/// The stream header of a run of `name` with `seed` and the parameter
/// digest `params`.
#[must_use]
pub fn header(name: &str, seed: u64, params: u64) -> Record {
    let mut preset = PresetName::new();
    // Names are checked against the header's capacity when a scenario is
    // read; a longer one is truncated here.
    for c in name.chars() {
        if preset.push(c).is_err() {
            break;
        }
    }
    Record::Header(Header {
        version: FORMAT_VERSION,
        preset,
        seed,
        params,
    })
}

/// The one run loop: writes `header`, then steps `sim` to its end,
/// reporting progress.
///
/// # Errors
/// The first error of the sink or of a step.
pub fn drive(
    sim: &mut dyn Simulation,
    header: &Record,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), Error> {
    sink.record(header)?;
    loop {
        let p = sim.step(sink)?;
        progress(p);
        if p.finished() {
            return Ok(());
        }
    }
}

/// Holds the running simulation, whatever its model, at the fixed capacity
/// of an MCU.
// The runner lives in a `static` and there is no allocator to box its
// variants: each is as big as its model's bounded state, by design.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Default)]
#[non_exhaustive]
// A tag as wide as the payloads' alignment: no padding between them, so
// writing an empty model into the runner is one memset in place (with
// padding in between, the compiler builds the value on the stack first:
// 46 KB for bones).
#[repr(u64)]
pub enum Runner<'a> {
    /// Nothing started.
    #[default]
    Idle,
    /// A growth curve.
    GrowthCurve(GrowthCurve),
    /// A horn.
    Horn(Horn<'a>),
    /// A mosaic, its cells stored inline ([`McuStore`]).
    Mosaic(Mosaic<'a, McuStore>),
    /// A mosaic on a surface, its cells and mesh stored inline
    /// ([`McuSurfaceStore`], [`McuMeshStore`]; feature `surface-runner`).
    #[cfg(feature = "surface-runner")]
    SurfaceMosaic(SurfaceMosaic<'a, McuSurfaceStore, McuMeshStore>),
    /// An L-system, derived streaming.
    LSystem(LSystem),
    /// A body.
    Body(Body<'a>),
    /// A bone.
    Bones(Bones<'a, MCU_VERTICES, MCU_TRIANGLES>),
}

/// The idle models written into the runner when it switches model: `const`
/// items, so that the compiler writes them in place instead of building
/// the model on a small stack first (measured with `llvm-objdump` on
/// thumbv7m: moved to a function of its own per model, the same write once
/// built bones on the stack, a 13.7 KB frame). Every idle model is all zero
/// bytes (uninitialised capacity aside; deferred errors are
/// [`Deferred`](crate::sim::Deferred)), so the write is a memset: a model
/// with one non-zero byte would instead be copied from a constant of its
/// whole size in flash (50 KB for the mosaic).
const IDLE_MOSAIC: Mosaic<'static, McuStore> = Mosaic::new(McuStore::EMPTY);
/// The limit a surface mosaic meets in a [`Runner`] built without the
/// feature `surface-runner`: it runs none.
pub const SURFACE_MOSAICS: &str =
    "surface mosaics a Runner runs (the core's feature `surface-runner`)";

/// An idle mosaic on a surface.
#[cfg(feature = "surface-runner")]
const IDLE_SURFACE_MOSAIC: SurfaceMosaic<'static, McuSurfaceStore, McuMeshStore> =
    SurfaceMosaic::on_mesh(McuSurfaceStore::EMPTY, McuMeshStore::EMPTY);
/// An idle L-system.
const IDLE_LSYSTEM: LSystem = LSystem::new();
/// An idle body.
const IDLE_BODY: Body<'static> = Body::new();
/// An idle bone (its mesh buffers are uninitialised capacity).
const IDLE_BONES: Bones<'static, MCU_VERTICES, MCU_TRIANGLES> = Bones::new();

impl<'a> Runner<'a> {
    /// An idle runner (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Runner<'a> {
        Runner::Idle
    }

    /// Starts `model` with `seed` in place, through the model's [`Start`]
    /// (reusing the state of the same model).
    ///
    /// # Errors
    /// The model's refusal of its parameters (each names the limit or the
    /// parameter); the runner is then idle.
    pub fn start(&mut self, model: &Model<'a>, seed: u64) -> Result<(), Error> {
        /// Switches the runner to `$variant` (idle `$idle`) unless it holds
        /// one, then starts it with `$params`.
        macro_rules! start {
            ($variant:ident, $idle:expr, $params:expr) => {{
                if !matches!(self, Runner::$variant(_)) {
                    *self = Runner::$variant($idle);
                }
                match self {
                    Runner::$variant(sim) => start_in_place(sim, $params, seed),
                    _ => Err(Error::NotStarted),
                }
            }};
        }
        let result = match *model {
            Model::GrowthCurve(ref p) => start!(GrowthCurve, GrowthCurve::IDLE, p),
            Model::Horn(p) => start!(Horn, Horn::IDLE, p),
            #[cfg(feature = "surface-runner")]
            Model::Mosaic(p) if p.surface.is_some() => {
                start!(SurfaceMosaic, IDLE_SURFACE_MOSAIC, p)
            }
            #[cfg(not(feature = "surface-runner"))]
            Model::Mosaic(p) if p.surface.is_some() => Err(Error::Capacity {
                limit: SURFACE_MOSAICS,
                capacity: 0,
            }),
            Model::Mosaic(p) => start!(Mosaic, IDLE_MOSAIC, p),
            Model::LSystem(grammar) => start!(LSystem, IDLE_LSYSTEM, grammar),
            Model::Body(p) => start!(Body, IDLE_BODY, p),
            Model::Bones(p) => start!(Bones, IDLE_BONES, p),
        };
        if result.is_err() {
            *self = Runner::Idle;
        }
        result
    }
}

/// Starts `sim` through its [`Start`], in a stack frame of its own: the
/// temporaries of one model's start (a horn's kernel, a grammar's parse)
/// then do not add to the frame of [`run`], which stays on the stack below
/// every step.
#[inline(never)]
fn start_in_place<'a, M: Start<'a> + ?Sized>(
    sim: &mut M,
    params: &'a M::Params,
    seed: u64,
) -> Result<(), Error> {
    sim.start(params, seed)
}

impl Simulation for Runner<'_> {
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        match self {
            Runner::Idle => Err(Error::NotStarted),
            Runner::GrowthCurve(sim) => sim.step(sink),
            Runner::Horn(sim) => sim.step(sink),
            Runner::Mosaic(sim) => sim.step(sink),
            #[cfg(feature = "surface-runner")]
            Runner::SurfaceMosaic(sim) => sim.step(sink),
            Runner::LSystem(sim) => sim.step(sink),
            Runner::Body(sim) => sim.step(sink),
            Runner::Bones(sim) => sim.step(sink),
        }
    }
}

/// Runs `preset` with `seed` in `runner`: start, header, every step. The
/// runner is idle again afterwards.
///
/// # Errors
/// The model's refusal of its parameters, then the first error of the sink
/// or of a step.
pub fn run<'a>(
    preset: &Preset<'a>,
    seed: u64,
    runner: &mut Runner<'a>,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), Error> {
    let params = preset.model.params_digest();
    run_with_digest(preset, seed, params, runner, sink, progress)
}

/// [`run`] with the parameter digest of the header given: `params` must be
/// `preset.model.params_digest()`. A device whose presets are compiled in
/// passes the digest its build computed, and so carries no serializer for
/// any model's parameters (some 4 KB of flash on a Cortex-M).
///
/// # Errors
/// As [`run`].
pub fn run_with_digest<'a>(
    preset: &Preset<'a>,
    seed: u64,
    params: u64,
    runner: &mut Runner<'a>,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), Error> {
    runner.start(&preset.model, seed)?;
    let header = header(preset.name, seed, params);
    let result = drive(runner, &header, sink, progress);
    *runner = Runner::Idle;
    result
}
