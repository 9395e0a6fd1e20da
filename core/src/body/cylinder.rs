//! The cylinder hierarchy (growth paper, Sec. 5): each cylinder encloses a
//! part of the body, hangs from a parent (a tree, root first), and carries
//! two features — point pairs fixed in its own space whose measured lengths
//! size it (Sec. 6).
//!
//! A cylinder is placed in model space by the centre of its base (its
//! origin, the joint with its parent), the centre of its other end (the
//! direction and length of its X axis), its radius and a roll about the
//! axis. Its rest rotation is `R = R_z·R_y·R_x(roll)` with R_z, R_y turning
//! X onto the axis, so an axis in a plane z = const keeps local Z = world Z
//! (the joint-bending axis of a leg seen from the side).

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use super::{BodyError, Label};
use crate::fx::{Angle, Fx, Real};
use crate::geom::{rot_x, rot_y, rot_z};

/// Where a feature's two points are given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Anchor {
    /// In model space, at the model's size (converted to the cylinder's
    /// space when the model is loaded).
    Model,
    /// In the cylinder's canonical space, where its length and radius are 1
    /// (the paper's convention): X along the axis, Y and Z across.
    Canonical,
}

/// What length a feature must have at a given age.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Drive {
    /// The table column's value itself: the feature is the measurement.
    Measured(u8),
    /// The feature keeps its model length scaled by the column's growth
    /// since the model's age: `model × value(age) / value(model age)`
    /// (a part that is not measured grows with a documented neighbour).
    Follows(u8),
    /// The feature is the lower part of the measured height `column`, and
    /// the part above it (the column's value at the model's age less the
    /// feature's model length) follows column `above`:
    /// `value(age) − (value(model age) − model) × above(age) / above(model
    /// age)`. Table 2's withers height is the leg below the elbow plus the
    /// trunk above it, whose depth is the chest depth: so the legs make
    /// the height the table measures at every age.
    Below {
        /// The measured height.
        column: u8,
        /// The column the part above the feature follows.
        above: u8,
    },
}

impl Drive {
    /// The table column that drives the feature.
    #[must_use]
    pub const fn column(self) -> u8 {
        match self {
            Drive::Measured(c) | Drive::Follows(c) | Drive::Below { column: c, .. } => c,
        }
    }

    /// Every table column the feature reads (the second is the first when
    /// it reads one).
    #[must_use]
    pub const fn columns(self) -> [u8; 2] {
        match self {
            Drive::Measured(c) | Drive::Follows(c) => [c, c],
            Drive::Below { column, above } => [column, above],
        }
    }
}

/// A length measurement between two points fixed in a cylinder's space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Feature {
    /// One end.
    pub from: [Fx; 3],
    /// The other end.
    pub to: [Fx; 3],
    /// The space `from` and `to` are given in.
    pub anchor: Anchor,
    /// Its length over age.
    pub drive: Drive,
}

/// One node of the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Cylinder {
    /// Its name (in errors and files).
    pub name: Label,
    /// Index of its parent, which comes earlier in the list; `None` for the
    /// root (exactly one, the first).
    pub parent: Option<u8>,
    /// Centre of the base, model space: the origin of its frame and its
    /// joint with the parent.
    pub base: [Fx; 3],
    /// Centre of the other end, model space.
    pub tip: [Fx; 3],
    /// Radius, model space.
    pub radius: Fx,
    /// Rotation about its own axis (moves the canonical Y and Z).
    pub roll: Angle,
    /// The two features that size it.
    pub features: [Feature; 2],
}

/// A point of model space as a vector.
#[must_use]
pub fn point<R: Real>(p: [Fx; 3]) -> Vector3<R> {
    Vector3::new(R::from_fx(p[0]), R::from_fx(p[1]), R::from_fx(p[2]))
}

/// The Euclidean length, scaled by the largest component first so that no
/// square overflows the fixed-point range (|v| up to the range itself).
#[must_use]
pub fn norm<R: Real>(v: &Vector3<R>) -> R {
    let big = v
        .iter()
        .fold(R::zero(), |m, x| if x.abs() > m { x.abs() } else { m });
    if big == R::zero() {
        return R::zero();
    }
    let u = v.map(|x| x.div(big));
    big * (u.x * u.x + u.y * u.y + u.z * u.z).sqrt()
}

/// A cylinder's placement in model space, derived once: `P_model =
/// origin + rotation · diag(length, radius, radius) · P_canonical`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rest<R: Real> {
    /// Rest rotation R_WB (model from local).
    pub rotation: Matrix3<R>,
    /// Base centre T_WB.
    pub origin: Vector3<R>,
    /// Model length L₀.
    pub length: R,
    /// Model radius R₀.
    pub radius: R,
}

