//! A scenario sent to a device over its UART, to change what a rig shows
//! without reflashing (docs/stream-format.md, "Sending a scenario"):
//! `morphogen send` turns a checked scenario into one frame — postcard, a
//! CRC-32, COBS and a zero byte, as every record — and the firmware reads
//! it into a [`SentScenario`] of fixed capacity, then runs it as it runs
//! its built-in presets.
//!
//! A growth curve, a horn, an L-system or a bone can be sent. A body's
//! mesh and tables do not fit a message, and a mosaic's parameters do not
//! fit the stack the firmware has left: they are built in
//! (`MORPHOGEN_SCENARIOS`).

use serde::{Deserialize, Serialize};

use crate::bones::{BonesParams, Frames};
use crate::fx::Fx;
use crate::growth::Sigmoid;
use crate::growth_curve;
use crate::horn::{HornParams, Module};
use crate::preset::{Model, Preset};
use crate::shrinkwrap::WrapParams;
use crate::stream::{Deframer, FORMAT_VERSION, FrameError, PresetName};

/// Modules of a sent horn (a ram's horn has 8).
pub const SENT_MODULES: usize = 8;
/// Outline points of a sent horn.
pub const SENT_OUTLINE: usize = 32;
/// Bytes of a sent L-system grammar (the built-in ones have at most 493
/// without their comments).
pub const SENT_GRAMMAR: usize = 512;
/// The largest message: a [`SentScenario`]'s postcard bytes and their
/// CRC-32 (the frame that carries it is at most 3 bytes longer).
pub const MAX_SENT: usize = 640;

/// A scenario as sent: its name, seed and parameter digest (for the stream
/// header), and its model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SentScenario {
    /// [`FORMAT_VERSION`] of the sender.
    pub version: u16,
    /// The scenario's name (the stream header's preset).
    pub name: PresetName,
    /// The seed to run with.
    pub seed: u64,
    /// The parameter digest the header carries.
    pub params: u64,
    /// The model and its parameters.
    pub model: SentModel,
}

/// The models a scenario can be sent with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SentModel {
    /// The seasonal growth curve.
    GrowthCurve(growth_curve::Params),
    /// A horn.
    Horn(SentHorn),
    /// An L-system: the grammar's text, comments left out.
    LSystem(heapless::String<SENT_GRAMMAR>),
    /// A bone: its skeleton's grammar (as an L-system's) and the wrap.
    Bones {
        /// As [`BonesParams::grammar`].
        grammar: heapless::String<SENT_GRAMMAR>,
        /// As [`BonesParams::wrap`].
        wrap: SentWrap,
        /// As [`BonesParams::frames`].
        frames: Frames,
    },
}

/// [`HornParams`] in fixed-capacity storage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SentHorn {
    /// As [`HornParams::modules`].
    pub modules: heapless::Vec<Module, SENT_MODULES>,
    /// As [`HornParams::outline`].
    pub outline: heapless::Vec<[Fx; 2], SENT_OUTLINE>,
    /// As [`HornParams::ring_points`].
    pub ring_points: u16,
    /// As [`HornParams::rings_per_module`].
    pub rings_per_module: u16,
    /// As [`HornParams::delay_days`].
    pub delay_days: u16,
    /// As [`HornParams::growth`].
    pub growth: Sigmoid,
    /// As [`HornParams::frames_per_year`].
    pub frames_per_year: u16,
    /// As [`HornParams::years`].
    pub years: u16,
}

/// [`WrapParams`] with every field on the wire (its own encoding leaves
/// the paper's split tolerance out, for the parameter digest).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SentWrap {
    /// As [`WrapParams::meridians`].
    pub meridians: u8,
    /// As [`WrapParams::parallels`].
    pub parallels: u8,
    /// As [`WrapParams::target`].
    pub target: Fx,
    /// As [`WrapParams::step`].
    pub step: Fx,
    /// As [`WrapParams::max_iterations`].
    pub max_iterations: u16,
    /// As [`WrapParams::split_tolerance`].
    pub split_tolerance: Fx,
    /// As [`WrapParams::weights`].
    pub weights: crate::shrinkwrap::Weights,
    /// As [`WrapParams::target_max`].
    pub target_max: Option<Fx>,
    /// As [`WrapParams::step_max`].
    pub step_max: Option<Fx>,
}

