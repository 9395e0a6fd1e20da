//! The posed hierarchy: every cylinder's growth at an age and its map from
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
use super::solve::{self, Growth};
use super::stance::{self, Part};
use super::{BodyModel, GrowthTable};
use crate::Error;
use crate::fx::Real;

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
    /// `joint(i, cylinder)` is cylinder i's motion from its rest pose.
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
        let lift = match self.ground {
            Some(ground) => stance::stand(
                &self.parts,
                &self.rests,
                &self.growth,
                &mut self.maps,
                ground,
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
        };
        for (w, g) in self.maps.iter_mut().zip(&self.growth) {
            w.translation.y += lift;
            *w = deformation(w, g);
        }
        Ok(())
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
