//! The built-in scenarios, and the [`Runner`] that holds whichever one is
//! running in one place (a `static` on the MCU).

use crate::Error;
use crate::body::{self, Body, BodyParams};
use crate::bones::{self, Bones, BonesParams};
use crate::growth_curve::{self, GrowthCurve};
use crate::horn::{self, Horn};
use crate::lsys::{self, LSystem};
use crate::mosaic::{Mosaic, Params as MosaicParams, presets as mosaics};
use crate::sim::{Progress, Simulation};
use crate::stream::{FORMAT_VERSION, Header, PresetName, Record, Sink, params_digest};

/// A named scenario: parameters, a default seed, and how to start it.
#[derive(Debug)]
pub struct Preset {
    /// The name used on the command line and in stream headers.
    pub name: &'static str,
    /// One line for `morphogen list`.
    pub summary: &'static str,
    /// The seed used when none is given.
    pub default_seed: u64,
    /// Puts a fresh simulation into the runner; returns the parameter digest.
    start: fn(&mut Runner, u64) -> u64,
}

/// Every built-in preset, in `morphogen list` order.
pub static PRESETS: &[Preset] = &[
    Preset {
        name: "growth-curve",
        summary: "seasonal sigmoid growth f(t) of a horn module over one year, daily (horn paper Sec. 2, Fig. 7c)",
        default_seed: 0,
        start: |runner, _seed| {
            *runner = Runner::GrowthCurve(GrowthCurve::new(growth_curve::PARAMS));
            params_digest(&growth_curve::PARAMS)
        },
    },
    Preset {
        name: "ram-horn",
        summary: "ram horn of 8 modules placed by positioners (horn paper Table 1), every half year for 8 years",
        default_seed: 0,
        start: |runner, _seed| {
            *runner = Runner::Horn(Horn::new(&horn::presets::RAM_HORN));
            params_digest(&horn::presets::RAM_HORN)
        },
    },
    Preset {
        name: "ram-horn-animation",
        summary: "the ram horn growing, monthly frames for 8 years, monthly rings (horn paper Sec. 7, Fig. 10)",
        default_seed: 0,
        start: |runner, _seed| {
            *runner = Runner::Horn(Horn::new(&horn::presets::RAM_HORN_ANIMATION));
            params_digest(&horn::presets::RAM_HORN_ANIMATION)
        },
    },
    Preset {
        name: "abop-shrub",
        summary: "L-system: ABOP Fig. 1.25 shrub, n = 7, δ = 22.5°, 77 399 modules derived streaming (grammars/abop-shrub.lsys)",
        default_seed: 0,
        start: |runner, seed| start_lsystem(runner, lsys::presets::SHRUB, seed),
    },
    Preset {
        name: "abop-2d-plant",
        summary: "L-system: ABOP Fig. 1.24a bracketed 2D plant, n = 5, δ = 25.7° (grammars/abop-2d-plant.lsys)",
        default_seed: 0,
        start: |runner, seed| start_lsystem(runner, lsys::presets::PLANT_2D, seed),
    },
    Preset {
        name: "abop-stochastic",
        summary: "L-system: ABOP Fig. 1.27 stochastic plants, three side by side from seeds s, s+1, s+2 (grammars/abop-stochastic.lsys)",
        default_seed: 1,
        start: |runner, seed| start_lsystem(runner, lsys::presets::STOCHASTIC, seed),
    },
    Preset {
        name: "abop-monopodial",
        summary: "L-system: ABOP Fig. 2.6a parametric monopodial tree, n = 10 (grammars/abop-monopodial.lsys)",
        default_seed: 0,
        start: |runner, seed| start_lsystem(runner, lsys::presets::MONOPODIAL, seed),
    },
    Preset {
        name: "croton-mcu",
        summary: "MClone croton leaf sized for a 64 KB MCU: 180 cells growing to ~1 800 over 35 days, every day (thesis Fig. 4.1; runs on the firmware)",
        default_seed: 1,
        start: |runner, seed| start_mosaic_mcu(runner, &mosaics::CROTON_MCU, seed),
    },
    Preset {
        name: "horse-growth",
        summary: "quarter horse of 18 cylinders grown by its measured table, 0-60 months every 6 months (growth paper Table 1, Fig. 5)",
        default_seed: 0,
        start: |runner, _seed| start_body(runner, &body::presets::HORSE_GROWTH),
    },
    Preset {
        name: "cow-growth",
        summary: "Holstein of 18 cylinders grown by its measured table, 0-36 months every 3 months (growth paper Table 2, Fig. 6)",
        default_seed: 0,
        start: |runner, _seed| start_body(runner, &body::presets::COW_GROWTH),
    },
    Preset {
        name: "horse-trot",
        summary: "the horse trotting (12 frames per stride, diagonal pairs) while growing from 6 to 60 months (growth paper Sec. 7, Fig. 8)",
        default_seed: 0,
        start: |runner, _seed| start_body(runner, &body::presets::HORSE_TROT),
    },
    Preset {
        name: "long-bone",
        summary: "bone: an L-system shaft with two epiphyses after 12 steps, shrinkwrapped at V0 = 3.4 (bones paper Fig. 1; grammars/long-bone.lsys)",
        default_seed: 0,
        start: |runner, seed| start_bones(runner, &bones::presets::LONG_BONE, seed),
    },
    Preset {
        name: "long-bone-random",
        summary: "bone: the same rules with chance in them, three bones from seeds s, s+1, s+2 (bones paper Fig. 3; grammars/long-bone-random.lsys)",
        default_seed: 1,
        start: |runner, seed| start_bones(runner, &bones::presets::LONG_BONE_RANDOM, seed),
    },
    Preset {
        name: "bone-growth",
        summary: "bone: the long bone wrapped after each of its 12 L-system steps (bones paper Fig. 2)",
        default_seed: 0,
        start: |runner, seed| start_bones(runner, &bones::presets::BONE_GROWTH, seed),
    },
];

