//! Convex polygon elements (bones paper, Sec. 6, after eq. (6)): "if the
//! element is a convex polygon, R_i is the projection of r into the
//! polygon", so its surface lies ρ / V0 from the polygon, with rounded
//! (cylindrical) rims.
//!
//! A polygon of k vertices is k consecutive [`Element`]s, its edges,
//! tagged k, k − 1, …, 1 ([`Element::polygon`]). R_i is r projected onto
//! the polygon's plane when that projection lies inside every edge, else
//! the nearest point of the nearest edge.

use nalgebra::Vector3;

use super::ShrinkwrapError;
use super::element::Element;
use crate::Error;
use crate::fx::Real;

/// Edges of one polygon element: its tag is a `u8`.
pub const MAX_POLYGON_EDGES: usize = u8::MAX as usize;

/// The planarity and convexity tolerance, as a fraction of the polygon's
/// size (the largest distance of a vertex from the first): 1/1024, but at
/// least 2⁻¹² units (the rounding of fixed-point vertices). A vertex may
/// lie this far off the plane, or this far outside the line of an edge.
pub const POLYGON_TOLERANCE: i32 = 1024;

/// The smallest tolerance, 2⁻¹² units (16 LSB of I16F16): the rounding of
/// a turtle's fixed-point vertices.
fn min_tolerance<R: Real>() -> R {
    R::from_ratio(1, 4096)
}

fn at<R: Real>(p: &[R; 3]) -> Vector3<R> {
    Vector3::from(*p)
}

/// The unit normal of the polygon with edges `edges` (Newell's sum, on
/// the vertices scaled to the polygon's size so that no product
/// overflows; counter-clockwise seen from its tip) and that size, or
/// `None` for a polygon without area (below 2⁻¹³ of its size squared).
fn unit_normal<R: Real>(
    edges: impl Iterator<Item = Element<R>> + Clone,
) -> Option<(Vector3<R>, R)> {
    let a0 = at(&edges.clone().next()?.a);
    let size = edges
        .clone()
        .map(|e| R::norm(&(at(&e.a) - a0)))
        .fold(R::zero(), |m, d| if d > m { d } else { m });
    if size <= R::zero() {
        return None;
    }
    let scaled = |p: &[R; 3]| (at(p) - a0).map(|c| c.div(size));
    let n = edges.fold(Vector3::from([R::zero(); 3]), |n, e| {
        n + scaled(&e.a).cross(&scaled(&e.b))
    });
    let length = R::norm(&n);
    if length < R::from_ratio(1, 8192) {
        return None;
    }
    Some((n.map(|c| c.div(length)), size))
}

/// How far `v` lies inside the line of the edge `e` (positive inside, in
/// the plane of `normal`), or `None` for an edge of no length.
fn inside_edge<R: Real>(e: &Element<R>, normal: &Vector3<R>, v: &Vector3<R>) -> Option<R> {
    let a = at(&e.a);
    let d = at(&e.b) - a;
    let length = R::norm(&d);
    if length <= R::zero() {
        return None;
    }
    let unit = d.map(|c| c.div(length));
    Some(R::dot(&unit.cross(&(v - a)), normal))
}

/// R_i of the polygon with edges `edges` for the point `r`: its projection
/// onto the plane when that lies inside every edge, else the nearest point
/// of the nearest edge (the first of equals). A polygon without area is
/// measured by its edges alone.
#[must_use]
pub fn nearest<R: Real>(edges: &[Element<R>], r: &Vector3<R>) -> Vector3<R> {
    if let Some((normal, _)) = unit_normal(edges.iter().copied()) {
        let inside = edges
            .iter()
            .all(|e| inside_edge(e, &normal, r).is_none_or(|s| s >= R::zero()));
        if let (true, Some(first)) = (inside, edges.first()) {
            return r - normal * R::dot(&(r - at(&first.a)), &normal);
        }
    }
    let mut best = (R::zero(), *r);
    for (k, e) in edges.iter().enumerate() {
        let p = e.nearest(r);
        let d = R::norm(&(r - p));
        if k == 0 || d < best.0 {
            best = (d, p);
        }
    }
    best.1
}

