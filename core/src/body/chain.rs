//! The transform chain from a cylinder's space up to the world (growth
//! paper, Secs. 5 and 7), with joint rotations and scales.
//!
//! The paper takes a point from child B's canonical space to its parent A's
//! canonical space by `P_A = T_AB·G_A⁻¹·R_AB·R·S·G_B·P_B`, where G = diag(L,
//! R, R, 1) is the growth matrix, `R_AB = R_AW·R_WB` the rest rotation of B
//! in A, T_AB the translation to B's origin in A's canonical space, and R,
//! S a joint rotation and scale in B's frame; the root's `M_WA = T·R·G`
//! takes it to the world.
//!
//! Here every frame is kept at its real size, `Q = G·P` (the cylinder's
//! local frame, in table units), which turns the chain into
//! `Q_A = T(G_A·t_AB)·R_AB·R·S·Q_B` — the same product with `G_A·G_A⁻¹`
//! cancelled, so I16F16 never divides by a length and multiplies it back.
//! `G_A·t_AB` is B's origin in A's local frame at A's current size: a
//! joint moves with the growth of its parent, and a child's growth never
//! leaks into its parent (the paper's "absolute" growth matrices).

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use super::cylinder::Rest;
use super::solve::Growth;
use crate::fx::{Angle, Fx, Real};
use crate::geom::{rot_y, rot_z};

/// A linear map plus a translation: `p ↦ linear·p + translation` (rigid
/// unless a joint scales).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine<R: Real> {
    /// The linear part.
    pub linear: Matrix3<R>,
    /// The translation.
    pub translation: Vector3<R>,
}

impl<R: Real> Affine<R> {
    /// The identity.
    #[must_use]
    pub fn identity() -> Affine<R> {
        Affine {
            linear: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// `self · other`: apply `other` first.
    #[must_use]
    pub fn compose(&self, other: &Affine<R>) -> Affine<R> {
        Affine {
            linear: self.linear * other.linear,
            translation: self.linear * other.translation + self.translation,
        }
    }

    /// The image of a point.
    #[must_use]
    pub fn apply(&self, p: &Vector3<R>) -> Vector3<R> {
        self.linear * p + self.translation
    }
}

/// A joint's motion in the cylinder's own frame, measured from the rest
/// position the cylinder was placed in (Sec. 7, Fig. 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Joint {
    /// Rotation about the local Z axis (for a cylinder in a side plane:
    /// the flexion seen from the side; positive turns the tip from X
    /// towards local Y).
    pub bend: Angle,
    /// Rotation about the local Y axis (abduction), applied before `bend`.
    pub turn: Angle,
    /// Uniform scale of the cylinder and everything below it (S).
    pub scale: Fx,
}

impl Joint {
    /// No motion.
    pub const REST: Joint = Joint {
        bend: Angle::ZERO,
        turn: Angle::ZERO,
        scale: Fx::ONE,
    };

    /// A bend alone.
    #[must_use]
    pub const fn bend(bend: Angle) -> Joint {
        Joint {
            bend,
            ..Joint::REST
        }
    }

