//! The compound solid Z(t) (horn paper, Sec. 7) as rings of points: the
//! generic kernel behind the `Fx` stream and its `f64` reference.
//!
//! [`HornKernel::place`] applies Eq. 1 and chains the positioners from the
//! skull outwards: module k's frame is the skull's, and module i−1's is
//! module i's carried by P_i(τ_i) (only the youngest positioner moves; the
//! others are at τ = T). [`HornKernel::emit`] then sweeps each module's
//! cross-sections (Algorithm 1), oldest module (the tip) first, each from
//! its upper base (θ = 0) to its lower base (θ = τ_i), emitting only the
//! renderable part V_i(τ) — rings with θ_j = j·T/J ≤ τ_i, then the active
//! area at θ = τ_i when it falls between two of them. The part U_i(τ) still
//! inside the skull is not emitted.
//!
//! Continuity is by construction: the upper base of module i and the lower
//! base of module i−1 are the same points carried by the same transform
//! W_i·P_i(τ_i), and their scales are the same number (checked by
//! [`HornParams::validate`]).
//!
//! State: the resampled outline and one transform per module — memory
//! O(k + points per ring); nothing of the mesh is stored.

use nalgebra::Vector3;

use super::positioner::Growth;
use super::{HornParams, LocalTime, MAX_MODULES, Moment, Outline};
use crate::Error;
use crate::fx::Real;
use crate::geom::Rigid;

/// What the kernel emits, in order: per module and ring a `Ring` header
/// followed by its `points` `Point`s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emit<R: Real> {
    /// A cross-section starts.
    Ring {
        /// Module index i (1-based, the tip is 1).
        module: u16,
        /// Ring j within the module (0 is the upper base).
        ring: u16,
        /// Number of points that follow.
        points: u16,
    },
    /// A point of the current ring, in the skull frame (cm).
    Point(Vector3<R>),
}

/// The horn kernel over a scalar `R`.
#[derive(Clone, Debug)]
pub struct HornKernel<'a, R: Real> {
    params: &'a HornParams<'a>,
    outline: Outline<R>,
    /// `upper[i]` = W_i·P_i(τ_i): module i's upper base in the skull frame,
    /// which is also module i−1's frame W_{i−1} (0-based indices).
    upper: [Rigid<R>; MAX_MODULES],
    /// Eq. 1 at the placed time.
    local: LocalTime,
}

