//! The skeleton's field V(r) = Σ ρ_i / |r − R_i| and its gradient (seed
//! `003_…`, eq. (6) and (12)), where R_i is the point of element i nearest
//! to r.

use heapless::Vec;
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
/// arithmetic ([`summed_field`]), [`Fx`] by an integer kernel on prepared
/// elements that rounds and saturates exactly as [`summed_field`] does on
/// [`Fx`] but skips the saturation where the range is proven (issue 15).
pub trait FieldReal: Real {
    /// The element in the integer form of the kernel, if this number type
    /// has one and the element is in its range.
    fn prepare(_element: &Element<Self>) -> Option<PreparedElement> {
        None
    }

    /// V(r) of `field`'s skeleton, and ∇V(r) when `gradient` (zero
    /// otherwise).
    fn field_of(
        field: &SkeletonField<'_, Self>,
        r: &Vector3<Self>,
        gradient: bool,
    ) -> (Self, Vector3<Self>) {
        let (v, g) = summed_field(field.elements, r);
        (
            v,
            if gradient {
                g
            } else {
                Vector3::from([Self::zero(); 3])
            },
        )
    }
}

impl FieldReal for f64 {}

impl FieldReal for Fx {
    fn prepare(element: &Element<Fx>) -> Option<PreparedElement> {
        PreparedElement::new(element)
    }

    /// The kernel on the prepared elements at points within ±8192 units (`NEAR`);
    /// elsewhere, and for a skeleton left unprepared, [`summed_field`]
    /// itself.
    fn field_of(
        field: &SkeletonField<'_, Fx>,
        r: &Vector3<Fx>,
        gradient: bool,
    ) -> (Fx, Vector3<Fx>) {
        let rb = [r.x, r.y, r.z].map(Fx::to_bits);
        if field.prepared.len() != field.elements.len() || spread(&rb) >= NEAR {
            let (v, g) = summed_field(field.elements, r);
            return (v, if gradient { g } else { Vector3::zeros() });
        }
        // At most PREPARED_ELEMENTS = 2⁶ terms, each an i32: the sums stay
        // below 2³⁷, where `Real::widen`'s saturation never acts.
        let mut v = 0i64;
        let mut g = [0i64; 3];
        for e in field.prepared {
            let p = e.offset(&rb);
            let inverse = inverse_distance(length_of_squared(dot_near(&p, &p) as u64));
            let vi = weight_times(e.weight, inverse);
            v = v.wrapping_add(vi as i64);
            if gradient {
                // ∇(ρ/|p|) = −ρ p / |p|³ = −(vi / d) · (p / d), as
                // `contribution` rounds it.
                let s = Fx::from_bits(weight_times(Fx::from_bits(vi), inverse));
                for (gk, pk) in g.iter_mut().zip(p) {
                    // |p_k| ≤ |p| ≤ distance + ½ and inverse ≤ 2³²/distance
                    // + ½, so |p_k · inverse| < 2³³ and p_k / distance fits
                    // in Q16.
                    let unit = (pk as i64)
                        .wrapping_mul(inverse as i64)
                        .wrapping_add(1 << 15)
                        >> 16;
                    let term = s.saturating_mul(Fx::from_bits(unit as i32));
                    *gk = gk.wrapping_add((-term).to_bits() as i64);
                }
            }
        }
        (Fx::narrow(v), Vector3::from(g.map(Fx::narrow)))
    }
}

/// Elements a [`SkeletonField`] prepares, as many as a bone skeleton
/// holds ([`crate::bones::MAX_ELEMENTS`]); a longer skeleton is evaluated
/// unprepared, by [`summed_field`].
pub const PREPARED_ELEMENTS: usize = 64;

/// A skeleton's field, ready to be evaluated at many points (the vertices
/// and edge midpoints of a shrinkwrap pass): for [`Fx`], each element's
/// integer form is computed once here rather than at every point.
#[derive(Debug)]
pub struct SkeletonField<'a, R: Real> {
    elements: &'a [Element<R>],
    /// The elements' integer forms, all of them or none.
    prepared: &'a [PreparedElement],
}

