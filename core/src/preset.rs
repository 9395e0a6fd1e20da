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
use crate::sim::{Progress, Simulation};
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

/// An empty MCU mosaic, written into the runner in place (a `const` of
/// zeros, so no 49 KB temporary on a small stack).
const EMPTY_MCU_MOSAIC: Mosaic<'static, McuStore> = Mosaic::new(McuStore::EMPTY);
/// An empty L-system, written into the runner in place.
const EMPTY_LSYSTEM: LSystem = LSystem::new();
/// An empty bone simulation, written into the runner in place (its mesh
/// buffers are uninitialised capacity, so no 48 KB temporary).
const EMPTY_BONES: Bones<'static, MCU_VERTICES, MCU_TRIANGLES> = Bones::new();

impl<'a> Runner<'a> {
    /// An idle runner (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Runner<'a> {
        Runner::Idle
    }

    /// Starts `model` with `seed` in place (reusing the state of the same
    /// model, so that no model-sized temporary lands on the stack).
    ///
    /// # Errors
    /// The model's refusal of its parameters (each names the limit or the
    /// parameter); the runner is then idle.
    pub fn start(&mut self, model: &Model<'a>, seed: u64) -> Result<(), Error> {
        let result = match *model {
            Model::GrowthCurve(p) => {
                *self = Runner::GrowthCurve(GrowthCurve::new(p));
                Ok(())
            }
            Model::Horn(p) => {
                let horn = Horn::new(p);
                let checked = horn.check();
                *self = Runner::Horn(horn);
                checked
            }
            Model::Mosaic(p) => {
                if !matches!(self, Runner::Mosaic(_)) {
                    *self = Runner::Mosaic(EMPTY_MCU_MOSAIC);
                }
                match self {
                    Runner::Mosaic(m) => m.start(p, seed),
                    _ => Err(Error::NotStarted),
                }
            }
            Model::LSystem(grammar) => {
                if !matches!(self, Runner::LSystem(_)) {
                    *self = Runner::LSystem(EMPTY_LSYSTEM);
                }
                match self {
                    Runner::LSystem(sim) => sim.load(grammar, seed).map_err(Error::from),
                    _ => Err(Error::NotStarted),
                }
            }
            Model::Body(p) => {
                if !matches!(self, Runner::Body(_)) {
                    *self = Runner::Body(Body::new());
                }
                match self {
                    Runner::Body(sim) => sim.start(p),
                    _ => Err(Error::NotStarted),
                }
            }
            Model::Bones(p) => {
                if !matches!(self, Runner::Bones(_)) {
                    *self = Runner::Bones(EMPTY_BONES);
                }
                match self {
                    Runner::Bones(sim) => sim.start(p, seed),
                    _ => Err(Error::NotStarted),
                }
            }
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