impl<'a, R: Real> HornKernel<'a, R> {
    /// A kernel for `params`, validated, with the outline resampled.
    ///
    /// # Errors
    /// See [`HornParams::validate`] and [`Outline::resample`].
    pub fn new(params: &'a HornParams<'a>) -> Result<Self, Error> {
        params.validate()?;
        Ok(HornKernel {
            params,
            outline: Outline::resample(params.outline, params.ring_points)?,
            upper: [Rigid::identity(); MAX_MODULES],
            local: LocalTime {
                youngest: 0,
                tau: Moment::new(0, 1),
            },
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &'a HornParams<'a> {
        self.params
    }

    /// The growth of module `index` (0-based).
    fn growth(&self, index: usize) -> Option<Growth<'a>> {
        let params = self.params;
        params.modules.get(index).map(|module| Growth {
            module,
            sigmoid: &params.growth,
        })
    }

    /// P_i(θ) of module `module` (1-based) at local time `theta` in days.
    #[must_use]
    pub fn positioner(&self, module: u16, theta: R) -> Option<Rigid<R>> {
        self.growth(usize::from(module).checked_sub(1)?)
            .map(|g| g.positioner(theta))
    }

    /// Places the horn at global time `t` (a fraction of T): Eq. 1, then
    /// the chain of positioners. Returns the youngest module and its τ.
    ///
    /// # Errors
    /// [`super::HornError::PastLastModule`] when t ≤ 0 or t > k·T.
    pub fn place(&mut self, t: Moment) -> Result<LocalTime, Error> {
        let local = t
            .local()
            .filter(|l| l.youngest as usize <= self.params.modules.len())
            .ok_or(super::HornError::PastLastModule)?;
        let delay = self.params.delay_days;
        let youngest = local.youngest as usize; // ≤ k ≤ MAX_MODULES (validated)
        let mut carried = Rigid::identity(); // W_i, from the skull outwards
        for index in (0..youngest).rev() {
            let tau = if index + 1 == youngest {
                local.tau
            } else {
                Moment::new(1, 1)
            };
            let positioner = match self.growth(index) {
                Some(g) => g.positioner(tau.days::<R>(delay)),
                None => Rigid::identity(),
            };
            carried = if index + 1 == youngest {
                positioner // W_k is the identity: keep P_k(τ) exact
            } else {
                carried.compose(&positioner)
            };
            if let Some(slot) = self.upper.get_mut(index) {
                *slot = carried;
            }
        }
        self.local = local;
        Ok(local)
    }

    /// Eq. 1 at the last placed time (`youngest` is 0 before any `place`).
    #[must_use]
    pub fn local_time(&self) -> LocalTime {
        self.local
    }

    /// W_i: module `module`'s (1-based) frame in the skull frame, at the
    /// placed time; `None` for a module that does not exist yet.
    #[must_use]
    pub fn placement(&self, module: u16) -> Option<Rigid<R>> {
        let youngest = self.local.youngest as usize;
        let m = usize::from(module);
        if m == 0 || m > youngest {
            None
        } else if m == youngest {
            Some(Rigid::identity())
        } else {
            self.upper.get(m).copied()
        }
    }

    /// Module `index`'s (0-based) local time at the placed time.
    fn tau(&self, index: usize) -> Moment {
        if index + 1 == self.local.youngest as usize {
            self.local.tau
        } else {
            Moment::new(1, 1)
        }
    }

    /// The rings of module `index` (0-based) at local time `tau`: the last
    /// full ring j with θ_j ≤ τ, and whether the active area at τ follows.
    fn ring_span(&self, tau: Moment) -> (u16, bool) {
        let j = u32::from(self.params.rings_per_module);
        // floor(τ·J / T) with τ = num/den of T; ≤ J since τ ≤ T.
        let last =
            (u64::from(tau.num) * u64::from(j) / u64::from(tau.den.max(1))).min(u64::from(j));
        let partial = !Moment::new(last as u32, j).same(tau);
        (last as u16, partial)
    }

    /// Number of rings the placed frame emits.
    #[must_use]
    pub fn ring_count(&self) -> u32 {
        (0..self.local.youngest as usize)
            .map(|index| {
                let (last, partial) = self.ring_span(self.tau(index));
                u32::from(last) + 1 + u32::from(partial)
            })
            .sum()
    }

    /// Emits the placed frame's rings, module 1 (the tip) first.
    ///
    /// # Errors
    /// The first error `out` returns.
    pub fn emit(&self, out: &mut dyn FnMut(Emit<R>) -> Result<(), Error>) -> Result<(), Error> {
        let delay = self.params.delay_days;
        let j = self.params.rings_per_module;
        for index in 0..self.local.youngest as usize {
            let Some(growth) = self.growth(index) else {
                break;
            };
            let upper = self
                .upper
                .get(index)
                .copied()
                .unwrap_or_else(Rigid::identity);
            // W_i: where module i's own frame (and its active area) is.
            let own = self
                .placement((index + 1) as u16)
                .unwrap_or_else(Rigid::identity);
            let tau = self.tau(index);
            let (last, partial) = self.ring_span(tau);
            for ring in 0..=last + u16::from(partial) {
                let theta = if ring > last {
                    tau
                } else {
                    Moment::new(u32::from(ring), u32::from(j))
                };
                let theta_days = theta.days::<R>(delay);
                // W_i·P_i(τ)·P_i(θ)⁻¹, with the two ends exact: θ = 0 is the
                // upper base (P_i(0) = I), θ = τ the active area.
                let place = if ring == 0 {
                    upper
                } else if theta.same(tau) {
                    own
                } else {
                    upper.compose(&growth.positioner(theta_days).inverse())
                };
                let scale = growth.scale(theta_days);
                out(Emit::Ring {
                    module: (index + 1) as u16,
                    ring,
                    points: self.outline.len(),
                })?;
                for &[y, z] in self.outline.points() {
                    let local = Vector3::new(R::zero(), y * scale, z * scale);
                    out(Emit::Point(place.apply_point(&local)))?;
                }
            }
        }
        Ok(())
    }
}
