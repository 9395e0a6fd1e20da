//! The posed hierarchy (growth paper, Secs. 5–7): every cylinder's growth
//! at an age and its map from
//! model space to the deformed world, for a pose of the joints — the
//! kernel that [`super::Body`] runs in fixed point and tests run in `f64`.
//!
//! The feet stay on the ground ([`super::stance`]): after the chain is
//! evaluated the trunk pitches so that the lowest fore and hind soles are
//! level and the body is lifted or lowered so that they touch the model's
//! ground (in a trot these are the supporting hooves, so the body bobs). A
//! body without fore and hind supports is lifted so that its lowest
//! cylinder-axis end stays where it is in the model.

use heapless::Vec;
use nalgebra::Vector3;

use super::binding::{Binding, bind};
use super::chain::{Affine, Joint, deformation, link, root};
use super::cylinder::{Anchor, Cylinder, Rest, point, validate_hierarchy};
use super::gait::{Gait, gravity};
use super::solve::{self, Growth};
use super::stance::{self, Part};
use super::{BodyModel, GrowthTable};
use crate::Error;
use crate::fx::{Fx, Real};

/// A hierarchy of at most `C` cylinders, sized and posed.
#[derive(Clone, Debug)]
pub struct Skeleton<R: Real, const C: usize> {
    rests: Vec<Rest<R>, C>,
    growth: Vec<Growth<R>, C>,
    maps: Vec<Affine<R>, C>,
    model_ground: Option<R>,
    parts: Vec<Part<R>, C>,
    ground: Option<R>,
}

impl<R: Real, const C: usize> Default for Skeleton<R, C> {
    fn default() -> Self {
        Skeleton::new()
    }
}

fn capacity<const C: usize>() -> Error {
    Error::Capacity {
        limit: "MAX_CYLINDERS",
        capacity: C as u32,
    }
}

impl<R: Real, const C: usize> Skeleton<R, C> {
    /// An empty skeleton (`const`, for a `static`).
    #[must_use]
    pub const fn new() -> Self {
        Skeleton {
            rests: Vec::new(),
            growth: Vec::new(),
            maps: Vec::new(),
            model_ground: None,
            parts: Vec::new(),
            ground: None,
        }
    }

    /// Places `model`'s cylinders and checks the model against `table`.
    ///
    /// # Errors
    /// [`Error::Capacity`] (`MAX_CYLINDERS`) when the model has more than
    /// `C` cylinders (or more than 255); the model's [`super::BodyError`]s.
    pub fn load(&mut self, model: &BodyModel<'_>, table: &GrowthTable<'_>) -> Result<(), Error> {
        self.rests.clear();
        self.growth.clear();
        self.maps.clear();
        self.model_ground = None;
        self.parts.clear();
        self.ground = None;
        if model.cylinders.len() > C || model.cylinders.len() > usize::from(u8::MAX) {
            return Err(capacity::<C>());
        }
        table.validate()?;
        validate_hierarchy(model.cylinders)?;
        model.mesh.validate()?;
        let mut ground: Option<R> = None;
        for c in model.cylinders {
            let rest = Rest::<R>::of(c)?;
            solve::check(c, &rest, table)?;
            let tip_y = rest.origin.y + rest.rotation[(1, 0)] * rest.length;
            for y in [rest.origin.y, tip_y] {
                if ground.is_none_or(|g| y < g) {
                    ground = Some(y);
                }
            }
            self.rests.push(rest).map_err(|_| capacity::<C>())?;
        }
        self.model_ground = ground;
        if let Some((parts, ground)) = ground.and_then(|g| stance::parts(model, &self.rests, g)) {
            self.parts = parts;
            self.ground = Some(ground);
        }
        Ok(())
    }

    /// Sizes every cylinder at `age` (months) and poses the joints:
    /// `joint(i, cylinder)` is cylinder i's motion from its rest pose. The
    /// lowest fore and hind hooves stand on the ground.
    ///
    /// # Errors
    /// A cylinder's [`super::BodyError::NegativeSize`] (or the errors of
    /// [`Skeleton::load`] if the model changed).
    pub fn pose(
        &mut self,
        model: &BodyModel<'_>,
        table: &GrowthTable<'_>,
        age: R,
        joint: &dyn Fn(usize, &Cylinder) -> Joint,
    ) -> Result<(), Error> {
        self.chain(model, table, age, joint)?;
        let lift = self.stand(&|_| true);
        self.finish(lift);
        Ok(())
    }

