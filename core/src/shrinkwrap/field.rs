//! The skeleton's field V(r) = Σ ρ_i / |r − R_i| and its gradient (bones
//! paper, eqs. (6) and (12)), where R_i is the point of element i nearest
//! to r.

use heapless::Vec;
use nalgebra::Vector3;

use super::element::Element;
use super::kernel::{dot_near, inverse_of_squared};
use super::polygon;
use super::vertices::{MAX_VERTICES, normalised, normalised_fx};
use crate::fx::{Fx, Real};
#[cfg(test)]
use crate::geom::length_of_squared;

/// The distance below which an element counts as touching, 2⁻¹²: V stays
/// finite, and a vertex this close to the skeleton has collapsed anyway.
fn min_distance<R: Real>() -> R {
    R::from_ratio(1, 4096)
}

/// The number types the field is evaluated in: `f64` in its own
/// arithmetic ([`summed_field`]), [`Fx`] by an integer kernel on prepared
/// elements that rounds and saturates exactly as [`summed_field`] does on
/// [`Fx`] but skips the saturation where the range is proven.
pub trait FieldReal: Real {
    /// The element in the integer form of the kernel, if this number type
    /// has one and the element is in its range.
    fn prepare(_element: &Element<Self>) -> Option<PreparedElement> {
        None
    }

    /// V(r) of eqs. (1)–(2) over `vertices`, and ∇V(r) when `gradient`
    /// (zero otherwise): [`normalised`] in this type's arithmetic, or an
    /// integer kernel.
    fn normalised_of(
        vertices: &[[Self; 3]],
        r: &Vector3<Self>,
        gradient: bool,
    ) -> (Self, Vector3<Self>) {
        normalised(vertices, r, gradient)
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

    fn normalised_of(vertices: &[[Fx; 3]], r: &Vector3<Fx>, gradient: bool) -> (Fx, Vector3<Fx>) {
        normalised_fx(vertices, r, gradient)
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
        // On a computer one loop each, without a test of `gradient` per
        // element; on an MCU one loop for both (750 B less flash).
        if cfg!(target_pointer_width = "64") {
            if gradient {
                prepared_field(field.prepared, &rb, true)
            } else {
                prepared_field(field.prepared, &rb, false)
            }
        } else {
            prepared_field(field.prepared, &rb, gradient)
        }
    }
}

/// The [`Fx`] kernel of [`FieldReal::field_of`] on the prepared elements
/// at `rb` (Q16 bits within ±8192 units, `NEAR`): V, and ∇V when
/// `gradient` (zero otherwise). Inlined into `field_of` on a computer, a
/// copy for each value of `gradient`, where the call and the copied
/// result cost 40 instructions an evaluation.
#[cfg_attr(target_pointer_width = "64", inline(always))]
fn prepared_field(
    prepared: &[PreparedElement],
    rb: &[i32; 3],
    gradient: bool,
) -> (Fx, Vector3<Fx>) {
    // At most PREPARED_ELEMENTS = 2⁶ terms, each an i32: the sums stay
    // below 2³⁷, where `Real::widen`'s saturation never acts.
    let mut v = 0i64;
    let mut g = [0i64; 3];
    // 1/|r − x| of each shared end x ([`SHARED_ENDS`]) once computed, 0
    // before (`inverse_distance` is at least 1).
    let mut shared = [0u32; SHARED_ENDS];
    let distance_inverse = |p: &[i32; 3]| inverse_of_squared(dot_near(p, p) as u64);
    for e in prepared {
        let (p, end) = e.offset(rb);
        let inverse = match shared.get_mut(usize::from(end)) {
            Some(known) if SHARE_ENDS && *known != 0 => *known,
            Some(known) if SHARE_ENDS => {
                *known = distance_inverse(&p);
                *known
            }
            _ => distance_inverse(&p),
        };
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

/// Elements a [`SkeletonField`] prepares, as many as a bone skeleton
/// holds ([`crate::bones::MAX_ELEMENTS`]); a longer skeleton is evaluated
/// unprepared, by [`summed_field`].
pub const PREPARED_ELEMENTS: usize = 64;

// The paper's weights take up to two vertices an element.
const _: () = assert!(MAX_VERTICES == 2 * PREPARED_ELEMENTS);

/// A skeleton's field, ready to be evaluated at many points (the vertices
/// and edge midpoints of a shrinkwrap pass): for [`Fx`], each element's
/// integer form is computed once here rather than at every point.
#[derive(Debug)]
pub struct SkeletonField<'a, R: Real> {
    elements: &'a [Element<R>],
    /// The elements' integer forms, all of them or none.
    prepared: &'a [PreparedElement],
    /// With the paper's weights ([`super::Weights::Normalised`]): the
    /// skeleton's distinct vertices, its elements; `None` for constant
    /// weights.
    vertices: Option<&'a [[R; 3]]>,
}

impl<'a, R: FieldReal> SkeletonField<'a, R> {
    /// The field of `elements`, prepared in `storage`.
    pub fn new(
        elements: &'a [Element<R>],
        storage: &'a mut Vec<PreparedElement, PREPARED_ELEMENTS>,
    ) -> SkeletonField<'a, R> {
        storage.clear();
        // The distinct element ends met so far, for the first SHARED_ENDS.
        let mut ends: Vec<[i32; 3], SHARED_ENDS> = Vec::new();
        for e in elements {
            let prepared = R::prepare(e).map(|mut p| {
                if SHARE_ENDS {
                    p.ends = [p.a, p.end_b()].map(|x| shared_end(&mut ends, x));
                }
                storage.push(p)
            });
            if !matches!(prepared, Some(Ok(()))) {
                storage.clear();
                break;
            }
        }
        SkeletonField {
            elements,
            prepared: storage,
            vertices: None,
        }
    }

    /// The paper's field (eqs. (1)–(2)) of the vertices `vertices`
    /// ([`super::vertices::collect_vertices`]) of `elements`.
    pub fn normalised(elements: &'a [Element<R>], vertices: &'a [[R; 3]]) -> SkeletonField<'a, R> {
        SkeletonField {
            elements,
            prepared: &[],
            vertices: Some(vertices),
        }
    }

