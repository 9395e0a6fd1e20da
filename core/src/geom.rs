//! Vectors and rigid transforms on nalgebra types, generic over [`Real`]:
//! translation T, the right-handed rotations R_x, R_y, R_z, composition and
//! the exact rigid inverse (horn paper, Sec. 4: P = T·R_z·R_y·R_x; its
//! printed R_x has typos, the standard matrix is used here).

use nalgebra::{Matrix3, Matrix4, Vector3};

use crate::fx::{Angle, Fx, Real};
pub use crate::fx::{dot_wide, length, length_of_squared};

/// A 3-vector of any [`Real`].
pub type Vec3<R = Fx> = Vector3<R>;

/// The rotation about the x axis by `a` (standard right-handed).
#[must_use]
pub fn rot_x<R: Real>(a: Angle) -> Matrix3<R> {
    let (s, c) = (R::sin(a), R::cos(a));
    let (o, l) = (R::zero(), R::one());
    Matrix3::new(l, o, o, o, c, -s, o, s, c)
}

/// The rotation about the y axis by `a`.
#[must_use]
pub fn rot_y<R: Real>(a: Angle) -> Matrix3<R> {
    let (s, c) = (R::sin(a), R::cos(a));
    let (o, l) = (R::zero(), R::one());
    Matrix3::new(c, o, s, o, l, o, -s, o, c)
}

/// The rotation about the z axis by `a`.
#[must_use]
pub fn rot_z<R: Real>(a: Angle) -> Matrix3<R> {
    let (s, c) = (R::sin(a), R::cos(a));
    let (o, l) = (R::zero(), R::one());
    Matrix3::new(c, -s, o, s, c, o, o, o, l)
}

/// A rigid motion `p ↦ R·p + t`: a rotation followed by a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid<R: Real = Fx> {
    /// The rotation part (orthonormal up to rounding).
    pub rotation: Matrix3<R>,
    /// The translation part.
    pub translation: Vector3<R>,
}

