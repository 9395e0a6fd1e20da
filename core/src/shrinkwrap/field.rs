//! The skeleton's field V(r) = Σ ρ_i / |r − R_i| and its gradient (seed
//! `003_…`, eq. (6) and (12)), where R_i is the point of element i nearest
//! to r.

use nalgebra::Vector3;

use crate::fx::{Fx, Real};

/// One skeleton element: the segment from `a` to `b` (a point when
/// `a == b`) with weight ρ.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Element<R: Real = Fx> {
    /// One end.
    pub a: [R; 3],
    /// The other end (`a` again for a point).
    pub b: [R; 3],
    /// ρ: the surface of this element alone, at level V0, lies ρ / V0 from it.
    pub weight: R,
}

impl<R: Real> Element<R> {
    /// A point element.
    #[must_use]
    pub fn point(p: Vector3<R>, weight: R) -> Element<R> {
        Element::segment(p, p, weight)
    }

    /// A segment element.
    #[must_use]
    pub fn segment(a: Vector3<R>, b: Vector3<R>, weight: R) -> Element<R> {
        Element {
            a: [a.x, a.y, a.z],
            b: [b.x, b.y, b.z],
            weight,
        }
    }

    /// The element in another number type (e.g. the `f64` reference).
    #[must_use]
    pub fn convert<S: Real>(&self, f: impl Fn(R) -> S) -> Element<S> {
        Element {
            a: self.a.map(&f),
            b: self.b.map(&f),
            weight: f(self.weight),
        }
    }

    /// R_i: the point of the element nearest to `r`.
    #[must_use]
    pub fn nearest(&self, r: &Vector3<R>) -> Vector3<R> {
        let a = Vector3::from(self.a);
        let d = Vector3::from(self.b) - a;
        let dd = R::dot(&d, &d);
        if dd <= R::zero() {
            return a;
        }
        let t = R::dot(&(r - a), &d).div(dd);
        if t <= R::zero() {
            a
        } else if t >= R::one() {
            Vector3::from(self.b)
        } else {
            a + d * t
        }
    }
}

/// The distance below which an element counts as touching, 2⁻¹²: V stays
/// finite, and a vertex this close to the skeleton has collapsed anyway.
fn min_distance<R: Real>() -> R {
    R::from_ratio(1, 4096)
}

/// V(r) and ∇V(r), each summed in a wide accumulator.
#[must_use]
pub fn field<R: Real>(elements: &[Element<R>], r: &Vector3<R>) -> (R, Vector3<R>) {
    let mut v = R::Wide::default();
    let mut g = [R::Wide::default(); 3];
    for e in elements {
        let p = r - e.nearest(r);
        let d = R::norm(&p);
        let d = if d < min_distance() {
            min_distance()
        } else {
            d
        };
        // One division per element (the MCU has no 64-bit divider).
        let inverse = R::one().div(d);
        let vi = e.weight * inverse;
        v = R::widen(v, vi);
        // ∇(ρ/|p|) = −ρ p / |p|³ = −(vi / d) · (p / d)
        let s = vi * inverse;
        for (gk, pk) in g.iter_mut().zip(p.iter()) {
            *gk = R::widen(*gk, -(s * (*pk * inverse)));
        }
    }
    (
        R::narrow(v),
        Vector3::new(R::narrow(g[0]), R::narrow(g[1]), R::narrow(g[2])),
    )
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn fx3(x: f64, y: f64, z: f64) -> Vector3<Fx> {
        Vector3::new(x, y, z).map(|c| Fx::from_fixed(fixed::types::I16F16::from_num(c)))
    }

    #[test]
    fn a_point_gives_rho_over_distance() {
        let e = [Element::point(fx3(1.0, 2.0, 3.0), Fx::from_int(2))];
        let (v, g) = field(&e, &fx3(1.0, 6.0, 3.0));
        assert_eq!(v, Fx::HALF);
        // −ρ/d² along +y
        assert_eq!(g, fx3(0.0, -0.125, 0.0));
    }

    #[test]
    fn a_segment_measures_to_its_nearest_point() {
        let e = Element::segment(fx3(0.0, 0.0, 0.0), fx3(0.0, 4.0, 0.0), Fx::ONE);
        assert_eq!(e.nearest(&fx3(2.0, 1.5, 0.0)), fx3(0.0, 1.5, 0.0));
        assert_eq!(e.nearest(&fx3(2.0, -1.0, 0.0)), fx3(0.0, 0.0, 0.0));
        assert_eq!(e.nearest(&fx3(2.0, 9.0, 1.0)), fx3(0.0, 4.0, 0.0));
    }

    #[test]
    fn the_gradient_matches_a_finite_difference_in_f64() {
        let e: [Element<f64>; 3] = [
            Element::segment(
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(0.0, 5.0, 0.0),
                1.0,
            ),
            Element::point(Vector3::new(0.5, 5.5, 0.2), 0.7),
            Element::point(Vector3::new(-0.4, -0.3, 0.0), 0.6),
        ];
        for r in [
            Vector3::new(1.2, 2.0, 0.3),
            Vector3::new(-0.8, 6.0, -0.5),
            Vector3::new(0.3, -1.1, 0.9),
        ] {
            let (_, g) = field(&e, &r);
            let h = 1e-6;
            for k in 0..3 {
                let mut dr = Vector3::zeros();
                dr[k] = h;
                let numeric = (field(&e, &(r + dr)).0 - field(&e, &(r - dr)).0) / (2.0 * h);
                assert!((numeric - g[k]).abs() < 1e-6, "{numeric} vs {}", g[k]);
            }
        }
    }

    #[test]
    fn fixed_point_field_is_within_a_few_lsb_of_f64() {
        let e = [
            Element::segment(fx3(0.0, 0.0, 0.0), fx3(0.0, 5.0, 0.0), Fx::ONE),
            Element::point(fx3(0.5, 5.5, 0.25), Fx::from_ratio(7, 10)),
        ];
        let ef: [Element<f64>; 2] = e.map(|x| x.convert(f64::from_fx));
        let r = fx3(0.75, 3.0, -0.5);
        let (v, g) = field(&e, &r);
        let (vf, gf) = field(&ef, &r.map(f64::from_fx));
        let lsb = 1.0 / 65_536.0;
        assert!((v.to_f64() - vf).abs() < 8.0 * lsb);
        for k in 0..3 {
            assert!((g[k].to_f64() - gf[k]).abs() < 16.0 * lsb);
        }
    }
}