impl From<WrapParams> for SentWrap {
    fn from(w: WrapParams) -> SentWrap {
        SentWrap {
            meridians: w.meridians,
            parallels: w.parallels,
            target: w.target,
            step: w.step,
            max_iterations: w.max_iterations,
            split_tolerance: w.split_tolerance,
            weights: w.weights,
            target_max: w.target_max,
            step_max: w.step_max,
        }
    }
}

impl From<SentWrap> for WrapParams {
    fn from(w: SentWrap) -> WrapParams {
        WrapParams {
            meridians: w.meridians,
            parallels: w.parallels,
            target: w.target,
            step: w.step,
            max_iterations: w.max_iterations,
            split_tolerance: w.split_tolerance,
            weights: w.weights,
            target_max: w.target_max,
            step_max: w.step_max,
        }
    }
}

/// Why a scenario cannot be sent, or a message not read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SentError {
    /// The scenario carries what a device has no room for.
    NotSendable {
        /// What.
        what: &'static str,
        /// Why, and what to do instead.
        why: &'static str,
    },
    /// A part of the scenario exceeds a capacity of the message.
    Capacity {
        /// The limit's name.
        limit: &'static str,
        /// Its value.
        capacity: u32,
    },
    /// The frame could not be read ([`FrameError::TooLong`]: longer than
    /// [`MAX_SENT`]).
    Frame(FrameError),
    /// The frame checks but holds no scenario of this format version.
    Message,
}

impl core::fmt::Display for SentError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SentError::NotSendable { what, why } => {
                write!(f, "{what} cannot be sent to a device: {why}")
            }
            SentError::Capacity { limit, capacity } => {
                write!(f, "a sent scenario holds at most {limit} = {capacity}")
            }
            SentError::Frame(FrameError::TooLong) => {
                write!(f, "a message longer than MAX_SENT = {MAX_SENT} bytes")
            }
            SentError::Frame(e) => write!(f, "a damaged message: {e}"),
            SentError::Message => write!(
                f,
                "the message is not a scenario of stream format version {FORMAT_VERSION}"
            ),
        }
    }
}

impl core::error::Error for SentError {}

/// `items` into a vector of capacity `N`, or the limit it exceeds.
fn fill<T: Copy, const N: usize>(
    items: &[T],
    limit: &'static str,
) -> Result<heapless::Vec<T, N>, SentError> {
    heapless::Vec::from_slice(items).map_err(|()| SentError::Capacity {
        limit,
        capacity: N as u32,
    })
}

/// A grammar's text, or the limit it exceeds.
fn text(grammar: &str) -> Result<heapless::String<SENT_GRAMMAR>, SentError> {
    heapless::String::try_from(grammar).map_err(|()| SentError::Capacity {
        limit: "SENT_GRAMMAR bytes",
        capacity: SENT_GRAMMAR as u32,
    })
}

impl SentScenario {
    /// The message for `preset` run with `seed`, its header carrying the
    /// parameter digest `params`.
    ///
    /// # Errors
    /// [`SentError::NotSendable`] for a body or a mosaic;
    /// [`SentError::Capacity`] for a part bigger than the message holds.
    pub fn new(preset: &Preset<'_>, seed: u64, params: u64) -> Result<SentScenario, SentError> {
        let model = match preset.model {
            Model::GrowthCurve(p) => SentModel::GrowthCurve(p),
            Model::Horn(h) => SentModel::Horn(SentHorn {
                modules: fill(h.modules, "SENT_MODULES")?,
                outline: fill(h.outline, "SENT_OUTLINE")?,
                ring_points: h.ring_points,
                rings_per_module: h.rings_per_module,
                delay_days: h.delay_days,
                growth: h.growth,
                frames_per_year: h.frames_per_year,
                years: h.years,
            }),
            Model::LSystem(grammar) => SentModel::LSystem(text(grammar)?),
            Model::Bones(b) => SentModel::Bones {
                grammar: text(b.grammar)?,
                wrap: b.wrap.into(),
                frames: b.frames,
            },
            Model::Mosaic(_) => {
                return Err(SentError::NotSendable {
                    what: "a mosaic",
                    why: "the parameters it lends a run take 288 B of stack, which the firmware \
                          (its RAM 99 % used) does not have; build it into the firmware with \
                          MORPHOGEN_SCENARIOS",
                });
            }
            Model::Body(_) => {
                return Err(SentError::NotSendable {
                    what: "a body",
                    why: "its mesh and tables do not fit a message; \
                          build it into the firmware with MORPHOGEN_SCENARIOS",
                });
            }
        };
        let mut name = PresetName::new();
        name.push_str(preset.name)
            .map_err(|()| SentError::Capacity {
                limit: "preset name bytes",
                capacity: 32,
            })?;
        Ok(SentScenario {
            version: FORMAT_VERSION,
            name,
            seed,
            params,
            model,
        })
    }

