//! The built-in scenarios, and the [`Runner`] that holds whichever one is
//! running in one place (a `static` on the MCU).

use crate::Error;
use crate::growth_curve::{self, GrowthCurve};
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
pub static PRESETS: &[Preset] = &[Preset {
    name: "growth-curve",
    summary: "seasonal sigmoid growth f(t) of a horn module over one year, daily (horn paper Sec. 2, Fig. 7c)",
    default_seed: 0,
    start: |runner, _seed| {
        *runner = Runner::GrowthCurve(GrowthCurve::new(growth_curve::PARAMS));
        params_digest(&growth_curve::PARAMS)
    },
}];

/// The preset called `name`.
#[must_use]
pub fn find(name: &str) -> Option<&'static Preset> {
    PRESETS.iter().find(|p| p.name == name)
}

/// Holds the running simulation, whatever its model.
#[derive(Debug, Default)]
#[non_exhaustive]
pub enum Runner {
    /// Nothing started.
    #[default]
    Idle,
    /// `growth-curve`.
    GrowthCurve(GrowthCurve),
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
        let mut name = PresetName::new();
        // Preset names are short literals; a longer one is truncated.
        for c in preset.name.chars() {
            if name.push(c).is_err() {
                break;
            }
        }
        let header = Header {
            version: FORMAT_VERSION,
            preset: name,
            seed,
            params,
        };
        sink.record(&Record::Header(header))?;
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