impl<R: Real> Rest<R> {
    /// The placement of `cylinder`.
    ///
    /// # Errors
    /// [`BodyError::DegenerateCylinder`] when it has no length or radius.
    pub fn of(cylinder: &Cylinder) -> Result<Rest<R>, BodyError> {
        let origin = point::<R>(cylinder.base);
        let axis = point::<R>(cylinder.tip) - origin;
        let length = norm(&axis);
        let radius = R::from_fx(cylinder.radius);
        if length <= R::zero() || radius <= R::zero() {
            return Err(BodyError::DegenerateCylinder {
                cylinder: cylinder.name,
            });
        }
        let heading = R::atan2(axis.y, axis.x);
        let level = norm(&Vector3::new(axis.x, axis.y, R::zero()));
        let pitch = R::atan2(-axis.z, level);
        Ok(Rest {
            rotation: rot_z::<R>(heading) * rot_y::<R>(pitch) * rot_x::<R>(cylinder.roll),
            origin,
            length,
            radius,
        })
    }

    /// A model point in the cylinder's local frame (model size, not
    /// canonical): `R_WBᵀ·(p − T_WB)`.
    #[must_use]
    pub fn to_local(&self, p: &Vector3<R>) -> Vector3<R> {
        self.rotation.tr_mul(&(p - self.origin))
    }

    /// A feature's vector (`to − from`) in the local frame at model size.
    #[must_use]
    pub fn feature_vector(&self, feature: &Feature) -> Vector3<R> {
        let d = point::<R>(feature.to) - point::<R>(feature.from);
        match feature.anchor {
            Anchor::Model => self.rotation.tr_mul(&d),
            Anchor::Canonical => {
                Vector3::new(d.x * self.length, d.y * self.radius, d.z * self.radius)
            }
        }
    }
}

/// Checks the hierarchy: a root first, parents before children.
///
/// # Errors
/// [`BodyError::NoCylinders`] or [`BodyError::ParentOrder`].
pub fn validate_hierarchy(cylinders: &[Cylinder]) -> Result<(), BodyError> {
    let Some(root) = cylinders.first() else {
        return Err(BodyError::NoCylinders);
    };
    if root.parent.is_some() {
        return Err(BodyError::ParentOrder {
            cylinder: root.name,
        });
    }
    for (i, c) in cylinders.iter().enumerate().skip(1) {
        match c.parent {
            Some(p) if usize::from(p) < i => {}
            _ => return Err(BodyError::ParentOrder { cylinder: c.name }),
        }
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn n(v: Vector3<f64>) -> f64 {
        norm(&v)
    }

    fn cylinder(base: [i32; 3], tip: [i32; 3]) -> Cylinder {
        let p = |v: [i32; 3]| v.map(Fx::from_int);
        let f = Feature {
            from: [Fx::ZERO; 3],
            to: [Fx::ONE, Fx::ZERO, Fx::ZERO],
            anchor: Anchor::Canonical,
            drive: Drive::Follows(0),
        };
        Cylinder {
            name: Label::new("c"),
            parent: None,
            base: p(base),
            tip: p(tip),
            radius: Fx::from_int(2),
            roll: Angle::ZERO,
            features: [f, f],
        }
    }

    #[test]
    fn rest_rotation_turns_x_onto_the_axis_and_keeps_z_in_the_side_plane() {
        let c = cylinder([1, 5, 3], [1, -5, 3]); // a leg pointing down
        let r = Rest::<f64>::of(&c).unwrap();
        assert!((r.length - 10.0).abs() < 1e-12);
        let x = r.rotation * Vector3::x();
        assert!(n(x - Vector3::new(0.0, -1.0, 0.0)) < 1e-8);
        let z = r.rotation * Vector3::z();
        assert!(n(z - Vector3::z()) < 1e-8);
        // Local Y is forward (+x) for a downward axis: a positive bend about
        // local Z swings the tip forward.
        let y = r.rotation * Vector3::y();
        assert!(n(y - Vector3::x()) < 1e-8);
        // An axis with a z component.
        let c = cylinder([0, 0, 0], [3, 0, 4]);
        let r = Rest::<f64>::of(&c).unwrap();
        let x = r.rotation * Vector3::x();
        assert!(n(x - Vector3::new(0.6, 0.0, 0.8)) < 1e-8);
        let local = r.to_local(&Vector3::new(3.0, 0.0, 4.0));
        assert!(n(local - Vector3::new(5.0, 0.0, 0.0)) < 1e-8);
    }

    #[test]
    fn norm_does_not_overflow_fixed_point() {
        let v = Vector3::new(Fx::from_int(300), Fx::from_int(-400), Fx::ZERO);
        assert_eq!(norm(&v), Fx::from_int(500));
    }

    #[test]
    fn hierarchy_must_list_parents_first() {
        let mut a = cylinder([0, 0, 0], [1, 0, 0]);
        let mut b = a;
        b.parent = Some(0);
        assert_eq!(validate_hierarchy(&[a, b]), Ok(()));
        b.parent = Some(1);
        assert_eq!(
            validate_hierarchy(&[a, b]),
            Err(BodyError::ParentOrder { cylinder: b.name })
        );
        a.parent = Some(0);
        assert!(validate_hierarchy(&[a]).is_err());
        assert_eq!(validate_hierarchy(&[]), Err(BodyError::NoCylinders));
        let flat = cylinder([0, 0, 0], [0, 0, 0]);
        assert!(matches!(
            Rest::<Fx>::of(&flat),
            Err(BodyError::DegenerateCylinder { .. })
        ));
    }
}
