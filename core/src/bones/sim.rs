//! The bone simulation (bones paper, Secs. 2–6): grow the skeleton, wrap
//! it, stream the frame.
//!
//! A frame is one wrapped bone: `FrameStart` (time = derivation steps), a
//! `Segment` per skeleton element (a point has `a == b`; width = ρ; a
//! polygon element of k edges is a `Polygon` record of k vertices
//! followed by its k edges as `Segment`s), the
//! `MeshVertex`es and the `Triangle`s (counter-clockwise seen from
//! outside), `FrameEnd`. Each [`Simulation::step`] runs one shrinkwrap
//! iteration; progress counts finished frames.

use nalgebra::Vector3;

use crate::Error;
use crate::fx::Fx;
use crate::lsys::{Derivation, Streaming};
use crate::shrinkwrap::{Phase, Shrinkwrap};
use crate::sim::{Deferred, Progress, Simulation, Start};
use crate::stream::{Record, Sink};

use super::skeleton::{Grower, Skeleton};
use super::{BonesError, BonesParams, Frames};

/// A bone simulation with a mesh of at most `V` vertices and `T`
/// triangles, keeping the field at up to `C` of them between moves
/// ([`Shrinkwrap`]; 0 on an MCU, [`HOST_FIELD_CACHE`](super::HOST_FIELD_CACHE)
/// on a host).
/// The skeleton is derived by `D`: [`Streaming`] (the MCU's, context-free
/// grammars only) or [`crate::lsys::Buffered`] ([`Bones::with_derivation`]).
#[derive(Debug)]
pub struct Bones<'a, const V: usize, const T: usize, const C: usize = 0, D: Derivation = Streaming>
{
    frame: u32,
    wrapping: bool,
    seed: u64,
    params: Option<&'a BonesParams<'a>>,
    grower: Grower<D>,
    skeleton: Skeleton,
    wrap: Shrinkwrap<Fx, V, T, C>,
    /// The error that stopped the run, if any.
    failed: Deferred,
}

impl<'a, const V: usize, const T: usize, const C: usize> Bones<'a, V, T, C> {
    /// An idle simulation (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Bones<'a, V, T, C> {
        Bones::with_derivation(Streaming::new())
    }
}

impl<'a, const V: usize, const T: usize, const C: usize, D: Derivation> Bones<'a, V, T, C, D> {
    /// An idle simulation whose skeletons `derivation` derives.
    #[must_use]
    pub const fn with_derivation(derivation: D) -> Bones<'a, V, T, C, D> {
        Bones {
            grower: Grower::with_derivation(derivation),
            skeleton: Skeleton::new(),
            wrap: Shrinkwrap::new(Fx::ZERO),
            params: None,
            seed: 0,
            frame: 0,
            wrapping: false,
            failed: Deferred::new(),
        }
    }

    /// The current skeleton.
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The shrinkwrap run.
    #[must_use]
    pub fn wrap(&self) -> &Shrinkwrap<Fx, V, T, C> {
        &self.wrap
    }

    fn frames(&self) -> u32 {
        let n = self.grower.grammar().settings().steps;
        match self.params.map(|p| p.frames) {
            None => 0,
            Some(Frames::Final) => 1,
            // first ≤ n: checked by `start`.
            Some(Frames::EveryStep { first }) => n.saturating_sub(first) as u32 + 1,
            Some(Frames::Seeds(count)) => count as u32,
        }
    }

    /// Derivation steps and seed of frame `k`.
    fn frame_setup(&self, k: u32) -> (u8, u64) {
        let n = self.grower.grammar().settings().steps;
        match self.params {
            Some(p) => {
                let steps = match p.frames {
                    Frames::EveryStep { first } => first.saturating_add(k as u8),
                    Frames::Final | Frames::Seeds(_) => n,
                };
                (steps, p.frame_seed(self.seed, k))
            }
            None => (n, self.seed),
        }
    }

    fn advance(&mut self, params: &'a BonesParams<'a>, sink: &mut dyn Sink) -> Result<(), Error> {
        if !self.wrapping {
            let (steps, seed) = self.frame_setup(self.frame);
            self.grower.grow(steps, seed, &mut self.skeleton)?;
            let wrap = params.frame_wrap(seed, steps);
            self.wrap.start(&self.skeleton, &wrap)?;
            self.wrapping = true;
            return Ok(());
        }
        if self.wrap.iterate(&self.skeleton)? == Phase::Done {
            self.emit(sink)?;
            self.wrapping = false;
            self.frame += 1;
        }
        Ok(())
    }

    fn emit(&self, sink: &mut dyn Sink) -> Result<(), Error> {
        let (steps, _) = self.frame_setup(self.frame);
        sink.record(&Record::FrameStart {
            frame: self.frame,
            time: Fx::from_int(steps as i32),
        })?;
        // Edges of the current polygon still to come.
        let mut edges = 0u8;
        for e in &self.skeleton {
            if edges == 0 && e.polygon != 0 {
                edges = e.polygon;
                sink.record(&Record::Polygon {
                    vertices: u16::from(edges),
                    colour: 0,
                })?;
            }
            edges = edges.saturating_sub(1);
            sink.record(&Record::Segment {
                a: e.a,
                b: e.b,
                width: e.weight,
                colour: 0,
            })?;
        }
        let mesh = self.wrap.mesh();
        for (id, p) in mesh.vertices().iter().enumerate() {
            let p: &Vector3<Fx> = p;
            sink.record(&Record::MeshVertex {
                id: id as u32,
                p: [p.x, p.y, p.z],
            })?;
        }
        for t in mesh.triangles() {
            sink.record(&Record::Triangle {
                v: t.map(u32::from),
            })?;
        }
        sink.record(&Record::FrameEnd { frame: self.frame })?;
        Ok(())
    }
}

impl<const V: usize, const T: usize, const C: usize> Default for Bones<'_, V, T, C> {
    fn default() -> Self {
        Bones::new()
    }
}

impl<'a, const V: usize, const T: usize, const C: usize, D: Derivation> Start<'a>
    for Bones<'a, V, T, C, D>
{
    type Params = BonesParams<'a>;

    /// Starts `params` with `seed`; an error is also returned by the first
    /// step.
    ///
    /// # Errors
    /// The grammar's parse error, or [`BonesError::FirstStepPastEnd`].
    fn start(&mut self, params: &'a BonesParams<'a>, seed: u64) -> Result<(), Error> {
        self.params = Some(params);
        self.seed = seed;
        self.frame = 0;
        self.wrapping = false;
        let loaded = self.grower.load(params.grammar).map_err(Error::from);
        let checked = loaded.and_then(|()| {
            let steps = self.grower.grammar().settings().steps;
            match params.frames {
                Frames::EveryStep { first } if first > steps => {
                    Err(BonesError::FirstStepPastEnd { first, steps }.into())
                }
                _ => Ok(()),
            }
        });
        self.failed.keep(checked)
    }
}

impl<const V: usize, const T: usize, const C: usize, D: Derivation> Simulation
    for Bones<'_, V, T, C, D>
{
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.failed.check()?;
        let params = self.params.ok_or(Error::NotStarted)?;
        let total = self.frames();
        if self.frame < total {
            let advanced = self.advance(params, sink);
            self.failed.keep(advanced)?;
        }
        Ok(Progress {
            done: self.frame.min(total),
            total,
        })
    }
}