/// The preset called `name`.
#[must_use]
pub fn find(name: &str) -> Option<&'static Preset> {
    PRESETS.iter().find(|p| p.name == name)
}

/// The stream header of a run of the preset `name` with `seed` and the
/// parameter digest `params`, exactly as [`Runner::start`] writes it (the
/// host uses it for its own presets, so that their streams match).
#[must_use]
pub fn header(name: &str, seed: u64, params: u64) -> Record {
    let mut preset = PresetName::new();
    // Preset names are short literals; a longer one is truncated.
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

/// Holds the running simulation, whatever its model.
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
pub enum Runner {
    /// Nothing started.
    #[default]
    Idle,
    /// `growth-curve`.
    GrowthCurve(GrowthCurve),
    /// `ram-horn` and `ram-horn-animation`.
    Horn(Horn),
    /// The MCU-sized mosaics (`croton-mcu`), stored inline.
    Mosaic(Mosaic<mosaics::McuStore>),
    /// The L-system presets (`abop-*`), derived streaming.
    LSystem(LSystem),
    /// The body presets (`horse-growth`, `cow-growth`, `horse-trot`).
    Body(Body<'static>),
    /// The bone presets (`long-bone`, `long-bone-random`, `bone-growth`).
    Bones(Bones<{ bones::presets::MCU_VERTICES }, { bones::presets::MCU_TRIANGLES }>),
}

impl Runner {
    /// An idle runner (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Runner {
        Runner::Idle
    }

    /// Starts `preset` with `seed` and writes the stream header.
    ///
    /// # Errors
    /// When the sink refuses the header.
    pub fn start(&mut self, preset: &Preset, seed: u64, sink: &mut dyn Sink) -> Result<(), Error> {
        let params = (preset.start)(self, seed);
        sink.record(&header(preset.name, seed, params))?;
        Ok(())
    }

    /// Runs one step of the current simulation.
    ///
    /// # Errors
    /// [`Error::NotStarted`] when idle; otherwise the model's errors.
    pub fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
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

/// Runs `preset` to the end: header, then every step, reporting progress.
///
/// # Errors
/// The first error of [`Runner::start`] or [`Runner::step`].
pub fn run(
    preset: &Preset,
    seed: u64,
    runner: &mut Runner,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), Error> {
    runner.start(preset, seed, sink)?;
    loop {
        let p = runner.step(sink)?;
        progress(p);
        if p.finished() {
            *runner = Runner::Idle;
            return Ok(());
        }
    }
}

/// An empty MCU mosaic, written into the runner in place (a `const` of
/// zeros, so no 49 KB temporary on a small stack).
const EMPTY_MCU_MOSAIC: Mosaic<mosaics::McuStore> = Mosaic::new(mosaics::McuStore::EMPTY);

/// Starts an MCU-sized mosaic in `runner`, reusing its store if it holds one.
fn start_mosaic_mcu(runner: &mut Runner, params: &'static MosaicParams, seed: u64) -> u64 {
    if !matches!(runner, Runner::Mosaic(_)) {
        *runner = Runner::Mosaic(EMPTY_MCU_MOSAIC);
    }
    if let Runner::Mosaic(m) = runner {
        let _ = m.start(params, seed); // an error is reported by the first step
    }
    params_digest(params)
}

/// An empty L-system, written into the runner in place.
const EMPTY_LSYSTEM: LSystem = LSystem::new();

/// Starts the L-system `grammar` in `runner`, parsing in place (no
/// grammar-sized temporary on a small stack).
fn start_lsystem(runner: &mut Runner, grammar: &'static str, seed: u64) -> u64 {
    if !matches!(runner, Runner::LSystem(_)) {
        *runner = Runner::LSystem(EMPTY_LSYSTEM);
    }
    if let Runner::LSystem(sim) = runner {
        let _ = sim.load(grammar, seed); // an error is reported by the first step
    }
    params_digest(grammar)
}

/// Starts a body in `runner`, loading it in place.
fn start_body(runner: &mut Runner, params: &'static BodyParams<'static>) -> u64 {
    if !matches!(runner, Runner::Body(_)) {
        *runner = Runner::Body(Body::new());
    }
    if let Runner::Body(sim) = runner {
        sim.start(params); // an error is reported by the first step
    }
    params_digest(params)
}

/// An empty bone simulation, written into the runner in place (its mesh
/// buffers are uninitialised capacity, so no 48 KB temporary on a small
/// stack).
const EMPTY_BONES: Bones<{ bones::presets::MCU_VERTICES }, { bones::presets::MCU_TRIANGLES }> =
    Bones::new();

/// Starts a bone in `runner`, in place.
fn start_bones(runner: &mut Runner, params: &'static BonesParams, seed: u64) -> u64 {
    if !matches!(runner, Runner::Bones(_)) {
        *runner = Runner::Bones(EMPTY_BONES);
    }
    if let Runner::Bones(sim) = runner {
        let _ = sim.start(params, seed); // an error is reported by the first step
    }
    params_digest(params)
}