impl<'a, R: FieldReal> SkeletonField<'a, R> {
    /// The field of `elements`, prepared in `storage`.
    pub fn new(
        elements: &'a [Element<R>],
        storage: &'a mut Vec<PreparedElement, PREPARED_ELEMENTS>,
    ) -> SkeletonField<'a, R> {
        storage.clear();
        for e in elements {
            let prepared = R::prepare(e).map(|p| storage.push(p));
            if !matches!(prepared, Some(Ok(()))) {
                storage.clear();
                break;
            }
        }
        SkeletonField {
            elements,
            prepared: storage,
        }
    }

    /// V(r) and ∇V(r), as [`field`] gives them.
    #[must_use]
    pub fn at(&self, r: &Vector3<R>) -> (R, Vector3<R>) {
        R::field_of(self, r, true)
    }

    /// V(r) alone, as [`potential`] gives it.
    #[must_use]
    pub fn potential_at(&self, r: &Vector3<R>) -> R {
        R::field_of(self, r, false).0
    }
}

/// V(r) and ∇V(r) (the skeleton prepared for this one point: for many,
/// [`SkeletonField`]).
#[must_use]
pub fn field<R: FieldReal>(elements: &[Element<R>], r: &Vector3<R>) -> (R, Vector3<R>) {
    SkeletonField::new(elements, &mut Vec::new()).at(r)
}

