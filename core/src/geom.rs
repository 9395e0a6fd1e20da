//! Vectors and rigid transforms on nalgebra types, generic over [`Real`]:
//! translation T, the right-handed rotations R_x, R_y, R_z, composition and
//! the exact rigid inverse (horn paper, Sec. 4: P = T·R_z·R_y·R_x; its
//! printed R_x has typos, the standard matrix is used here).

use nalgebra::{Matrix3, Matrix4, Vector3};

use crate::fx::{Angle, Fx, Real};
pub use crate::fx::{dot_wide, length};

/// A 3-vector of any [`Real`].
pub type Vec3<R = Fx> = Vector3<R>;

/// First estimates of √n for n = k·2⁵⁶ + f (k = 64‥255, f < 2⁵⁶): round(√(k + ½)·2¹²)
/// (192 × 2 B = 384 B, computed by the compiler), within 0.4 % of √n / 2¹⁶.
const ROOT_ESTIMATES: [u16; 192] = {
    let mut table = [0u16; 192];
    let mut k = 0;
    while k < 192 {
        // round(√y) = ⌈⌊√(4y)⌋ / 2⌉ with y = (k + 64 + ½)·2²⁴.
        let four_y = (2 * (k as u64 + 64) + 1) << 25;
        table[k] = four_y.isqrt().div_ceil(2) as u16;
        k += 1;
    }
    table
};

/// ⌊√x⌋ in a few instructions where `u64::isqrt` needs a few dozen: x is
/// scaled by 4ʲ into [2⁶², 2⁶⁴), √ of that is estimated from
/// [`ROOT_ESTIMATES`] to ε ≤ 0.004, two Newton steps take the error to
/// ε²/2 ≈ 8·10⁻⁶ and then below 0.2 (of a result < 2³²), and one
/// correction after scaling back gives the floor.
#[must_use]
fn floor_sqrt(x: u64) -> u64 {
    if x == 0 {
        return 0;
    }
    // Even, so that √ scales back by a shift; x << shift has one of its
    // top two bits set.
    let shift = x.leading_zeros() & !1;
    let n = x << shift;
    // n ≥ 2⁶², so the top byte is 64‥255.
    let estimate = ROOT_ESTIMATES
        .get((n >> 56) as usize - 64)
        .map_or(u64::from(u32::MAX), |&e| u64::from(e) << 16);
    // Newton steps from any y > 0 stay ≥ ⌊√n⌋ and, from y ≥ 2³¹, below
    // 2³³ + 2³², so the sums cannot overflow (n / y ≤ 2³³).
    let y = (estimate + n / estimate) / 2;
    // y ≥ 2³¹; `max` spares the division its zero check.
    let y = (y + n / y.max(1)) / 2;
    // y ∈ {⌊√n⌋, ⌊√n⌋ + 1}, so r ∈ {⌊√x⌋, ⌊√x⌋ + 1}.
    let r = y >> (shift / 2);
    // r² > x implies r ≥ 1: no underflow.
    if r.checked_mul(r).is_none_or(|square| square > x) {
        r - 1
    } else {
        r
    }
}

/// The length whose square is `squared_q32` (Q32 bits, as [`dot_wide`]
/// gives it), rounded to nearest and saturated exactly as [`length`]
/// rounds it, by [`floor_sqrt`]: the shrinkwrap takes one per skeleton
/// element per field evaluation (issue 15).
#[must_use]
pub fn length_of_squared(squared_q32: u64) -> Fx {
    let r = floor_sqrt(squared_q32); // Q16
    // r² ≤ squared_q32: no underflow. Round up when the rest exceeds r,
    // i.e. squared_q32 ≥ (r + ½)².
    let rounded = if squared_q32 - r * r > r { r + 1 } else { r };
    Fx::from_bits(rounded.min(i32::MAX as u64) as i32)
}

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

    /// `floor_sqrt` is `u64::isqrt` at every bucket edge of the table, at
    /// squares and their neighbours over the whole range, and at random.
    #[test]
    fn floor_sqrt_is_isqrt() {
        let check = |x: u64| assert_eq!(floor_sqrt(x), x.isqrt(), "{x}");
        for x in 0..1 << 16 {
            check(x);
        }
        for k in 64..=256u64 {
            for shift in 0..=56 {
                let edge = (k << 56) >> shift;
                for x in [edge.wrapping_sub(1), edge, edge.wrapping_add(1)] {
                    check(x);
                }
            }
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = state >> (state % 64);
            let r = x.isqrt();
            for y in [x, r * r, (r * r).wrapping_sub(1), r * r + 2 * r] {
                check(y);
            }
        }
        check(u64::MAX);
        check(u64::from(u32::MAX) * u64::from(u32::MAX));
    }

    #[test]
    fn length_of_squared_is_length() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let c = |k: u32| Fx::from_bits((state >> k) as i32 >> (state % 31));
            let v = Vector3::new(c(0), c(16), c(32));
            assert_eq!(length_of_squared(dot_wide(&v, &v) as u64), length(&v));
        }
        let extreme = Vector3::new(Fx::MIN, Fx::MIN, Fx::MIN);
        assert_eq!(
            length_of_squared(dot_wide(&extreme, &extreme) as u64),
            Fx::MAX
        );
    }

    #[test]
    fn wide_length() {
        let v = Vector3::new(Fx::from_int(300), Fx::from_int(400), Fx::ZERO);
        assert_eq!(length(&v), Fx::from_int(500)); // 300² overflows Fx, not the accumulator
    }
}
