//! A growing (and moving) body as a [`Simulation`] (growth paper, Secs.
//! 6–7: the growth process and animation): one frame per step.
//!
//! Frame f shows the body at age `first_age + (last_age − first_age)·f /
//! (frames − 1)` months, with the gait (if any) at phase `(f mod
//! frames_per_stride) / frames_per_stride`. A frame is `FrameStart{time =
//! age in months}`, every vertex of the deformed mesh as `MeshVertex`
//! (ids from 0), every triangle, `FrameEnd`. Vertices are bound and
//! deformed one at a time, so the state is the skeleton alone (about
//! 3.1 KB for 24 cylinders), whatever the mesh size.

use serde::Serialize;

use super::gait::Gait;
use super::skeleton::Skeleton;
use super::{BodyModel, GrowthTable, MAX_CYLINDERS};
use crate::Error;
use crate::fx::Fx;
use crate::sim::{Deferred, Progress, Simulation, Start};
use crate::stream::{Record, Sink};

/// What a body run shows.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BodyParams<'a> {
    /// The body: cylinders, features and mesh.
    pub model: &'a BodyModel<'a>,
    /// The growth data its features follow.
    pub table: &'a GrowthTable<'a>,
    /// Number of frames (at least 1).
    pub frames: u16,
    /// Age of the first frame, months.
    pub first_age: Fx,
    /// Age of the last frame, months.
    pub last_age: Fx,
    /// The joint motion, if the body moves.
    pub gait: Option<&'a Gait<'a>>,
    /// Frames per stride of the gait (at least 1 with a gait).
    pub frames_per_stride: u16,
}

impl BodyParams<'_> {
    /// The age of frame `frame`, months (rounded to nearest).
    #[must_use]
    pub fn age(&self, frame: u32) -> Fx {
        let span = i64::from(self.frames.saturating_sub(1)).max(1);
        let diff = i64::from(self.last_age.to_bits()) - i64::from(self.first_age.to_bits());
        let step = diff * i64::from(frame.min(u32::from(self.frames)));
        let offset = (2 * step + span * step.signum()) / (2 * span);
        Fx::from_bits((i64::from(self.first_age.to_bits()) + offset) as i32)
    }

    /// The gait phase of frame `frame`, in [0, 1).
    #[must_use]
    pub fn phase(&self, frame: u32) -> Fx {
        let n = u32::from(self.frames_per_stride.max(1));
        Fx::from_ratio((frame % n) as i32, n as i32)
    }
}

/// A body run holding at most `C` cylinders; see the module docs.
#[derive(Clone, Debug)]
pub struct Body<'a, const C: usize = MAX_CYLINDERS> {
    params: Option<&'a BodyParams<'a>>,
    skeleton: Skeleton<Fx, C>,
    failure: Deferred,
    frame: u32,
    unbound: u32,
}

impl<const C: usize> Default for Body<'_, C> {
    fn default() -> Self {
        Body::new()
    }
}

impl<'a, const C: usize> Body<'a, C> {
    /// A body with nothing loaded (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Self {
        Body {
            params: None,
            skeleton: Skeleton::new(),
            failure: Deferred::new(),
            frame: 0,
            unbound: 0,
        }
    }

    /// Vertices in no cylinder, following the nearest (counted in frame 0).
    #[must_use]
    pub fn unbound_vertices(&self) -> u32 {
        self.unbound
    }
}

impl<'a, const C: usize> Start<'a> for Body<'a, C> {
    type Params = BodyParams<'a>;

    /// Loads `params` in place; a body grows deterministically, so
    /// `seed` is not used. An invalid model or table is also the first
    /// step's error.
    fn start(&mut self, params: &'a BodyParams<'a>, _seed: u64) -> Result<(), Error> {
        self.params = Some(params);
        self.frame = 0;
        self.unbound = 0;
        let result =
            if params.frames == 0 || (params.gait.is_some() && params.frames_per_stride == 0) {
                Err(super::BodyError::ZeroCount.into())
            } else {
                self.skeleton.load(params.model, params.table)
            };
        self.failure.keep(result)
    }
}

impl<const C: usize> Simulation for Body<'_, C> {
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.failure.check()?;
        let Some(params) = self.params else {
            return Err(Error::NotStarted);
        };
        let total = u32::from(params.frames);
        if self.frame >= total {
            return Ok(Progress { done: total, total });
        }
        let (model, frame) = (params.model, self.frame);
        let age = params.age(frame);
        let phase = params.phase(frame);
        self.skeleton
            .pose_in_gait(model, params.table, age, params.gait, phase)
            .map_err(|e| match e {
                Error::Body(e) => Error::Body(e.at_age(age)),
                e => e,
            })?;
        sink.record(&Record::FrameStart { frame, time: age })?;
        for id in 0..model.mesh.vertex_count() {
            let Some(p) = model.mesh.vertex::<Fx>(id) else {
                continue;
            };
            let binding = self.skeleton.bind(&p)?;
            if frame == 0 && binding.is_nearest() {
                self.unbound += 1;
            }
            let q = self.skeleton.blend(&binding);
            sink.record(&Record::MeshVertex {
                id,
                p: [q.x, q.y, q.z],
            })?;
        }
        for i in 0..model.mesh.triangle_count() {
            if let Some(v) = model.mesh.triangle(i) {
                sink.record(&Record::Triangle { v })?;
            }
        }
        sink.record(&Record::FrameEnd { frame })?;
        self.frame += 1;
        Ok(Progress {
            done: self.frame,
            total,
        })
    }
}