/// The edges of the convex polygon with `vertices` (in order around it)
/// as one polygon element of weight ρ = `weight`.
///
/// # Errors
/// Fewer than 3 vertices, or no area
/// ([`ShrinkwrapError::PolygonDegenerate`]); a vertex off the plane or
/// inside-out by more than the tolerance ([`POLYGON_TOLERANCE`]:
/// [`ShrinkwrapError::PolygonNotPlanar`],
/// [`ShrinkwrapError::PolygonNotConvex`]); more than
/// [`MAX_POLYGON_EDGES`] vertices.
pub fn polygon_edges<R: Real>(
    vertices: &[Vector3<R>],
    weight: R,
) -> Result<impl Iterator<Item = Element<R>> + Clone + '_, Error> {
    if vertices.len() > MAX_POLYGON_EDGES {
        return Err(Error::Capacity {
            limit: "MAX_POLYGON_EDGES",
            capacity: MAX_POLYGON_EDGES as u32,
        });
    }
    let count = vertices.len();
    let zero = Vector3::from([R::zero(); 3]);
    let vertex = move |k: usize| vertices.get(k % count.max(1)).copied().unwrap_or(zero);
    // Edge k (mod count), from vertex k to the next.
    let edge = move |k: usize| {
        let k = k % count.max(1);
        Element {
            polygon: (count - k) as u8, // count ≤ MAX_POLYGON_EDGES
            ..Element::segment(vertex(k), vertex(k + 1), weight)
        }
    };
    let edges = (0..count).map(edge);
    let degenerate = Error::Shrinkwrap(ShrinkwrapError::PolygonDegenerate);
    if count < 3 {
        return Err(degenerate);
    }
    let (normal, size) = unit_normal(edges.clone()).ok_or(degenerate)?;
    let tolerance = {
        let t = size.div(R::from_int(POLYGON_TOLERANCE));
        if t < min_tolerance() {
            min_tolerance()
        } else {
            t
        }
    };
    let a0 = vertex(0);
    // The vertex farthest off the plane through the first one.
    let (worst, off) = vertices
        .iter()
        .map(|v| R::dot(&(v - a0), &normal).abs())
        .enumerate()
        .fold((0, R::zero()), |w, (k, d)| if d > w.1 { (k, d) } else { w });
    if off > tolerance {
        return Err(ShrinkwrapError::PolygonNotPlanar {
            vertex: worst as u8, // < MAX_POLYGON_EDGES
        }
        .into());
    }
    // Each vertex turns the same way as the polygon (a dented vertex is
    // named), then every vertex lies inside every edge (so the polygon
    // winds once: a pentagram turns one way at every vertex).
    for k in 0..count {
        if inside_edge(&edge(k + count - 1), &normal, &vertex(k + 1))
            .is_some_and(|s| s < -tolerance)
        {
            let vertex = k as u8; // < count ≤ MAX_POLYGON_EDGES
            return Err(ShrinkwrapError::PolygonNotConvex { vertex }.into());
        }
    }
    for e in edges.clone() {
        for (k, v) in vertices.iter().enumerate() {
            match inside_edge(&e, &normal, v) {
                None => return Err(degenerate),
                Some(s) if s < -tolerance => {
                    return Err(ShrinkwrapError::PolygonNotConvex { vertex: k as u8 }.into());
                }
                Some(_) => {}
            }
        }
    }
    Ok(edges)
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::fx::Fx;
    use crate::shrinkwrap::field;

    /// |v| in f64 (nalgebra's `norm` needs its `libm` feature).
    fn length(v: Vector3<f64>) -> f64 {
        v.dot(&v).sqrt()
    }

    fn fx(v: Vector3<f64>) -> Vector3<Fx> {
        v.map(|c| Fx::from_fixed(fixed::types::I16F16::from_num(c)))
    }

    /// The closest point of the triangle abc to p (Ericson, Real-Time
    /// Collision Detection, Sec. 5.1.5), in f64: an implementation of the
    /// polygon distance independent of [`nearest`], by its fan of
    /// triangles.
    fn closest_on_triangle(
        p: Vector3<f64>,
        a: Vector3<f64>,
        b: Vector3<f64>,
        c: Vector3<f64>,
    ) -> Vector3<f64> {
        let (ab, ac, ap) = (b - a, c - a, p - a);
        let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
        if d1 <= 0.0 && d2 <= 0.0 {
            return a;
        }
        let bp = p - b;
        let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
        if d3 >= 0.0 && d4 <= d3 {
            return b;
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            return a + ab * (d1 / (d1 - d3));
        }
        let cp = p - c;
        let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
        if d6 >= 0.0 && d5 <= d6 {
            return c;
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            return a + ac * (d2 / (d2 - d6));
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
        }
        let denom = 1.0 / (va + vb + vc);
        a + ab * (vb * denom) + ac * (vc * denom)
    }

    /// The distance from p to the convex polygon `v` by its fan of triangles.
    fn fan_distance(p: Vector3<f64>, v: &[Vector3<f64>]) -> f64 {
        (1..v.len() - 1)
            .map(|k| length(p - closest_on_triangle(p, v[0], v[k], v[k + 1])))
            .fold(f64::INFINITY, f64::min)
    }

    struct Xorshift(u64);
    impl Xorshift {
        /// Uniform in [0, 1).
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A random convex polygon of 3 to 12 vertices, 0.5 to 16 units
    /// across, in a random plane: points of an ellipse at increasing
    /// random angles, turned and moved.
    fn random_polygon(rng: &mut Xorshift) -> std::vec::Vec<Vector3<f64>> {
        let k = 3 + (rng.next() * 10.0) as usize;
        let size = 0.25 * 32f64.powf(rng.next());
        let (ra, rb) = (size, size * (0.3 + 0.7 * rng.next()));
        // One angle in each k-th of the turn, at least 1/5 of it apart.
        let offset = rng.next();
        let angles: std::vec::Vec<f64> = (0..k)
            .map(|j| (offset + j as f64 + 0.8 * rng.next()) * std::f64::consts::TAU / k as f64)
            .collect();
        // A random plane: u, w orthonormal (Gram–Schmidt).
        let mut random = || Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
        let (u, w) = (random(), random());
        let u = u / length(u);
        let w = w - u * u.dot(&w);
        let w = w / length(w);
        let centre = Vector3::new(rng.next(), rng.next(), rng.next()) * 20.0;
        angles
            .iter()
            .map(|t| centre + u * (ra * t.cos()) + w * (rb * t.sin()))
            .collect()
    }

    /// The fixed-point polygon distance |r − R_i| is within 2⁻⁹ units
    /// plus 2⁻¹⁰ of the distance of an independent f64 implementation
    /// (the fan of triangles, Ericson's closest point) on the same
    /// vertices, over 2 000 random convex polygons up to 16 units across
    /// and points up to 3 sizes from them, above the inside, beside the
    /// edges and near the corners. Measured worst (`cargo test -p
    /// morphogen --lib polygon -- --nocapture`): 9.8·10⁻⁴ units, 6.3·10⁻⁴
    /// of max(distance, 1).
    #[test]
    fn the_fixed_distance_is_within_its_bound_of_an_f64_one() {
        let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
        let (mut worst, mut worst_relative, mut points) = (0f64, 0f64, 0);
        for _ in 0..2_000 {
            let polygon = random_polygon(&mut rng);
            let vertices: std::vec::Vec<Vector3<Fx>> = polygon.iter().map(|&v| fx(v)).collect();
            let rounded: std::vec::Vec<Vector3<f64>> =
                vertices.iter().map(|v| v.map(f64::from_fx)).collect();
            let Ok(edges) = polygon_edges(&vertices, Fx::ONE) else {
                // Only a sliver may be refused (its rounded vertices off
                // the line of an edge); none of these is one.
                panic!("{polygon:?} refused");
            };
            let edges: std::vec::Vec<Element<Fx>> = edges.collect();
            let size = (1..rounded.len())
                .map(|k| length(rounded[k] - rounded[0]))
                .fold(0.0, f64::max);
            let centre = rounded.iter().sum::<Vector3<f64>>() / rounded.len() as f64;
            for _ in 0..20 {
                let near = rounded[(rng.next() * rounded.len() as f64) as usize];
                let base = if rng.next() < 0.5 { centre } else { near };
                let offset = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5)
                    * (6.0 * size * rng.next());
                let r = fx(base + offset);
                let rf = r.map(f64::from_fx);
                let got = length(rf - nearest(&edges, &r).map(f64::from_fx));
                let want = fan_distance(rf, &rounded);
                let error = (got - want).abs();
                worst = worst.max(error);
                worst_relative = worst_relative.max(error / want.max(1.0));
                points += 1;
                assert!(
                    error <= 1.0 / 512.0 + want / 1024.0,
                    "{polygon:?} at {rf:?}: {got} vs {want}"
                );
            }
        }
        std::println!(
            "polygon distance, {points} points: worst |fixed − f64| = {worst:.3e}, relative to max(d, 1) {worst_relative:.3e}"
        );
    }

    /// Above the inside, V is ρ / height (the plane's projection); beyond
    /// an edge, ρ / the distance to that edge.
    #[test]
    fn the_field_of_a_square_plate() {
        let v = [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]
            .map(|(x, y)| fx(Vector3::new(x, y, 0.0)));
        let edges: std::vec::Vec<Element<Fx>> =
            polygon_edges(&v, Fx::from_int(2)).unwrap().collect();
        assert_eq!(
            edges
                .iter()
                .map(|e| e.polygon)
                .collect::<std::vec::Vec<_>>(),
            [4, 3, 2, 1]
        );
        let at = |x: f64, y: f64, z: f64| field::potential(&edges, &fx(Vector3::new(x, y, z)));
        // 2 / 0.5 above an inside point, wherever it is.
        assert_eq!(at(2.0, 2.0, 0.5), Fx::from_int(4));
        assert_eq!(at(0.25, 3.5, -0.5), Fx::from_int(4));
        // 2 / 1 beyond the edge x = 4, in the plane and at 45°.
        assert_eq!(at(5.0, 1.0, 0.0), Fx::from_int(2));
        let diagonal = at(4.5, 3.0, 0.5).to_f64();
        assert!(
            (diagonal - 2.0 / 0.5f64.hypot(0.5)).abs() < 1e-4,
            "{diagonal}"
        );
        // The same edges as plain segments: the middle sees four terms.
        let segments: std::vec::Vec<Element<Fx>> =
            edges.iter().map(|e| Element { polygon: 0, ..*e }).collect();
        let middle = field::potential(&segments, &fx(Vector3::new(2.0, 2.0, 0.5))).to_f64();
        assert!(
            (middle - 4.0 * 2.0 / 4.25f64.sqrt()).abs() < 1e-3,
            "{middle}"
        );
    }

    #[test]
    fn polygons_that_are_not_convex_or_planar_are_refused() {
        let p = |v: &[(f64, f64, f64)]| -> std::vec::Vec<Vector3<Fx>> {
            v.iter()
                .map(|&(x, y, z)| fx(Vector3::new(x, y, z)))
                .collect()
        };
        let refused = |v: &[(f64, f64, f64)]| polygon_edges(&p(v), Fx::ONE).err();
        let not_convex = |vertex| {
            Some(Error::Shrinkwrap(ShrinkwrapError::PolygonNotConvex {
                vertex,
            }))
        };
        let degenerate = Some(Error::Shrinkwrap(ShrinkwrapError::PolygonDegenerate));
        // A dart: vertex 3 is dented in.
        assert_eq!(
            refused(&[
                (0.0, 0.0, 0.0),
                (4.0, 0.0, 0.0),
                (4.0, 4.0, 0.0),
                (3.0, 1.0, 0.0)
            ]),
            not_convex(3)
        );
        // Clockwise is as convex as counter-clockwise.
        assert_eq!(
            refused(&[
                (0.0, 0.0, 0.0),
                (0.0, 4.0, 0.0),
                (4.0, 4.0, 0.0),
                (4.0, 0.0, 0.0)
            ]),
            None
        );
        // A pentagram turns one way at every vertex but winds twice.
        let star: std::vec::Vec<(f64, f64, f64)> = (0..5)
            .map(|k| {
                let t = (2 * k) as f64 * std::f64::consts::TAU / 5.0;
                (3.0 * t.cos(), 3.0 * t.sin(), 1.0)
            })
            .collect();
        assert!(matches!(
            refused(&star),
            Some(Error::Shrinkwrap(ShrinkwrapError::PolygonNotConvex { .. }))
        ));
        // A square with one corner lifted 1/100 of its size, and one lifted
        // within the tolerance (1/1024 of the size: 4/1024 here).
        // (The plane through vertex 0 with the Newell normal holds the
        // lifted corner; vertices 1 and 3 lie 0.02 off it.)
        assert_eq!(
            refused(&[
                (0.0, 0.0, 0.0),
                (4.0, 0.0, 0.0),
                (4.0, 4.0, 0.04),
                (0.0, 4.0, 0.0)
            ]),
            Some(Error::Shrinkwrap(ShrinkwrapError::PolygonNotPlanar {
                vertex: 1
            }))
        );
        assert_eq!(
            refused(&[
                (0.0, 0.0, 0.0),
                (4.0, 0.0, 0.0),
                (4.0, 4.0, 0.002),
                (0.0, 4.0, 0.0)
            ]),
            None
        );
        // Too few vertices, no area, a repeated vertex.
        assert_eq!(refused(&[(0.0, 0.0, 0.0), (4.0, 0.0, 0.0)]), degenerate);
        assert_eq!(
            refused(&[(0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (4.0, 0.0, 0.0)]),
            degenerate
        );
        assert_eq!(
            refused(&[
                (0.0, 0.0, 0.0),
                (4.0, 0.0, 0.0),
                (4.0, 0.0, 0.0),
                (0.0, 4.0, 0.0)
            ]),
            degenerate
        );
        // More edges than a tag holds.
        let many: std::vec::Vec<(f64, f64, f64)> = (0..=MAX_POLYGON_EDGES)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 256.0;
                (100.0 * t.cos(), 100.0 * t.sin(), 0.0)
            })
            .collect();
        assert_eq!(
            refused(&many),
            Some(Error::Capacity {
                limit: "MAX_POLYGON_EDGES",
                capacity: 255
            })
        );
    }
}
