//! Binding a vertex to the cylinders that contain it, and blending their
//! motions (growth paper, Sec. 6).
//!
//! The paper weights a vertex inside several cylinders "inversely
//! proportional to the distance from the point to the axis" and notes it
//! has not studied continuity; the original program allowed at most two
//! cylinders and aborted beyond. Here:
//!
//! - every containing cylinder counts, up to [`MAX_BINDINGS`] (an error
//!   naming the limit beyond);
//! - the raw weight is `taper / max(d, R₀/8)`: inverse distance to the
//!   axis, floored near the axis, times a taper that falls linearly to zero
//!   over the outer quarter of the radius and the last eighth of the length
//!   at each end. Without the taper a weight jumps from 0 to 1/d where a
//!   vertex enters a cylinder, tearing the mesh where cylinders overlap;
//!   with it every weight is continuous in the vertex position;
//! - weights are normalised, then the rounding remainder goes to the
//!   largest weight (ties: the first), so in fixed point they sum to
//!   exactly [`Fx::ONE`] and none is negative;
//! - a vertex with no positive weight (in no cylinder, or on the very edge
//!   of one) follows the nearest cylinder alone and is reported as such.

use nalgebra::Vector3;

use super::chain::Affine;
use super::cylinder::{Rest, norm};
use crate::Error;
use crate::fx::{Fx, Real};

/// Capacity: cylinders blended at one vertex.
pub const MAX_BINDINGS: usize = 8;

/// The distance floor near the axis, as a fraction of the radius.
pub const AXIS_FLOOR: Fx = Fx::from_ratio(1, 8);
/// The width of the radial taper, as a fraction of the radius.
pub const RADIAL_TAPER: Fx = Fx::from_ratio(1, 4);
/// The width of the taper at each end, as a fraction of the length.
pub const AXIAL_TAPER: Fx = Fx::from_ratio(1, 8);

/// The cylinders a vertex follows, with its position in each one's local
/// frame and the normalised weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binding<R: Real> {
    count: u8,
    cylinders: [u8; MAX_BINDINGS],
    weights: [R; MAX_BINDINGS],
    local: [Vector3<R>; MAX_BINDINGS],
    nearest: bool,
}

impl<R: Real> Binding<R> {
    /// Number of cylinders.
    #[must_use]
    pub fn len(&self) -> usize {
        usize::from(self.count).min(MAX_BINDINGS)
    }

    /// Whether the binding is empty (never, once built by [`bind`]).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The weights, in cylinder order.
    #[must_use]
    pub fn weights(&self) -> &[R] {
        &self.weights[..self.len()]
    }

    /// The cylinder indices.
    #[must_use]
    pub fn cylinders(&self) -> &[u8] {
        &self.cylinders[..self.len()]
    }

    /// Whether the vertex lies in no cylinder and follows the nearest.
    #[must_use]
    pub fn is_nearest(&self) -> bool {
        self.nearest
    }

    /// The deformed position: `Σ wᵢ·mapᵢ(localᵢ)` with `maps` indexed by
    /// cylinder (see [`super::chain::deformation`]).
    #[must_use]
    pub fn blend(&self, maps: &[Affine<R>]) -> Vector3<R> {
        let mut sum = Vector3::zeros();
        for i in 0..self.len() {
            if let Some(map) = maps.get(usize::from(self.cylinders[i])) {
                sum += map.apply(&self.local[i]) * self.weights[i];
            }
        }
        sum
    }
}

/// `x` limited to at most one.
fn at_most_one<R: Real>(x: R) -> R {
    if x > R::one() { R::one() } else { x }
}

/// The larger of two values.
fn larger<R: Real>(a: R, b: R) -> R {
    if a > b { a } else { b }
}