/// V(r) alone: where only the level is asked, a third of the work.
#[must_use]
pub fn potential<R: FieldReal>(elements: &[Element<R>], r: &Vector3<R>) -> R {
    SkeletonField::new(elements, &mut Vec::new()).potential_at(r)
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
/// range in which the [`Fx`] kernel needs no saturating sum.
const NEAR: u32 = 1 << 29;

/// The bitwise or of the magnitudes: below [`NEAR`] exactly when each is.
fn spread(c: &[i32; 3]) -> u32 {
    c.iter().fold(0, |acc, x| acc | x.unsigned_abs())
}

/// `Real::dot` of Q32 bits below 2⁶² in magnitude: rounded half up to
/// Q16, saturated.
fn q32_to_q16(q32: i64) -> i32 {
    Fx::narrow(q32.wrapping_add(1 << 15) >> 16).to_bits()
}

/// u·w of Q16 bits within ±2³⁰, exact in Q32 (below 3·2⁶⁰).
fn dot_near(u: &[i32; 3], w: &[i32; 3]) -> i64 {
    let product = |k: usize| (u[k] as i64).wrapping_mul(w[k] as i64);
    product(0).wrapping_add(product(1)).wrapping_add(product(2))
}

/// `a − b` of Q16 bits within ±2³⁰ whose difference is too.
fn difference(a: &[i32; 3], b: &[i32; 3]) -> [i32; 3] {
    [0, 1, 2].map(|k| a[k].wrapping_sub(b[k]))
}

/// An element within ±8192 units (`NEAR`) in the integer form of the [`Fx`] kernel:
/// Q16 bits of one end `a`, of `d` = b − a, and of d·d as `Real::dot`
/// rounds it.
#[derive(Clone, Copy, Debug)]
pub struct PreparedElement {
    a: [i32; 3],
    d: [i32; 3],
    /// d·d in Q16, saturated: at most 0 for a point (or a segment too
    /// short for `Element::nearest` to see).
    dd: i32,
    weight: Fx,
}

impl PreparedElement {
    /// The element's integer form, if both ends are within ±8192 units (`NEAR`).
    fn new(e: &Element<Fx>) -> Option<PreparedElement> {
        let a = e.a.map(Fx::to_bits);
        let b = e.b.map(Fx::to_bits);
        if (spread(&a) | spread(&b)) >= NEAR {
            return None;
        }
        // Both ends within ±2²⁹: d within ±2³⁰.
        let d = difference(&b, &a);
        Some(PreparedElement {
            a,
            d,
            dd: q32_to_q16(dot_near(&d, &d)),
            weight: e.weight,
        })
    }

    /// r − R: `r` (within ±8192 units (`NEAR`)) minus the point of the element
    /// nearest to it as `Element::nearest` rounds it; within ±2³⁰, since R
    /// lies between a and b.
    fn offset(&self, r: &[i32; 3]) -> [i32; 3] {
        let (d, dd) = (&self.d, self.dd);
        let ra = difference(r, &self.a);
        if dd <= 0 {
            return ra;
        }
        let along = q32_to_q16(dot_near(&ra, d));
        // t = along / dd rounded as `Fx::saturating_div` (dd > 0): at most
        // 0 for along ≤ 0, at least 1 for along ≥ dd; the ends are
        // compared before the saturation, which keeps them.
        if along <= 0 {
            return ra;
        }
        if along < dd {
            // 0 < along < dd < 2³¹: n < 2⁴⁷, and t ≤ 2¹⁶.
            let (n, dd) = ((along as u64) << 16, dd as u64);
            let t = n.wrapping_add(dd / 2) / dd;
            if t == 0 {
                return ra;
            }
            if t < 1 << 16 {
                // 0 < t < 1: |d_k·t| < 2⁴⁶, rounded as `Fx` multiplication.
                let along_d = |k: usize| {
                    ((d[k] as i64).wrapping_mul(t as i64).wrapping_add(1 << 15) >> 16) as i32
                };
                return difference(&ra, &[0, 1, 2].map(along_d));
            }
        }
        // r − b = (r − a) − d.
        difference(&ra, d)
    }
}

/// 1 / max(distance, 2⁻¹²) rounded as `Fx::saturating_div`, in Q16 bits:
/// at most 2²⁸, in one 32-bit division, since for d ≥ 16 bits
/// 2³² + ⌊d/2⌋ = d + (2³² − ⌈d/2⌉) and the latter fits in 32 bits (a
/// 64-bit division is a library call on the MCU).
fn inverse_distance(distance: Fx) -> u32 {
    let d = distance.max(min_distance()).to_bits().unsigned_abs();
    (0u32.wrapping_sub(d.wrapping_sub(d / 2)) / d).wrapping_add(1)
}

/// `x · inverse` rounded and saturated as `Fx` multiplication (inverse ≤
/// 2²⁸, so the product is below 2⁵⁹).
fn weight_times(x: Fx, inverse: u32) -> i32 {
    let product = (x.to_bits() as i64).wrapping_mul(inverse as i64);
    Fx::narrow(product.wrapping_add(1 << 15) >> 16).to_bits()
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
            // Beside the middle of a segment, where t is strictly between 0 and 1.
            let last = elements[elements.len() - 1];
            let beside = Vector3::from(last.a).zip_map(&Vector3::from(last.b), |a, b| {
                Fx::from_bits(((a.to_bits() as i64 + b.to_bits() as i64) / 2) as i32)
                    + Fx::from_bits(next() as i32 >> 16)
            });
            let mut storage = Vec::new();
            let prepared = SkeletonField::new(&elements, &mut storage);
            for r in [point(&mut next), near, Vector3::from(elements[0].b), beside] {
                let summed = summed_field(&elements, &r);
                assert_eq!(field(&elements, &r), summed, "{elements:?} at {r:?}");
                assert_eq!(potential(&elements, &r), summed.0, "{elements:?} at {r:?}");
                assert_eq!(prepared.at(&r), summed, "{elements:?} at {r:?}");
                assert_eq!(prepared.potential_at(&r), summed.0, "{elements:?} at {r:?}");
            }
        }
    }

    /// A skeleton is prepared whole or not at all: one element out of the
    /// kernel's range, or more elements than [`PREPARED_ELEMENTS`], leave
    /// it unprepared, with the same field.
    #[test]
    fn a_skeleton_is_prepared_whole_or_not_at_all() {
        let rod = |k: i32| {
            Element::segment(
                fx3(0.0, k as f64 / 8.0, 0.0),
                fx3(0.5, k as f64 / 8.0, 1.0),
                Fx::from_ratio(1, 8),
            )
        };
        let far = Element::point(fx3(9000.0, 0.0, 0.0), Fx::ONE);
        let r = fx3(0.25, 2.0, -0.75);
        let mut storage = Vec::new();
        for (elements, prepared) in [
            ((0..64).map(rod).collect::<std::vec::Vec<_>>(), 64),
            ((0..65).map(rod).collect(), 0),
            ((0..3).map(rod).chain([far]).collect(), 0),
            (std::vec::Vec::new(), 0),
        ] {
            let field_of = SkeletonField::new(&elements, &mut storage);
            assert_eq!(field_of.prepared.len(), prepared);
            assert_eq!(field_of.at(&r), summed_field(&elements, &r));
        }
        // f64 has no integer form: its field is its own.
        let elements = [rod(1).convert(f64::from_fx)];
        let field_of = SkeletonField::new(&elements, &mut storage);
        let r = r.map(f64::from_fx);
        assert_eq!(field_of.at(&r), field(&elements, &r));
        assert_eq!(field_of.potential_at(&r), potential(&elements, &r));
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