    /// Poses the body at `age` in `gait` at `phase` ∈ [0, 1) of the stride
    /// (at rest without a gait). With the gait's footfall timing only the
    /// hooves on the ground at `phase` support the body; when none is (a
    /// trot's suspension) the body flies: its root follows the ballistic
    /// path, under the table unit's gravity, from where it stood at the
    /// last lift-off to where it stands at the next touchdown, and no
    /// hoof goes below the ground.
    ///
    /// # Errors
    /// As [`Skeleton::pose`].
    pub fn pose_in_gait(
        &mut self,
        model: &BodyModel<'_>,
        table: &GrowthTable<'_>,
        age: R,
        gait: Option<&Gait<'_>>,
        phase: Fx,
    ) -> Result<(), Error> {
        let joint_at = |phase: Fx| {
            move |_: usize, c: &Cylinder| gait.map_or(Joint::REST, |g| g.joint(c.name, phase))
        };
        let footfall = gait.and_then(|g| g.footfall.map(|f| (g, f)));
        let Some((gait, footfall)) = footfall.filter(|_| self.ground.is_some()) else {
            return self.pose(model, table, age, &joint_at(phase));
        };
        let name = |i: usize| model.cylinders.get(i).map(|c| c.name);
        let support = |i: usize| self.parts.get(i).is_some_and(|p| p.end.is_some());
        // The phase since each hoof's touchdown.
        let since = |i: usize, at: Fx| {
            name(i)
                .and_then(|n| gait.touchdown(n))
                .map(|t| Fx::from_bits((at - t).to_bits() & 0xFFFF))
        };
        let on = |i: usize, at: Fx| name(i).is_some_and(|n| gait.on_ground(n, at));
        let count = self.parts.len();
        if (0..count).any(|i| support(i) && on(i, phase)) {
            self.chain(model, table, age, &joint_at(phase))?;
            let lift = self.stand(&|i| on(i, phase));
            self.finish(lift);
            return Ok(());
        }
        // In the air: since the last lift-off and until the next touchdown.
        let duty = footfall.duty_factor;
        let (mut flown, mut ahead) = (Fx::ONE, Fx::ONE);
        for i in (0..count).filter(|&i| support(i)) {
            if let Some(s) = since(i, phase) {
                flown = flown.min(s - duty);
                ahead = ahead.min(Fx::ONE - s);
            }
        }
        let flight = flown + ahead;
        let eps = Fx::from_ratio(1, 1024);
        // Where the trunk's centre stood at lift-off (the hooves that left the
        // ground) and will stand at touchdown (the hooves that land).
        let mut stood = [R::zero(); 2];
        for (k, at) in [phase - flown, phase + ahead].into_iter().enumerate() {
            self.chain(model, table, age, &joint_at(at))?;
            let lift = self.stand(&|i| {
                since(i, at).is_some_and(|s| {
                    let edge = if k == 0 { duty } else { Fx::ZERO };
                    (s - edge).abs() < eps || (k == 1 && Fx::ONE - s < eps)
                })
            });
            stood[k] = self.root_height() + lift;
        }
        self.chain(model, table, age, &joint_at(phase))?;
        let lowest = self.stand(&|_| true);
        let share = if flight > Fx::ZERO {
            R::from_fx(flown.div(flight))
        } else {
            R::zero()
        };
        // Seconds flown and still to fly; the parabola g/2·τ·(T − τ) above
        // the chord, g·τ first (a length per second, of order 100).
        let bump = gravity(table.unit).map_or(R::zero(), |g| {
            let (tau, rest) = (
                R::from_fx(flown * footfall.stride_seconds),
                R::from_fx(ahead * footfall.stride_seconds),
            );
            R::from_fx(g) * tau * rest * R::from_ratio(1, 2)
        });
        let path = stood[0] + (stood[1] - stood[0]) * share + bump;
        let lift = path - self.root_height();
        self.finish(if lift > lowest { lift } else { lowest });
        Ok(())
    }

    /// Sizes every cylinder and evaluates the chain (before the stance).
    fn chain(
        &mut self,
        model: &BodyModel<'_>,
        table: &GrowthTable<'_>,
        age: R,
        joint: &dyn Fn(usize, &Cylinder) -> Joint,
    ) -> Result<(), Error> {
        self.growth.clear();
        self.maps.clear();
        let model_age = R::from_fx(model.model_age);
        for (i, (c, rest)) in model.cylinders.iter().zip(self.rests.iter()).enumerate() {
            let g = solve::solve(c, rest, table, age, model_age)?;
            let j = joint(i, c);
            let world = match c.parent {
                None => root(rest, &j),
                Some(p) => {
                    let p = usize::from(p);
                    match (self.maps.get(p), self.rests.get(p), self.growth.get(p)) {
                        (Some(w), Some(r), Some(pg)) => w.compose(&link(r, pg, rest, &j)),
                        _ => return Err(super::BodyError::ParentOrder { cylinder: c.name }.into()),
                    }
                }
            };
            self.growth.push(g).map_err(|_| capacity::<C>())?;
            self.maps.push(world).map_err(|_| capacity::<C>())?;
        }
        Ok(())
    }

