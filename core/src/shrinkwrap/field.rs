//! The skeleton's field V(r) = Σ ρ_i / |r − R_i| and its gradient (seed
//! `003_…`, eq. (6) and (12)), where R_i is the point of element i nearest
//! to r.

use nalgebra::Vector3;

use crate::fx::{Fx, Real};
use crate::geom::length_of_squared;

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

/// The number types the field is evaluated in: `f64` in its own
/// arithmetic ([`summed_field`]), [`Fx`] by an integer kernel that rounds
/// and saturates exactly as [`summed_field`] does on [`Fx`] but skips the
/// saturation where the range is proven (issue 15).
pub trait FieldReal: Real {
    /// V(r) and ∇V(r).
    fn field(elements: &[Element<Self>], r: &Vector3<Self>) -> (Self, Vector3<Self>) {
        summed_field(elements, r)
    }

    /// V(r) alone, as [`FieldReal::field`] gives it.
    fn potential(elements: &[Element<Self>], r: &Vector3<Self>) -> Self {
        Self::field(elements, r).0
    }
}

impl FieldReal for f64 {}

impl FieldReal for Fx {
    fn field(elements: &[Element<Fx>], r: &Vector3<Fx>) -> (Fx, Vector3<Fx>) {
        let (v, g) = fixed_field(elements, r, true);
        (v, Vector3::from(g))
    }

    fn potential(elements: &[Element<Fx>], r: &Vector3<Fx>) -> Fx {
        fixed_field(elements, r, false).0
    }
}

/// V(r) and ∇V(r).
#[must_use]
pub fn field<R: FieldReal>(elements: &[Element<R>], r: &Vector3<R>) -> (R, Vector3<R>) {
    R::field(elements, r)
}

/// V(r) alone: where only the level is asked, a third of the work.
#[must_use]
pub fn potential<R: FieldReal>(elements: &[Element<R>], r: &Vector3<R>) -> R {
    R::potential(elements, r)
}

/// V(r) and ∇V(r) in `R`'s own arithmetic, each summed in a wide
/// accumulator: the definition the [`Fx`] kernel of [`FieldReal`] follows
/// bit for bit.
#[must_use]
pub fn summed_field<R: Real>(elements: &[Element<R>], r: &Vector3<R>) -> (R, Vector3<R>) {
    let mut v = R::Wide::default();
    let mut g = [R::Wide::default(); 3];
    for e in elements {
        let (vi, gi) = contribution(e, r);
        v = R::widen(v, vi);
        for (gk, gik) in g.iter_mut().zip(gi.iter()) {
            *gk = R::widen(*gk, *gik);
        }
    }
    (
        R::narrow(v),
        Vector3::new(R::narrow(g[0]), R::narrow(g[1]), R::narrow(g[2])),
    )
}

/// One element's term of V(r) and of ∇V(r).
fn contribution<R: Real>(e: &Element<R>, r: &Vector3<R>) -> (R, Vector3<R>) {
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
    // ∇(ρ/|p|) = −ρ p / |p|³ = −(vi / d) · (p / d)
    let s = vi * inverse;
    (vi, p.map(|pk| -(s * (pk * inverse))))
}

/// Coordinates (Q16 bits) of magnitude below this, 2¹³ units, keep every
/// difference below 2³⁰ and every sum of three squares below 2⁶²: the
/// range in which [`fixed_field`] needs no saturating sum.
const NEAR: u32 = 1 << 29;

/// The bitwise or of the magnitudes: below [`NEAR`] exactly when each is.
fn spread(c: &[i32; 3]) -> u32 {
    c.iter().fold(0, |acc, x| acc | x.unsigned_abs())
}

/// `Real::dot` of Q32 bits: rounded half up to Q16, saturated.
fn q32_to_q16(q32: i64) -> i32 {
    Fx::narrow(q32.saturating_add(1 << 15) >> 16).to_bits()
}

/// u·w of Q16 bits within ±2³⁰, exact in Q32 (below 3·2⁶⁰).
fn dot_near(u: &[i32; 3], w: &[i32; 3]) -> i64 {
    u[0] as i64 * w[0] as i64 + u[1] as i64 * w[1] as i64 + u[2] as i64 * w[2] as i64
}