    /// Whether `storage` holds `elements` as [`SkeletonField::new`]
    /// prepares them (a skeleton left unprepared never does): a field
    /// evaluated then is the field of `elements`.
    #[must_use]
    pub fn holds(elements: &[Element<R>], storage: &[PreparedElement]) -> bool {
        !storage.is_empty()
            && storage.len() == elements.len()
            && elements.iter().zip(storage).all(|(e, kept)| {
                R::prepare(e).is_some_and(|p| {
                    PreparedElement {
                        ends: kept.ends,
                        ..p
                    } == *kept
                })
            })
    }

    /// V(r) and ∇V(r), as [`field`] gives them.
    #[must_use]
    pub fn at(&self, r: &Vector3<R>) -> (R, Vector3<R>) {
        match self.vertices {
            Some(vertices) => R::normalised_of(vertices, r, true),
            None => R::field_of(self, r, true),
        }
    }

    /// V(r) alone, as [`potential`] gives it.
    #[must_use]
    pub fn potential_at(&self, r: &Vector3<R>) -> R {
        match self.vertices {
            Some(vertices) => R::normalised_of(vertices, r, false).0,
            None => R::field_of(self, r, false).0,
        }
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
    let mut rest = elements;
    while let Some(e) = rest.first() {
        // A polygon's edges are one term (a tag beyond the skeleton's end
        // takes what is left).
        let (group, next) = rest.split_at(usize::from(e.polygon).clamp(1, rest.len()));
        rest = next;
        let nearest = if e.polygon == 0 {
            e.nearest(r)
        } else {
            polygon::nearest(group, r)
        };
        let (vi, gi) = contribution(e.weight, r - nearest);
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

/// One element's term of V(r) and of ∇V(r), of weight ρ = `weight` and
/// offset `p` = r − R_i.
fn contribution<R: Real>(weight: R, p: Vector3<R>) -> (R, Vector3<R>) {
    let d = R::norm(&p);
    let d = if d < min_distance() {
        min_distance()
    } else {
        d
    };
    // One division per element (the MCU has no 64-bit divider).
    let inverse = R::one().div(d);
    let vi = weight * inverse;
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

/// `a − b` of Q16 bits within ±2³⁰ whose difference is too.
fn difference(a: &[i32; 3], b: &[i32; 3]) -> [i32; 3] {
    [0, 1, 2].map(|k| a[k].wrapping_sub(b[k]))
}

/// An element within ±8192 units (`NEAR`) in the integer form of the [`Fx`] kernel:
/// Q16 bits of one end `a`, of `d` = b − a, and of d·d as `Real::dot`
/// rounds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreparedElement {
    a: [i32; 3],
    d: [i32; 3],
    /// d·d in Q16, saturated: at most 0 for a point (or a segment too
    /// short for `Element::nearest` to see).
    dd: i32,
    weight: Fx,
    /// The shared-end numbers of a and b ([`SHARED_ENDS`]; `NOT_SHARED`
    /// beyond them).
    ends: [u8; 2],
}

/// Element ends (points, segment ends) whose inverse distance a field
/// evaluation computes once for every element that meets them: a bone's
/// condyles are a segment's end and a point at the same place, and its
/// shaft ends start three segments and hold a point (the full long bone has
/// 6 distinct ends for 11 elements). Integer sums are exact in any order,
/// and r − x is the same bits whichever element computes it, so sharing
/// changes no result.
const SHARED_ENDS: usize = 8;

/// The number of an end beyond the first [`SHARED_ENDS`].
const NOT_SHARED: u8 = u8::MAX;

/// Whether ends are shared ([`SHARED_ENDS`]): on a computer. On an MCU
/// the 430 B of flash it takes are more than the flash goal allows for it
/// (every end is then `NOT_SHARED`, and the field the same).
const SHARE_ENDS: bool = cfg!(target_pointer_width = "64");

/// The shared-end number of position `x` (Q16 bits), given the distinct
/// ones met so far in `ends`: its index there, a new one, or `NOT_SHARED`
/// when the table is full.
fn shared_end(ends: &mut Vec<[i32; 3], SHARED_ENDS>, x: [i32; 3]) -> u8 {
    if let Some(k) = ends.iter().position(|e| *e == x) {
        return k as u8; // < SHARED_ENDS ≤ 255
    }
    match ends.push(x) {
        Ok(()) => (ends.len() - 1) as u8,
        Err(_) => NOT_SHARED,
    }
}

impl PreparedElement {
    /// The element's integer form, if it is a point or a segment (a
    /// skeleton with polygons is evaluated by [`summed_field`]) and both
    /// ends are within ±8192 units (`NEAR`).
    fn new(e: &Element<Fx>) -> Option<PreparedElement> {
        let a = e.a.map(Fx::to_bits);
        let b = e.b.map(Fx::to_bits);
        if e.polygon != 0 || (spread(&a) | spread(&b)) >= NEAR {
            return None;
        }
        // Both ends within ±2²⁹: d within ±2³⁰.
        let d = difference(&b, &a);
        Some(PreparedElement {
            a,
            d,
            dd: q32_to_q16(dot_near(&d, &d)),
            weight: e.weight,
            ends: [NOT_SHARED; 2],
        })
    }

    /// b (Q16 bits): a + d, within ±2²⁹ as `new` checked.
    fn end_b(&self) -> [i32; 3] {
        [0, 1, 2].map(|k| self.a[k].wrapping_add(self.d[k]))
    }

    /// r − R: `r` (within ±8192 units (`NEAR`)) minus the point of the element
    /// nearest to it as `Element::nearest` rounds it; within ±2³⁰, since R
    /// lies between a and b. With it the shared-end number of R when R is
    /// an end (`NOT_SHARED` otherwise): r − a, or r − b as (r − a) − d,
    /// which is the same bits as r − b since all three are within ±2³⁰.
    #[inline(always)]
    fn offset(&self, r: &[i32; 3]) -> ([i32; 3], u8) {
        let (d, dd) = (&self.d, self.dd);
        let ra = difference(r, &self.a);
        let [at_a, at_b] = self.ends;
        if dd <= 0 {
            return (ra, at_a);
        }
        // r·d as `Real::dot` rounds it to Q16, before its saturation to
        // i32, which changes neither comparison below (dd is an i32): the
        // rounded value itself, below 2⁴⁶ in magnitude.
        let along = dot_near(&ra, d).wrapping_add(1 << 15) >> 16;
        // t = along / dd rounded as `Fx::saturating_div` (dd > 0): at most
        // 0 for along ≤ 0, at least 1 for along ≥ dd; the ends are
        // compared before the saturation, which keeps them.
        if along <= 0 {
            return (ra, at_a);
        }
        if along < i64::from(dd) {
            // 0 < along < dd < 2³¹: n < 2⁴⁷, and t ≤ 2¹⁶.
            let (n, dd) = ((along as u64) << 16, dd as u64);
            let t = n.wrapping_add(dd / 2) / dd;
            if t == 0 {
                return (ra, at_a);
            }
            if t < 1 << 16 {
                // 0 < t < 1: |d_k·t| < 2⁴⁶, rounded as `Fx` multiplication.
                let along_d = |k: usize| {
                    ((d[k] as i64).wrapping_mul(t as i64).wrapping_add(1 << 15) >> 16) as i32
                };
                return (difference(&ra, &[0, 1, 2].map(along_d)), NOT_SHARED);
            }
        }
        // r − b = (r − a) − d.
        (difference(&ra, d), at_b)
    }
}

/// 1 / max(distance, 2⁻¹²) rounded as `Fx::saturating_div`, in Q16 bits:
/// at most 2²⁸, in one 32-bit division, since for d ≥ 16 bits
/// 2³² + ⌊d/2⌋ = d + (2³² − ⌈d/2⌉) and the latter fits in 32 bits (a
/// 64-bit division is a library call on the MCU). The definition
/// [`inverse_of_squared`] computes; kept for its test.
#[cfg(test)]
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

    /// Ends shared by several elements (a bone's joints: segments meeting
    /// at a point element) give the field of `summed_field` bit for bit,
    /// near the ends, beside the segments and far away, with more
    /// distinct ends than are shared ([`SHARED_ENDS`]).
    #[test]
    fn shared_ends_change_no_bit() {
        let w = |k: i32| Fx::from_ratio(k, 10);
        let (a, b) = (fx3(0.0, 0.0, 0.0), fx3(0.0, 2.5, 0.0));
        let mut elements = std::vec::Vec::new();
        for (end, sign) in [(a, -1.0), (b, 1.0)] {
            for (k, side) in [(1, 0.4), (2, -0.4), (3, 0.1)] {
                let c = end + fx3(side, sign * 0.45, 0.05 * k as f64);
                elements.push(Element::segment(end, c, w(2)));
                elements.push(Element::point(c, w(2 + k)));
            }
            elements.push(Element::point(end, w(1)));
        }
        elements.push(Element::segment(a, b, w(5)));
        let mut storage = Vec::new();
        let _ = SkeletonField::new(&elements, &mut storage);
        assert_eq!(storage.len(), elements.len());
        // 8 distinct ends: all shared (on a computer: `SHARE_ENDS`).
        let shared = storage
            .iter()
            .all(|p| p.ends.iter().all(|&e| e < NOT_SHARED));
        assert_eq!(shared, SHARE_ENDS);
        let prepared = SkeletonField::new(&elements, &mut storage);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for k in 0..4_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let spread = [1.0, 0.5, 4.0, 40.0][k % 4];
            let c = |s: u32| ((state >> s) as u16 as f64 / 65_536.0 - 0.5) * spread;
            let r = fx3(c(0), 1.25 + c(16), c(32));
            assert_eq!(prepared.at(&r), summed_field(&elements, &r), "at {r:?}");
        }
        for e in &elements {
            let r = Vector3::from(e.b);
            assert_eq!(prepared.at(&r), summed_field(&elements, &r));
        }
        assert!(SkeletonField::holds(&elements, &storage));
        let mut moved = elements.clone();
        moved[3].weight = w(7);
        assert!(!SkeletonField::holds(&moved, &storage));
        assert!(!SkeletonField::holds(&elements[1..], &storage));
        // More distinct ends than SHARED_ENDS: the later ones unshared.
        elements.push(Element::segment(
            fx3(3.0, 0.0, 0.0),
            fx3(3.0, 1.0, 0.0),
            w(3),
        ));
        let _ = SkeletonField::new(&elements, &mut storage);
        assert_eq!(storage[storage.len() - 1].ends, [NOT_SHARED; 2]);
        let prepared = SkeletonField::new(&elements, &mut storage);
        for k in 0..200 {
            let r = fx3(k as f64 / 40.0, 1.0, 0.25);
            assert_eq!(prepared.at(&r), summed_field(&elements, &r));
        }
    }

    /// `inverse_of_squared` is `inverse_distance(length_of_squared(..))`
    /// from 0 through the threshold of the minimum distance, at squares
    /// and their neighbours, and up to 3·2⁶⁰.
    #[test]
    fn inverse_of_squared_is_the_inverse_of_the_length() {
        let check = |x: u64| {
            assert_eq!(
                inverse_of_squared(x),
                inverse_distance(length_of_squared(x)),
                "{x}"
            );
        };
        (0..100_000).for_each(check);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = (state % (3 << 60)) >> (state % 61);
            let r = x.isqrt();
            [x, r * r, r * r + r, r * r + r + 1]
                .into_iter()
                .for_each(check);
        }
        check((3 << 60) - 1);
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