/// Binds model point `p` to the cylinders `rests` (in hierarchy order).
///
/// # Errors
/// [`Error::Capacity`] (`MAX_BINDINGS`) when more cylinders contain it.
pub fn bind<R: Real>(rests: &[Rest<R>], p: &Vector3<R>) -> Result<Binding<R>, Error> {
    let mut b = Binding {
        count: 0,
        cylinders: [0; MAX_BINDINGS],
        weights: [R::zero(); MAX_BINDINGS],
        local: [Vector3::zeros(); MAX_BINDINGS],
        nearest: false,
    };
    let (floor, radial_taper, axial_taper) = (
        R::from_fx(AXIS_FLOOR),
        R::from_fx(RADIAL_TAPER),
        R::from_fx(AXIAL_TAPER),
    );
    let mut total = R::zero();
    // Nearest cylinder so far: (index, local point, distance outside).
    let mut nearest: Option<(usize, Vector3<R>, R)> = None;
    for (c, rest) in rests.iter().enumerate() {
        let q = rest.to_local(p);
        let d = norm(&Vector3::new(R::zero(), q.y, q.z));
        let along = larger(R::zero(), larger(-q.x, q.x - rest.length));
        let across = larger(R::zero(), d - rest.radius);
        let outside = norm(&Vector3::new(along, across, R::zero()));
        if nearest.as_ref().is_none_or(|n| outside < n.2) {
            nearest = Some((c, q, outside));
        }
        if outside > R::zero() {
            continue;
        }
        let to_end = if q.x < rest.length - q.x {
            q.x
        } else {
            rest.length - q.x
        };
        let taper = at_most_one((rest.radius - d).div(radial_taper * rest.radius))
            * at_most_one(to_end.div(axial_taper * rest.length));
        let raw = taper.div(larger(d, floor * rest.radius));
        if raw <= R::zero() {
            continue;
        }
        let k = b.len();
        if k == MAX_BINDINGS {
            return Err(Error::Capacity {
                limit: "MAX_BINDINGS",
                capacity: MAX_BINDINGS as u32,
            });
        }
        // Indices fit u8: the hierarchy holds at most 255 cylinders.
        b.cylinders[k] = c as u8;
        b.weights[k] = raw;
        b.local[k] = q;
        b.count += 1;
        total += raw;
    }
    if b.count == 0 {
        if let Some((c, q, _)) = nearest {
            b.cylinders[0] = c as u8;
            b.weights[0] = R::one();
            b.local[0] = q;
            b.count = 1;
            b.nearest = true;
        }
        return Ok(b);
    }
    // Normalise; each quotient is rounded, so hand the remainder (a few
    // LSB of either sign) to the largest weight: Σ = 1 exactly, and the
    // largest (≥ 1/n) stays far above the remainder, so none is negative.
    let n = b.len();
    let mut sum = R::zero();
    let mut largest = 0;
    for i in 0..n {
        b.weights[i] = b.weights[i].div(total);
        sum += b.weights[i];
        if b.weights[i] > b.weights[largest] {
            largest = i;
        }
    }
    b.weights[largest] += R::one() - sum;
    Ok(b)
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::body::Label;
    use crate::body::cylinder::{Anchor, Cylinder, Drive, Feature};
    use crate::fx::Angle;

    fn rest(base: [i32; 3], tip: [i32; 3], radius: i32) -> Rest<Fx> {
        let f = Feature {
            from: [Fx::ZERO; 3],
            to: [Fx::ONE, Fx::ZERO, Fx::ZERO],
            anchor: Anchor::Canonical,
            drive: Drive::Follows(0),
        };
        Rest::of(&Cylinder {
            name: Label::new("c"),
            parent: None,
            base: base.map(Fx::from_int),
            tip: tip.map(Fx::from_int),
            radius: Fx::from_int(radius),
            roll: Angle::ZERO,
            features: [f, f],
        })
        .unwrap()
    }

    fn p(x: i32, y: i32, z: i32) -> Vector3<Fx> {
        Vector3::new(Fx::from_int(x), Fx::from_int(y), Fx::from_int(z))
    }

    #[test]
    fn inverse_distance_inside_and_nearest_outside() {
        let rests = [
            rest([0, 0, 0], [40, 0, 0], 10),
            rest([20, 20, 0], [20, -40, 0], 10),
        ];
        // In both, 2 from the first axis and 3 from the second: weights 3:2
        // (both tapers are 1 there).
        let b = bind(&rests, &p(23, -2, 0)).unwrap();
        assert_eq!(b.cylinders(), &[0, 1]);
        let w = b.weights();
        assert_eq!(w[0] + w[1], Fx::ONE);
        assert!((w[0].to_f64() - 0.6).abs() < 1e-4, "{w:?}");
        // Outside both: 20 from the first's side, 5 from the second's.
        let b = bind(&rests, &p(35, -30, 0)).unwrap();
        assert!(b.is_nearest());
        assert_eq!(b.cylinders(), &[1]);
        assert_eq!(b.weights(), &[Fx::ONE]);
    }

    #[test]
    fn too_many_cylinders_is_an_error_naming_the_limit() {
        let rests = [rest([0, 0, 0], [10, 0, 0], 5); MAX_BINDINGS + 1];
        assert_eq!(
            bind(&rests, &p(5, 1, 0)),
            Err(Error::Capacity {
                limit: "MAX_BINDINGS",
                capacity: MAX_BINDINGS as u32
            })
        );
        let b = bind(&rests[..MAX_BINDINGS], &p(5, 1, 0)).unwrap();
        assert_eq!(b.len(), MAX_BINDINGS);
        assert_eq!(b.weights().iter().fold(Fx::ZERO, |s, w| s + *w), Fx::ONE);
    }
}
