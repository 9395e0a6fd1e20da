//! One skeleton element (bones paper, Sec. 6: "points, lines or convex
//! polygons"): a point, a segment, or one edge of a convex polygon element
//! ([`super::polygon`]), with its weight ρ.

use nalgebra::Vector3;

use crate::fx::{Fx, Real};

/// One skeleton element: the segment from `a` to `b` (a point when
/// `a == b`) with weight ρ, or one edge of a convex polygon element
/// (Sec. 6: "points, lines or convex polygons"; [`Element::polygon`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Element<R: Real = Fx> {
    /// One end.
    pub a: [R; 3],
    /// The other end (`a` again for a point).
    pub b: [R; 3],
    /// ρ: the surface of this element alone, at level V0, lies ρ / V0 from it.
    pub weight: R,
    /// 0 for a point or a segment; for an edge of a polygon, the edges
    /// of that polygon from this one to its last (k, k − 1, …, 1): the
    /// k consecutive elements from one tagged k are one polygon, whose
    /// term of V is ρ / (distance to the polygon), with the first edge's ρ.
    pub polygon: u8,
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
            polygon: 0,
        }
    }

    /// The element in another number type (e.g. the `f64` reference).
    #[must_use]
    pub fn convert<S: Real>(&self, f: impl Fn(R) -> S) -> Element<S> {
        Element {
            a: self.a.map(&f),
            b: self.b.map(&f),
            weight: f(self.weight),
            polygon: self.polygon,
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