    /// The height of the trunk's centre (the root's axis midpoint, near
    /// the centre of mass) before the lift.
    fn root_height(&self) -> R {
        match (self.maps.first(), self.rests.first(), self.growth.first()) {
            (Some(w), Some(rest), Some(g)) => {
                let half = rest.length * g.length * R::from_ratio(1, 2);
                w.apply(&Vector3::new(half, R::zero(), R::zero())).y
            }
            _ => R::zero(),
        }
    }

    /// Pitches the trunk on the supports `on(i)` and returns the lift that
    /// stands the body (see [`stance::stand`]); a body without fore and
    /// hind supports keeps its lowest axis end at the model's ground.
    fn stand(&mut self, on: &dyn Fn(usize) -> bool) -> R {
        match self.ground {
            Some(ground) => stance::stand(
                &self.parts,
                &self.rests,
                &self.growth,
                &mut self.maps,
                ground,
                on,
            )
            .unwrap_or_else(R::zero),
            None => {
                // Keep the lowest axis end at the model's ground.
                let mut lowest: Option<R> = None;
                for ((w, g), rest) in self.maps.iter().zip(&self.growth).zip(&self.rests) {
                    let tip = w.apply(&Vector3::new(g.length * rest.length, R::zero(), R::zero()));
                    for y in [w.translation.y, tip.y] {
                        if lowest.is_none_or(|l| y < l) {
                            lowest = Some(y);
                        }
                    }
                }
                match (self.model_ground, lowest) {
                    (Some(g), Some(l)) => g - l,
                    _ => R::zero(),
                }
            }
        }
    }

    /// Lifts the posed chain and applies the growth.
    fn finish(&mut self, lift: R) {
        for (w, g) in self.maps.iter_mut().zip(&self.growth) {
            w.translation.y += lift;
            *w = deformation(w, g);
        }
    }

    /// The cylinders a model point follows, with weights.
    ///
    /// # Errors
    /// [`Error::Capacity`] (`MAX_BINDINGS`).
    pub fn bind(&self, p: &Vector3<R>) -> Result<Binding<R>, Error> {
        bind(&self.rests, p)
    }

    /// The deformed position of a bound point at the last [`Skeleton::pose`].
    #[must_use]
    pub fn blend(&self, binding: &Binding<R>) -> Vector3<R> {
        binding.blend(&self.maps)
    }

    /// The deformed position of model point `p` at the last [`Skeleton::pose`].
    ///
    /// # Errors
    /// As [`Skeleton::bind`].
    pub fn deform(&self, p: &Vector3<R>) -> Result<Vector3<R>, Error> {
        Ok(self.bind(p)?.blend(&self.maps))
    }

    /// Where cylinder `c` alone takes model point `p` (no blending).
    #[must_use]
    pub fn follow(&self, c: usize, p: &Vector3<R>) -> Option<Vector3<R>> {
        Some(self.maps.get(c)?.apply(&self.rests.get(c)?.to_local(p)))
    }

    /// Cylinder `c`'s growth at the last pose.
    #[must_use]
    pub fn growth(&self, c: usize) -> Option<Growth<R>> {
        self.growth.get(c).copied()
    }

    /// Cylinder `c`'s rest placement.
    #[must_use]
    pub fn rest(&self, c: usize) -> Option<&Rest<R>> {
        self.rests.get(c)
    }

    /// The length of feature `i` of `cylinder` (index `c`) in the deformed
    /// world: both points carried by the cylinder's own map.
    #[must_use]
    pub fn feature_length(&self, cylinder: &Cylinder, c: usize, i: usize) -> Option<R> {
        let f = cylinder.features.get(i)?;
        let rest = self.rests.get(c)?;
        let (a, b) = (point::<R>(f.from), point::<R>(f.to));
        let (a, b) = match f.anchor {
            Anchor::Model => (rest.to_local(&a), rest.to_local(&b)),
            Anchor::Canonical => {
                let s = |p: Vector3<R>| {
                    Vector3::new(p.x * rest.length, p.y * rest.radius, p.z * rest.radius)
                };
                (s(a), s(b))
            }
        };
        let map = self.maps.get(c)?;
        Some(super::cylinder::norm(&(map.apply(&b) - map.apply(&a))))
    }
}