    /// Frames the message into `frame` (at most [`MAX_SENT`] + 3 bytes);
    /// returns the frame's length. On the wire, send a zero byte before it
    /// ([`SentReader::push`]).
    ///
    /// # Errors
    /// [`SentError::Frame`]`(`[`FrameError::TooLong`]`)` when it exceeds
    /// [`MAX_SENT`] or `frame`.
    pub fn encode(&self, frame: &mut [u8]) -> Result<usize, SentError> {
        let mut raw = [0u8; MAX_SENT];
        let too_long = SentError::Frame(FrameError::TooLong);
        let len = postcard::to_slice(self, &mut raw[..MAX_SENT - 4])
            .map_err(|_| too_long)?
            .len();
        crate::stream::frame_payload(&mut raw, len, frame).ok_or(too_long)
    }

    /// The preset this message describes, lent to `f` (its parameters
    /// borrow from the message).
    pub fn with_preset<R>(&self, f: impl FnOnce(&Preset<'_>) -> R) -> R {
        let preset = |model| Preset {
            name: self.name.as_str(),
            summary: "",
            default_seed: self.seed,
            model,
        };
        match &self.model {
            SentModel::GrowthCurve(p) => f(&preset(Model::GrowthCurve(*p))),
            SentModel::LSystem(grammar) => f(&preset(Model::LSystem(grammar.as_str()))),
            SentModel::Bones {
                grammar,
                wrap,
                frames,
            } => {
                let params = BonesParams {
                    grammar,
                    wrap: (*wrap).into(),
                    frames: *frames,
                };
                f(&preset(Model::Bones(&params)))
            }
            SentModel::Horn(h) => {
                let params = HornParams {
                    modules: &h.modules,
                    outline: &h.outline,
                    ring_points: h.ring_points,
                    rings_per_module: h.rings_per_module,
                    delay_days: h.delay_days,
                    growth: h.growth,
                    frames_per_year: h.frames_per_year,
                    years: h.years,
                };
                f(&preset(Model::Horn(&params)))
            }
        }
    }
}

/// Reads sent scenarios one byte at a time, decoding each frame into a
/// buffer its owner lends (at least [`MAX_SENT`] bytes; a device lends
/// its display's cell plane, idle between runs).
#[derive(Debug)]
pub struct SentReader<'b> {
    frames: Deframer<&'b mut [u8]>,
}