    /// `R·S` = R_z(bend)·R_y(turn)·scale.
    #[must_use]
    pub fn matrix<R: Real>(&self) -> Matrix3<R> {
        let r = rot_z::<R>(self.bend) * rot_y::<R>(self.turn);
        if self.scale == Fx::ONE {
            r
        } else {
            r * R::from_fx(self.scale)
        }
    }
}

/// The root's frame: `T_WA·R_WA·R·S` (its growth is applied to its points).
#[must_use]
pub fn root<R: Real>(rest: &Rest<R>, joint: &Joint) -> Affine<R> {
    Affine {
        linear: rest.rotation * joint.matrix::<R>(),
        translation: rest.origin,
    }
}

/// The link from child B's local frame to parent A's:
/// `T(G_A·t_AB)·R_AB·R·S`, with `t_AB` B's origin in A's canonical space.
#[must_use]
pub fn link<R: Real>(
    parent: &Rest<R>,
    parent_growth: &Growth<R>,
    child: &Rest<R>,
    joint: &Joint,
) -> Affine<R> {
    // G_A·t_AB = diag(L/L₀, R/R₀, R/R₀)·(B's origin in A's local frame at
    // model size).
    let offset = parent.to_local(&child.origin);
    let grown = Vector3::new(
        offset.x * parent_growth.length,
        offset.y * parent_growth.radius,
        offset.z * parent_growth.radius,
    );
    Affine {
        linear: parent.rotation.tr_mul(&child.rotation) * joint.matrix::<R>(),
        translation: grown,
    }
}

/// The map from a model point, given in the cylinder's local frame at model
/// size (`Rest::to_local`), to its deformed world position:
/// `world · G·G₀⁻¹` with `world` the chain up to the world.
#[must_use]
pub fn deformation<R: Real>(world: &Affine<R>, growth: &Growth<R>) -> Affine<R> {
    let g = Matrix3::from_diagonal(&Vector3::new(growth.length, growth.radius, growth.radius));
    Affine {
        linear: world.linear * g,
        translation: world.translation,
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use nalgebra::Matrix4;

    use super::*;
    use crate::body::Label;
    use crate::body::cylinder::{Anchor, Cylinder, Drive, Feature, norm as n};

    fn cylinder(base: [f64; 3], tip: [f64; 3], radius: f64, parent: Option<u8>) -> Cylinder {
        let fx = |v: f64| Fx::from_bits((v * 65_536.0).round() as i32);
        let f = Feature {
            from: [Fx::ZERO; 3],
            to: [Fx::ONE, Fx::ZERO, Fx::ZERO],
            anchor: Anchor::Canonical,
            drive: Drive::Follows(0),
        };
        Cylinder {
            name: Label::new("c"),
            parent,
            base: base.map(fx),
            tip: tip.map(fx),
            radius: fx(radius),
            roll: Angle::ZERO,
            features: [f, f],
        }
    }

    fn homogeneous(linear: Matrix3<f64>, t: Vector3<f64>) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&linear);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&t);
        m
    }

    /// The paper's chain with 4×4 matrices and canonical coordinates,
    /// literally: P_W = M_WA·T_AB·G_A⁻¹·R_AB·R·S·G_B·P_B.
    #[test]
    fn real_size_chain_equals_the_papers_canonical_chain() {
        let a = cylinder([0.0, 40.0, 0.0], [50.0, 42.0, 0.0], 12.0, None);
        let b = cylinder([30.0, 30.0, 6.0], [31.0, 10.0, 6.0], 3.0, Some(0));
        let (ra, rb) = (Rest::<f64>::of(&a).unwrap(), Rest::<f64>::of(&b).unwrap());
        let (ga, gb) = (
            Growth {
                length: 0.8,
                radius: 1.3,
            },
            Growth {
                length: 1.2,
                radius: 0.7,
            },
        );
        let joint = Joint {
            bend: Angle::from_degrees(25),
            turn: Angle::from_degrees(-10),
            scale: Fx::from_ratio(11, 10),
        };
        // Ours.
        let world_a = root(&ra, &Joint::REST);
        let world_b = world_a.compose(&link(&ra, &ga, &rb, &joint));
        let map_b = deformation(&world_b, &gb);
        // The paper's: canonical P_B, G = diag(L, R, R, 1) absolute.
        let g = |r: &Rest<f64>, g: &Growth<f64>| {
            Matrix4::from_diagonal(&nalgebra::Vector4::new(
                r.length * g.length,
                r.radius * g.radius,
                r.radius * g.radius,
                1.0,
            ))
        };
        let (g_a, g_b) = (g(&ra, &ga), g(&rb, &gb));
        // M_AW = M_WA⁻¹ = S₀⁻¹·Rᵀ·T⁻¹, written out (no matrix inversion).
        let inv_diag = |d: nalgebra::Vector4<f64>| Matrix4::from_diagonal(&d.map(|x| 1.0 / x));
        let m_aw0 = inv_diag(nalgebra::Vector4::new(ra.length, ra.radius, ra.radius, 1.0))
            * homogeneous(ra.rotation.transpose(), Vector3::zeros())
            * homogeneous(Matrix3::identity(), -ra.origin);
        let t_ab = m_aw0 * rb.origin.push(1.0);
        let t_ab = homogeneous(Matrix3::identity(), t_ab.xyz());
        let r_ab = homogeneous(ra.rotation.transpose() * rb.rotation, Vector3::zeros());
        let rs = homogeneous(joint.matrix::<f64>(), Vector3::zeros());
        let m_wa = homogeneous(ra.rotation, ra.origin) * g_a;
        let g_a_inv = inv_diag(g_a.diagonal());
        let chain = m_wa * t_ab * g_a_inv * r_ab * rs * g_b;
        for p_model in [
            Vector3::new(30.5, 25.0, 7.0),
            Vector3::new(31.0, 12.0, 4.0),
            Vector3::new(29.0, 29.0, 6.0),
        ] {
            let local = rb.to_local(&p_model);
            let canonical = Vector3::new(
                local.x / rb.length,
                local.y / rb.radius,
                local.z / rb.radius,
            );
            let paper = (chain * canonical.push(1.0)).xyz();
            let ours = map_b.apply(&local);
            assert!(n(&(paper - ours)) < 1e-9, "{paper} vs {ours}");
        }
    }

    #[test]
    fn the_model_pose_is_the_identity() {
        let a = cylinder([0.0, 40.0, 0.0], [50.0, 42.0, 0.0], 12.0, None);
        let b = cylinder([30.0, 30.0, 6.0], [31.0, 10.0, 6.0], 3.0, Some(0));
        let (ra, rb) = (Rest::<Fx>::of(&a).unwrap(), Rest::<Fx>::of(&b).unwrap());
        let world_b =
            root(&ra, &Joint::REST).compose(&link(&ra, &Growth::model(), &rb, &Joint::REST));
        let p = Vector3::new(Fx::from_int(30), Fx::from_int(20), Fx::from_int(7));
        let back = deformation(&world_b, &Growth::model()).apply(&rb.to_local(&p));
        for (x, y) in back.iter().zip(p.iter()) {
            // atan2 and sin/cos rounding of the rest rotations, over |p| ≈ 40.
            assert!((x.to_bits() - y.to_bits()).abs() <= 128, "{back} vs {p}");
        }
    }
}
