//! One face for every model: a [`Model`] is a model's validated parameters,
//! a [`Preset`] names one with a seed, the [`Runner`] holds whichever one is
//! running in one place (a `static` on the MCU), and [`drive`] is the one
//! run loop (header, then steps).
//!
//! The core holds no preset data: built-in presets are the scenario files
//! in `scenarios/` (read by the host at run time, and turned into
//! `static` [`Preset`]s at the firmware's build time).

use crate::Error;
use crate::body::{Body, BodyParams};
use crate::bones::{Bones, BonesParams, MCU_TRIANGLES, MCU_VERTICES};
use crate::growth_curve::{self, GrowthCurve};
use crate::horn::{Horn, HornParams};
use crate::lsys::LSystem;
use crate::mosaic::{self, McuStore, Mosaic, Params as MosaicParams};
use crate::sim::{Progress, Simulation, Start};
use crate::stream::{FORMAT_VERSION, Header, PresetName, Record, Sink, params_digest};

/// A model and its parameters: what a scenario file describes, checked.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
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
    /// ([`mosaic::expected_peak_cells`]) fits the inline store; every other
    /// model's state is bounded by its type (a run that exceeds a limit
    /// stops with an error naming it).
    #[must_use]
    pub fn fits_mcu(&self) -> bool {
        match self {
            Model::Mosaic(p) => mosaic::expected_peak_cells(p) <= McuStore::CAPACITY as u64,
            _ => true,
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
    /// An L-system, derived streaming.
    LSystem(LSystem),
    /// A body.
    Body(Body<'a>),
    /// A bone.
    Bones(Bones<'a, MCU_VERTICES, MCU_TRIANGLES>),
}

/// Defines `fn $name(runner, params, seed)`: puts an idle `$variant` into
/// the runner unless it holds one (an idle model is a `const`, written in
/// place: no model-sized temporary on a small stack), then starts it. Not
/// inlined, so that the start of one model does not add its temporaries to
/// the stack frame of every other's.
macro_rules! start_in_place {
    ($name:ident, $variant:ident, $params:ty, $idle:expr) => {
        #[inline(never)]
        fn $name<'a>(runner: &mut Runner<'a>, params: &'a $params, seed: u64) -> Result<(), Error> {
            if !matches!(runner, Runner::$variant(_)) {
                *runner = Runner::$variant($idle);
            }
            match runner {
                Runner::$variant(sim) => Start::start(sim, params, seed),
                _ => Err(Error::NotStarted),
            }
        }
    };
}

/// The growth curve copies its parameters: they need not outlive the call.
#[inline(never)]
fn start_curve(
    runner: &mut Runner<'_>,
    params: &growth_curve::Params,
    seed: u64,
) -> Result<(), Error> {
    let mut curve = GrowthCurve::IDLE;
    let started = Start::start(&mut curve, params, seed);
    *runner = Runner::GrowthCurve(curve);
    started
}

start_in_place!(start_horn, Horn, HornParams<'a>, Horn::IDLE);
start_in_place!(
    start_mosaic,
    Mosaic,
    MosaicParams<'a>,
    Mosaic::new(McuStore::EMPTY)
);
start_in_place!(start_lsystem, LSystem, str, LSystem::new());
start_in_place!(start_body, Body, BodyParams<'a>, Body::new());
start_in_place!(start_bones, Bones, BonesParams<'a>, Bones::new());

impl<'a> Runner<'a> {
    /// An idle runner (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Runner<'a> {
        Runner::Idle
    }

    /// Starts `model` with `seed` in place, through the model's
    /// [`Start`].
    ///
    /// # Errors
    /// The model's refusal of its parameters (each names the limit or the
    /// parameter); the runner is then idle.
    pub fn start(&mut self, model: &Model<'a>, seed: u64) -> Result<(), Error> {
        let result = match *model {
            Model::GrowthCurve(ref p) => start_curve(self, p, seed),
            Model::Horn(p) => start_horn(self, p, seed),
            Model::Mosaic(p) => start_mosaic(self, p, seed),
            Model::LSystem(grammar) => start_lsystem(self, grammar, seed),
            Model::Body(p) => start_body(self, p, seed),
            Model::Bones(p) => start_bones(self, p, seed),
        };
        if result.is_err() {
            *self = Runner::Idle;
        }
        result
    }
}

impl Simulation for Runner<'_> {
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        match self {
            Runner::Idle => Err(Error::NotStarted),
            Runner::GrowthCurve(sim) => sim.step(sink),
            Runner::Horn(sim) => sim.step(sink),
            Runner::Mosaic(sim) => sim.step(sink),
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
    runner.start(&preset.model, seed)?;
    let header = header(preset.name, seed, preset.model.params_digest());
    let result = drive(runner, &header, sink, progress);
    *runner = Runner::Idle;
    result
}