impl<R: Real> Rigid<R> {
    /// The identity motion.
    #[must_use]
    pub fn identity() -> Self {
        Rigid {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// A pure translation T.
    #[must_use]
    pub fn translation(t: Vector3<R>) -> Self {
        Rigid {
            rotation: Matrix3::identity(),
            translation: t,
        }
    }

    /// A pure rotation.
    #[must_use]
    pub fn rotation(rotation: Matrix3<R>) -> Self {
        Rigid {
            rotation,
            translation: Vector3::zeros(),
        }
    }

    /// The positioner form of the horn paper, `T·R_z(z)·R_y(y)·R_x(x)`.
    #[must_use]
    pub fn positioner(t: Vector3<R>, z: Angle, y: Angle, x: Angle) -> Self {
        Rigid {
            rotation: rot_z::<R>(z) * rot_y::<R>(y) * rot_x::<R>(x),
            translation: t,
        }
    }

    /// `self · other`: apply `other` first, then `self`.
    #[must_use]
    pub fn compose(&self, other: &Self) -> Self {
        Rigid {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// The image of a point.
    #[must_use]
    pub fn apply_point(&self, p: &Vector3<R>) -> Vector3<R> {
        self.rotation * p + self.translation
    }

    /// The image of a direction (translation ignored).
    #[must_use]
    pub fn apply_vector(&self, v: &Vector3<R>) -> Vector3<R> {
        self.rotation * v
    }

    /// The exact rigid inverse: `Rᵀ` and `−Rᵀ·t` (no matrix inversion).
    #[must_use]
    pub fn inverse(&self) -> Self {
        let rt = self.rotation.transpose();
        Rigid {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// The 4×4 homogeneous matrix.
    #[must_use]
    pub fn to_homogeneous(&self) -> Matrix4<R> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotation);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest deviation of `m` from the identity, in LSB.
    fn off_identity(m: &Matrix4<Fx>) -> i32 {
        let id = Matrix4::<Fx>::identity();
        m.iter()
            .zip(id.iter())
            .map(|(a, b)| (a.to_bits() - b.to_bits()).abs())
            .max()
            .unwrap_or(0)
    }

    fn angles() -> impl Iterator<Item = Angle> {
        (0..97u32).map(|i| Angle(i.wrapping_mul(0x02A3_D70B) ^ 0x5555))
    }

    #[test]
    fn rotations_are_orthonormal_within_six_lsb() {
        for a in angles() {
            for r in [
                rot_x::<Fx>(a),
                rot_y(a),
                rot_z(a),
                rot_z::<Fx>(a) * rot_y::<Fx>(a + Angle::QUARTER) * rot_x::<Fx>(-a),
            ] {
                let rrt = Rigid::rotation(r * r.transpose()).to_homogeneous();
                assert!(
                    off_identity(&rrt) <= 6,
                    "R·Rᵀ off by {} LSB at {a:?}",
                    off_identity(&rrt)
                );
            }
        }
    }

    #[test]
    fn composition_with_the_inverse_is_identity() {
        // Bound: rotation block ≤ 6 LSB; translation ≤ 6 LSB per unit of |t|.
        for (i, a) in angles().enumerate() {
            let t = Vector3::new(
                Fx::from_int(i as i32 - 40),
                Fx::from_ratio(7, 3),
                Fx::from_int(12),
            );
            let m = Rigid::positioner(t, a, a + a, Angle(a.0 / 3));
            let both = m.compose(&m.inverse());
            let rotation = off_identity(&Rigid::rotation(both.rotation).to_homogeneous());
            assert!(rotation <= 6, "M·M⁻¹ rotation off by {rotation} LSB");
            let budget = 6 * (1 + length(&t).floor_int());
            let drift = both
                .translation
                .iter()
                .map(|x| x.to_bits().abs())
                .max()
                .unwrap_or(0);
            assert!(
                drift <= budget,
                "M·M⁻¹ translation off by {drift} LSB > {budget}"
            );
        }
    }

    #[test]
    fn positioner_order_is_t_rz_ry_rx() {
        // Applying P to x̂: R_x leaves x̂ alone, R_y(90°) sends it to −ẑ, R_z leaves ẑ alone.
        let p = Rigid::<Fx>::positioner(
            Vector3::new(Fx::ONE, Fx::ZERO, Fx::ZERO),
            Angle::QUARTER,
            Angle::QUARTER,
            Angle::QUARTER,
        );
        let x = p.apply_point(&Vector3::x());
        assert_eq!(x, Vector3::new(Fx::ONE, Fx::ZERO, -Fx::ONE));
        // ŷ: R_x(90°) → ẑ, R_y(90°) → x̂, R_z(90°) → ŷ.
        assert_eq!(p.apply_vector(&Vector3::y()), Vector3::y());
        let h = p.to_homogeneous();
        let composed = Rigid::translation(p.translation).to_homogeneous()
            * Rigid::rotation(rot_z(Angle::QUARTER)).to_homogeneous()
            * Rigid::rotation(rot_y(Angle::QUARTER)).to_homogeneous()
            * Rigid::rotation(rot_x(Angle::QUARTER)).to_homogeneous();
        assert_eq!(h, composed);
    }

    #[test]
    fn right_handed_rotations() {
        let q = Angle::QUARTER;
        assert_eq!(rot_z::<Fx>(q) * Vector3::x(), Vector3::y());
        assert_eq!(rot_x::<Fx>(q) * Vector3::y(), Vector3::z());
        assert_eq!(rot_y::<Fx>(q) * Vector3::z(), Vector3::x());
    }

    #[test]
    fn fixed_and_f64_transforms_agree() {
        for a in angles() {
            let pf = Rigid::<Fx>::positioner(
                Vector3::new(Fx::from_int(3), Fx::ONE, Fx::HALF),
                a,
                -a,
                a + a,
            );
            let pd = Rigid::<f64>::positioner(Vector3::new(3.0, 1.0, 0.5), a, -a, a + a);
            let v = pf.apply_point(&Vector3::new(
                Fx::from_int(10),
                Fx::from_int(-4),
                Fx::from_int(2),
            ));
            let w = pd.apply_point(&Vector3::new(10.0, -4.0, 2.0));
            // Bound: 4 LSB per unit of the point's and translation's size (|p| + |t| < 15).
            for (x, y) in v.iter().zip(w.iter()) {
                assert!((x.to_f64() - y).abs() < 4.0 * 15.0 / 65536.0, "{x} vs {y}");
            }
        }
    }

    #[test]
    fn wide_length() {
        let v = Vector3::new(Fx::from_int(300), Fx::from_int(400), Fx::ZERO);
        assert_eq!(length(&v), Fx::from_int(500)); // 300² overflows Fx, not the accumulator
    }
}
