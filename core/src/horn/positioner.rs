//! The positioner P_i(θ) = T_i(θ)·R_z(α(θ))·R_y(0)·R_x(β(θ)) of a module
//! and the scale of its cross-section (horn paper, Secs. 4–6).
//!
//! The path K_i(θ) = T_i(θ)·0 is an arc of radius r in the x–y plane that
//! starts at the origin heading along +x and bends towards +y:
//! K(θ) = (r·sin α(θ), r·(1 − cos α(θ)), 0), so the positioner's x axis,
//! R_z(α)·x̂, is the path's tangent and the twist R_x(β) rolls the
//! positioner about it. Growth is α(θ) = α(T)·f(θ), β(θ) = β(T)·f(θ) with f
//! the module's sigmoid; the cross-section's scale runs from the
//! positioner's scale at θ = 0 to the lower base's at θ = T as
//! s(θ) = s_P + (s_L − s_P)·f(θ), so the module is a bent, twisted cone.

use nalgebra::Vector3;

use super::Module;
use crate::fx::{Angle, Real};
use crate::geom::Rigid;
use crate::growth::Sigmoid;

/// A module's growth: its parameters and the sigmoid f over its life.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth<'a> {
    /// The module.
    pub module: &'a Module,
    /// f(τ), with f(0) = 0 and f(T) = 1.
    pub sigmoid: &'a Sigmoid,
}

impl Growth<'_> {
    /// P_i(θ) at local time `theta` (days). P_i(0) is the identity exactly.
    #[must_use]
    pub fn positioner<R: Real>(&self, theta: R) -> Rigid<R> {
        let f = self.sigmoid.fraction(theta);
        let bend = f.scale_angle(self.module.bend);
        let twist = f.scale_angle(self.module.twist);
        let r = R::from_fx(self.module.path_radius);
        // Range: |K| ≤ 2r (≤ 40 cm in the presets).
        let path = Vector3::new(r * R::sin(bend), r * (R::one() - R::cos(bend)), R::zero());
        Rigid::positioner(path, bend, Angle::ZERO, twist)
    }

    /// The cross-section's scale s(θ) relative to L_1(T).
    #[must_use]
    pub fn scale<R: Real>(&self, theta: R) -> R {
        let (upper, lower) = (
            R::from_fx(self.module.positioner_scale),
            R::from_fx(self.module.base_scale),
        );
        let f = self.sigmoid.fraction(theta);
        upper + (lower - upper) * f
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::fx::Fx;

    /// One row of the horn paper's Table 1: scales in %, angles in
    /// degrees, path radius 20 cm (Sec. 6).
    const fn row(positioner: i32, base: i32, bend: i32, twist: i32) -> Module {
        Module {
            positioner_scale: Fx::from_ratio(positioner, 100),
            base_scale: Fx::from_ratio(base, 100),
            bend: Angle::from_degrees(bend),
            twist: Angle::from_degrees(twist),
            path_radius: Fx::from_int(20),
        }
    }

    /// Modules E_1 … E_3 of Table 1 (the ram horn's data is the
    /// `ram-horn` scenario; these rows are all the tests need).
    static TABLE_1: [Module; 3] = [
        row(30, 100, 75, 30),
        row(100, 137, 83, 33),
        row(137, 150, 59, 24),
    ];

    fn norm(v: Vector3<f64>) -> f64 {
        v.dot(&v).sqrt()
    }

    fn growth(i: usize) -> Growth<'static> {
        Growth {
            module: &TABLE_1[i],
            sigmoid: &Sigmoid::SEASONAL_YEAR,
        }
    }

    #[test]
    fn starts_at_identity_and_ends_at_the_full_bend() {
        let g = growth(0);
        assert_eq!(g.positioner(Fx::ZERO), Rigid::identity());
        assert_eq!(g.scale(Fx::ZERO), Fx::from_ratio(30, 100));
        assert_eq!(g.scale(Fx::from_int(365)), Fx::ONE);
        // At T: the tangent has turned by α(T) = 75° about z, the path is an
        // arc of 20 cm radius.
        let p = g.positioner(365.0f64);
        let a = 75f64.to_radians();
        assert!(
            norm(p.translation - Vector3::new(20.0 * a.sin(), 20.0 * (1.0 - a.cos()), 0.0)) < 1e-6
        );
        let tangent = p.apply_vector(&Vector3::x());
        assert!(norm(tangent - Vector3::new(a.cos(), a.sin(), 0.0)) < 1e-6);
        // The twist β(T) = 30° rolls the positioner about that tangent.
        let side = p.apply_vector(&Vector3::y());
        let untwisted = Vector3::new(-a.sin(), a.cos(), 0.0);
        assert!((side.dot(&untwisted) - 30f64.to_radians().cos()).abs() < 1e-6);
        assert!((side.dot(&Vector3::z()) - 30f64.to_radians().sin()).abs() < 1e-6);
    }

    #[test]
    fn the_path_is_tangent_to_the_positioner() {
        // dK/dθ is parallel to the positioner's x axis (no shear).
        let g = growth(2);
        for day in [30.0, 120.0, 151.5, 200.0, 330.0] {
            let h = 1e-4;
            let k = |t: f64| g.positioner(t).translation;
            let d = k(day + h) - k(day - h);
            let d = d / norm(d);
            let x = g.positioner(day).apply_vector(&Vector3::x());
            assert!(norm(d - x) < 1e-6, "day {day}: {d:?} vs {x:?}");
        }
    }
}