/// [`summed_field`] on [`Fx`], with ∇V only when `gradient` (one copy of
/// the code for both, for the firmware's flash): elements
/// and points within ±[`NEAR`] take the same roundings and saturations on
/// Q16 bits without the saturation of sums that cannot overflow; others
/// take [`contribution`].
fn fixed_field(elements: &[Element<Fx>], r: &Vector3<Fx>, gradient: bool) -> (Fx, [Fx; 3]) {
    let rb = [r.x, r.y, r.z].map(Fx::to_bits);
    let r_near = spread(&rb) < NEAR;
    let mut v = 0i64;
    let mut g = [0i64; 3];
    for e in elements {
        let a = e.a.map(Fx::to_bits);
        let b = e.b.map(Fx::to_bits);
        if !r_near || (spread(&a) | spread(&b)) >= NEAR {
            let (vi, gi) = contribution(e, r);
            v = v.saturating_add(vi.to_bits() as i64);
            for (gk, gik) in g.iter_mut().zip(gi.iter()) {
                *gk = gk.saturating_add(gik.to_bits() as i64);
            }
            continue;
        }
        // Every coordinate is below 2²⁹ in magnitude, so each difference
        // below is below 2³⁰, and each sum of three products below 2⁶².
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let dd = q32_to_q16(dot_near(&d, &d));
        // `Element::nearest`.
        let nearest = if dd <= 0 {
            a
        } else {
            let ra = [rb[0] - a[0], rb[1] - a[1], rb[2] - a[2]];
            let along = q32_to_q16(dot_near(&ra, &d));
            // t = along / dd rounded as `Fx::saturating_div` (dd > 0); the
            // ends are compared before the saturation, which keeps them.
            let (n, dd) = ((along as i64) << 16, dd as i64);
            let t = if n >= 0 {
                (n + dd / 2) / dd
            } else {
                -((dd / 2 - n) / dd)
            };
            if t <= 0 {
                a
            } else if t >= 1 << 16 {
                b
            } else {
                // 0 < t < 1: a + d·t lies between a and b.
                let t = Fx::from_bits(t as i32);
                [0, 1, 2].map(|k| a[k] + Fx::from_bits(d[k]).saturating_mul(t).to_bits())
            }
        };
        // The nearest point lies between a and b: |p| < 2³⁰.
        let p = [rb[0] - nearest[0], rb[1] - nearest[1], rb[2] - nearest[2]];
        let distance = length_of_squared(dot_near(&p, &p) as u64).max(min_distance());
        // 1 / distance rounded as `Fx::saturating_div`: distance ≥ 2⁻¹²,
        // so the quotient is positive and at most 2¹².
        let distance = distance.to_bits() as i64;
        let inverse = ((1i64 << 32) + distance / 2) / distance;
        let vi = weight_times(e.weight, inverse);
        // As `Real::widen`: saturating, like the generic terms above.
        v = v.saturating_add(vi as i64);
        if gradient {
            let s = weight_times(Fx::from_bits(vi), inverse);
            for (gk, pk) in g.iter_mut().zip(p) {
                // |p_k| ≤ |p| ≤ distance + ½ and inverse ≤ 2³²/distance + ½,
                // so |p_k · inverse| < 2³³ and p_k / distance fits in Q16.
                let unit = ((pk as i64 * inverse + (1 << 15)) >> 16) as i32;
                let term = Fx::from_bits(s).saturating_mul(Fx::from_bits(unit));
                *gk = gk.saturating_add((-term).to_bits() as i64);
            }
        }
    }
    (Fx::narrow(v), g.map(Fx::narrow))
}

/// `x · inverse` rounded and saturated as `Fx` multiplication (inverse ≤ 2²⁸).
fn weight_times(x: Fx, inverse: i64) -> i32 {
    x.saturating_mul(Fx::from_bits(inverse as i32)).to_bits()
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

    /// The integer kernel is [`summed_field`] on [`Fx`] bit for bit: for
    /// skeletons from a unit to the edge of the range (inside and outside
    /// the kernel's near range), points on, near and far from them,
    /// segments of every length down to none, and any weight.
    #[test]
    fn the_fixed_kernel_is_the_summed_field() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for case in 0..20_000 {
            // Coordinates of magnitude up to 2^scale LSB.
            let scale = 8 + case % 24;
            let coordinate =
                |next: &mut dyn FnMut() -> u64| Fx::from_bits((next() as i32) >> (31 - scale));
            let point = |next: &mut dyn FnMut() -> u64| {
                Vector3::new(coordinate(next), coordinate(next), coordinate(next))
            };
            let elements: std::vec::Vec<Element<Fx>> = (0..1 + case % 5)
                .map(|k| {
                    let a = point(&mut next);
                    let weight = Fx::from_bits((next() as i32) >> (next() % 32));
                    match k % 3 {
                        0 => Element::point(a, weight),
                        1 => Element::segment(a, point(&mut next), weight),
                        _ => {
                            let tiny = Vector3::new(Fx::DELTA, Fx::ZERO, -Fx::DELTA);
                            Element::segment(a, a + tiny, weight)
                        }
                    }
                })
                .collect();
            let near = Vector3::from(elements[0].a).map(|c| c + Fx::from_bits(next() as i32 >> 20));
            for r in [point(&mut next), near, Vector3::from(elements[0].b)] {
                let summed = summed_field(&elements, &r);
                assert_eq!(field(&elements, &r), summed, "{elements:?} at {r:?}");
                assert_eq!(potential(&elements, &r), summed.0, "{elements:?} at {r:?}");
            }
        }
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