impl<'b> SentReader<'b> {
    /// A reader decoding into `buffer`.
    pub const fn new(buffer: &'b mut [u8]) -> SentReader<'b> {
        SentReader {
            frames: Deframer::new(buffer),
        }
    }

    /// Takes one byte off the wire; at a zero byte, the scenario its frame
    /// holds, or why it holds none (a frame longer than the buffer is
    /// [`FrameError::TooLong`]). An empty frame is skipped: a sender starts
    /// with a zero byte, to end whatever partial frame came before (noise
    /// on a line at boot).
    pub fn push(&mut self, byte: u8) -> Option<Result<SentScenario, SentError>> {
        if byte == 0 && self.frames.pending() == 0 {
            return None;
        }
        let payload = self.frames.push(byte)?;
        Some(match payload {
            Err(e) => Err(SentError::Frame(e)),
            Ok(bytes) => match postcard::from_bytes::<SentScenario>(bytes) {
                Ok(sent) if sent.version == FORMAT_VERSION => Ok(sent),
                _ => Err(SentError::Message),
            },
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use crate::stream::FrameError;

    fn horn_preset<R>(f: impl FnOnce(&Preset<'_>) -> R) -> R {
        let modules = [Module {
            positioner_scale: Fx::ONE,
            base_scale: Fx::from_ratio(1, 2),
            bend: crate::fx::Angle::from_degrees(30),
            twist: crate::fx::Angle(0),
            path_radius: Fx::from_int(20),
        }; 2];
        let outline = [
            [Fx::ZERO, Fx::ONE],
            [Fx::ONE, Fx::ZERO],
            [-Fx::ONE, Fx::ZERO],
        ];
        let params = HornParams {
            modules: &modules,
            outline: &outline,
            ring_points: 6,
            rings_per_module: 4,
            delay_days: 365,
            growth: Sigmoid::SEASONAL_YEAR,
            frames_per_year: 1,
            years: 2,
        };
        f(&named("sent-horn", Model::Horn(&params)))
    }

    fn named<'a>(name: &'a str, model: Model<'a>) -> Preset<'a> {
        Preset {
            name,
            summary: "",
            default_seed: 0,
            model,
        }
    }

    /// Every byte of `frame` through a reader.
    fn read(frame: &[u8]) -> std::vec::Vec<Result<SentScenario, SentError>> {
        let mut buffer = [0u8; MAX_SENT];
        let mut reader = SentReader::new(&mut buffer);
        frame.iter().filter_map(|&b| reader.push(b)).collect()
    }

    #[test]
    fn a_horn_goes_through_the_wire_whole() {
        let sent = horn_preset(|p| SentScenario::new(p, 7, 0xabc)).unwrap();
        let mut frame = [0u8; MAX_SENT + 3];
        let len = sent.encode(&mut frame).unwrap();
        let back = read(&frame[..len]);
        assert_eq!(back, [Ok(sent.clone())]);
        // The preset it lends is the one it was made from.
        let original = horn_preset(|p| std::format!("{:?}", p.model));
        assert_eq!(
            sent.with_preset(|p| std::format!("{:?}", p.model)),
            original
        );
        // After line noise, the zero byte a sender starts with resyncs.
        let mut noisy = std::vec![0x37, 0x11, 0];
        noisy.extend_from_slice(&frame[..len]);
        let back = read(&noisy);
        assert_eq!(back.len(), 2);
        assert!(back[0].is_err());
        assert_eq!(back[1], Ok(sent.clone()));
        // A flipped bit anywhere: a damaged message, never a wrong one.
        for i in 0..len {
            let mut damaged = frame[..len].to_vec();
            damaged[i] ^= 0x04;
            assert!(read(&damaged).iter().all(Result::is_err), "byte {i}");
        }
    }

    #[test]
    fn a_bone_keeps_its_wrap_whole() {
        let bones = BonesParams {
            grammar: "axiom: O(1)\n",
            wrap: WrapParams {
                meridians: 8,
                parallels: 5,
                target: Fx::ONE,
                step: Fx::from_ratio(1, 4),
                max_iterations: 40,
                split_tolerance: crate::shrinkwrap::SPLIT_TOLERANCE,
                weights: crate::shrinkwrap::Weights::Normalised,
                target_max: Some(Fx::from_ratio(5, 4)),
                step_max: None,
            },
            frames: Frames::Seeds(3),
        };
        let preset = named("sent-bone", Model::Bones(&bones));
        let sent = SentScenario::new(&preset, 1, 2).unwrap();
        let mut frame = [0u8; MAX_SENT + 3];
        let len = sent.encode(&mut frame).unwrap();
        assert_eq!(read(&frame[..len]), [Ok(sent.clone())]);
        let back = sent.with_preset(|p| std::format!("{:?}", p.model));
        assert_eq!(back, std::format!("{:?}", preset.model));
    }

    #[test]
    fn limits_are_named() {
        let long = "F".repeat(SENT_GRAMMAR + 1);
        let preset = named("long", Model::LSystem(&long));
        let e = SentScenario::new(&preset, 0, 0).unwrap_err();
        assert_eq!(
            std::format!("{e}"),
            "a sent scenario holds at most SENT_GRAMMAR bytes = 512"
        );
        let mut frame = [0u8; 1000];
        let mut reader_buffer = [0u8; 16];
        let mut reader = SentReader::new(&mut reader_buffer);
        let grammar = Preset {
            model: Model::LSystem("axiom: F\nF -> FF\n"),
            ..preset
        };
        let len = SentScenario::new(&grammar, 0, 0)
            .unwrap()
            .encode(&mut frame)
            .unwrap();
        let out: std::vec::Vec<_> = frame[..len]
            .iter()
            .filter_map(|&b| reader.push(b))
            .collect();
        assert_eq!(out, [Err(SentError::Frame(FrameError::TooLong))]);
        assert_eq!(
            std::format!("{}", out[0].clone().unwrap_err()),
            "a message longer than MAX_SENT = 640 bytes"
        );
    }
}
