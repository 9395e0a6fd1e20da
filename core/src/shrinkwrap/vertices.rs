//! The paper's own field (bones paper, Sec. 5, eqs. (1)–(2) in (6)): the
//! skeleton's *vertices* are its elements (its edges are only drawn), and
//! each weighs ρ_i(r) = (1/|r − R_i|) / ρ(r) with ρ(r) = Σ_j 1/|r − R_j|,
//! so V(r) = Σ_i ρ_i / |r − R_i| = Σ u_i² / Σ u_i with u_i = 1/|r − R_i|:
//! a mean of the u_i weighted by themselves, between the least and the
//! largest. ∇V = Σ u_i² (V − 2 u_i) (r − R_i)/|r − R_i| / Σ u_i.

use heapless::Vec;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::kernel::{dot_near, inverse_of_squared};
use crate::fx::{Fx, Real};

use super::element::Element;

/// Distinct vertices of a skeleton wrapped with [`Weights::Normalised`]:
/// both ends of every element of a skeleton that the prepared field holds.
pub const MAX_VERTICES: usize = 128;

/// The weights ρ_i of the field's terms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[serde(rename_all = "snake_case")]
pub enum Weights {
    /// The paper's eqs. (1)–(2): the skeleton's distinct vertices (point
    /// elements and the ends of segments and polygon edges) are the
    /// elements, weighted by ρ_i(r) = (1/|r − R_i|) / Σ_j 1/|r − R_j|;
    /// the elements' own weights are only drawn.
    #[default]
    Normalised,
    /// Sec. 6's general shrinkwrap: points, segments and convex polygons,
    /// each with its own constant ρ (the turtle's width, or `O(ρ)`).
    Constant,
}

impl Weights {
    /// Whether these are the constant weights (left out of a parameter
    /// digest, which then stays that of runs made before weights were a
    /// parameter).
    #[must_use]
    pub fn is_constant(&self) -> bool {
        *self == Weights::Constant
    }
}

/// The skeleton's distinct vertices (point elements and the ends of
/// segments and polygon edges, in the order first met) into `out`.
///
/// # Errors
/// [`crate::Error::Capacity`] naming [`MAX_VERTICES`] when there are more.
pub fn collect_vertices<R: Real>(
    elements: &[Element<R>],
    out: &mut Vec<[R; 3], MAX_VERTICES>,
) -> Result<(), crate::Error> {
    out.clear();
    for e in elements {
        for p in [e.a, e.b] {
            if !out.contains(&p) {
                out.push(p).map_err(|_| crate::Error::Capacity {
                    limit: "MAX_VERTICES",
                    capacity: MAX_VERTICES as u32,
                })?;
            }
        }
    }
    Ok(())
}

/// Whether `stored` holds the vertices of `elements` as
/// [`collect_vertices`] collects them.
#[must_use]
pub fn vertices_hold<R: Real>(elements: &[Element<R>], stored: &[[R; 3]]) -> bool {
    let mut seen = 0;
    for e in elements {
        for p in [e.a, e.b] {
            let known = stored.get(..seen).is_some_and(|s| s.contains(&p));
            if !known {
                if stored.get(seen) != Some(&p) {
                    return false;
                }
                seen += 1;
            }
        }
    }
    !stored.is_empty() && seen == stored.len()
}

/// V(r) of eqs. (1)–(2) and (6) over `vertices`, and ∇V(r) when
/// `gradient` (zero otherwise), in `R`'s own arithmetic: the reference
/// the [`Fx`] kernel ([`normalised_fx`]) is measured against. A distance
/// counts as at least 2⁻¹², as in the constant-weight field.
#[must_use]
pub fn normalised<R: Real>(vertices: &[[R; 3]], r: &Vector3<R>, gradient: bool) -> (R, Vector3<R>) {
    let least = R::from_ratio(1, 4096);
    let inverse = |x: &[R; 3]| {
        let p = r - Vector3::from(*x);
        let d = R::norm(&p);
        (p, R::one().div(if d > least { d } else { least }))
    };
    let (mut n, mut d) = (R::Wide::default(), R::Wide::default());
    for x in vertices {
        let (_, u) = inverse(x);
        n = R::widen(n, u * u);
        d = R::widen(d, u);
    }
    let (n, d) = (R::narrow(n), R::narrow(d));
    if d <= R::zero() {
        return (R::zero(), Vector3::from([R::zero(); 3]));
    }
    let v = n.div(d);
    let mut g = [R::Wide::default(); 3];
    if gradient {
        for x in vertices {
            let (p, u) = inverse(x);
            let s = u * u * (v - u - u);
            for k in 0..3 {
                g[k] = R::widen(g[k], s * (p[k] * u));
            }
        }
    }
    (v, Vector3::from(g.map(|gk| R::narrow(gk).div(d))))
}

/// [`normalised`] in integers, for [`Fx`]: u_i = 1/|r − R_i| rounded as
/// the constant-weight kernel rounds it, V = Σ u_i² / Σ u_i rounded once
/// from exact sums, each gradient term saturating as `Fx` products do.
/// An offset beyond ±2¹⁴ units on an axis counts as 2¹⁴ (such a vertex
/// adds at most 4 LSB to Σ u_i). The same bits on every target.
#[must_use]
pub fn normalised_fx(vertices: &[[Fx; 3]], r: &Vector3<Fx>, gradient: bool) -> (Fx, Vector3<Fx>) {
    // On a computer one copy each, without the gradient's stores when
    // only V is asked (two in three calls of a shrinkwrap pass); on an
    // MCU one copy for both.
    if cfg!(target_pointer_width = "64") {
        if gradient {
            normalised_bits(vertices, r, true)
        } else {
            normalised_bits(vertices, r, false)
        }
    } else {
        normalised_bits(vertices, r, gradient)
    }
}

/// The kernel of [`normalised_fx`], inlined into it on a computer, a copy
/// for each value of `gradient`.
#[cfg_attr(target_pointer_width = "64", inline(always))]
fn normalised_bits(vertices: &[[Fx; 3]], r: &Vector3<Fx>, gradient: bool) -> (Fx, Vector3<Fx>) {
    let rb = [r.x, r.y, r.z].map(Fx::to_bits);
    // u_i, Q16 bits, at most 2²⁸.
    let mut inverses = [0u32; MAX_VERTICES];
    // Σ u_i² in Q32 (each at most 2⁵⁶, at most 2⁷ of them: below 2⁶³)
    // and Σ u_i in Q16: no sum wraps.
    let (mut n, mut d) = (0u64, 0u64);
    for (x, kept) in vertices.iter().zip(inverses.iter_mut()) {
        let p = offset(&rb, x);
        let u = inverse_of_squared(dot_near(&p, &p) as u64);
        if gradient {
            *kept = u;
        }
        n = n.wrapping_add(u64::from(u) * u64::from(u));
        d = d.wrapping_add(u64::from(u));
    }
    if d == 0 {
        return (Fx::ZERO, Vector3::zeros());
    }
    // A weighted mean of the u_i: at most 2²⁸ (Q16 bits).
    let d = d as i64;
    let v = Fx::from_wide_ratio(n as i64, d);
    if !gradient {
        return (v, Vector3::zeros());
    }
    let mut g = [0i64; 3];
    for (x, &u) in vertices.iter().zip(inverses.iter()) {
        let p = offset(&rb, x);
        let u_fx = Fx::from_bits(u as i32);
        // V − 2u within ±2³⁰.
        let s = u_fx
            .saturating_mul(u_fx)
            .saturating_mul(Fx::from_bits(v.to_bits() - 2 * u as i32));
        // On a computer, where |s| < 2²⁹, no term saturates (|unit| <
        // 2¹⁷ below: s · unit stays below 2⁴⁶) and none is tested; on an
        // MCU every term is saturated (less flash).
        let exact = cfg!(target_pointer_width = "64") && s.to_bits().unsigned_abs() < 1 << 29;
        for (gk, pk) in g.iter_mut().zip(p) {
            // (r − R_i)/|r − R_i| in Q16, below 2¹⁷: |p_k| ≤ d + ½ and
            // u ≤ 2³²/d + 1 with 16 ≤ d < 2³¹.
            let unit = ((i64::from(pk) * i64::from(u) + (1 << 15)) >> 16) as i32;
            *gk += if exact {
                (i64::from(s.to_bits()) * i64::from(unit) + (1 << 15)) >> 16
            } else {
                i64::from(s.saturating_mul(Fx::from_bits(unit)).to_bits())
            };
        }
    }
    // Each sum below 2⁷ · 2³¹; shifted, below 2⁵⁴. d ≥ 1.
    (
        v,
        Vector3::from(g.map(|gk| Fx::from_wide_ratio(gk << 16, d))),
    )
}

/// r − x in Q16 bits (`r` as `rb`), each axis clamped to ±2³⁰, the range
/// of `dot_near` (a vertex over 2¹⁴ units away on that axis). Inlined on
/// a computer; on an MCU one copy for both loops.
#[cfg_attr(target_pointer_width = "64", inline(always))]
#[cfg_attr(not(target_pointer_width = "64"), inline(never))]
fn offset(rb: &[i32; 3], x: &[Fx; 3]) -> [i32; 3] {
    const LIMIT: i64 = 1 << 30;
    let axis = |k: usize| i64::from(rb[k]) - i64::from(x[k].to_bits());
    let p = [axis(0), axis(1), axis(2)];
    // Every axis in [−2³⁰, 2³⁰) exactly when its sum with 2³⁰, unsigned,
    // is below 2³¹, and then so is their bitwise or: on a computer, one
    // test for three clamps that change nothing (on an MCU, the clamps
    // alone take less flash).
    let shifted = |c: i64| c.wrapping_add(LIMIT) as u64;
    if cfg!(target_pointer_width = "64") && shifted(p[0]) | shifted(p[1]) | shifted(p[2]) < 1 << 31
    {
        [p[0] as i32, p[1] as i32, p[2] as i32]
    } else {
        let clamped = |c: i64| c.clamp(-LIMIT, LIMIT) as i32;
        [clamped(p[0]), clamped(p[1]), clamped(p[2])]
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn fx3(x: f64, y: f64, z: f64) -> [Fx; 3] {
        [x, y, z].map(|c| Fx::from_fixed(fixed::types::I16F16::from_num(c)))
    }

    /// Eqs. (1)–(2) and (6) written out in f64, term by term.
    fn paper(vertices: &[[f64; 3]], r: [f64; 3]) -> f64 {
        let dist = |x: &[f64; 3]| {
            ((r[0] - x[0]).powi(2) + (r[1] - x[1]).powi(2) + (r[2] - x[2]).powi(2)).sqrt()
        };
        let rho: f64 = vertices.iter().map(|x| 1.0 / dist(x)).sum();
        vertices
            .iter()
            .map(|x| {
                let rho_i = (1.0 / dist(x)) / rho;
                rho_i / dist(x)
            })
            .sum()
    }

    fn shaft() -> std::vec::Vec<[f64; 3]> {
        let mut v: std::vec::Vec<[f64; 3]> =
            (0..=12).map(|k| [0.0, 0.5 * f64::from(k), 0.0]).collect();
        v.extend([[0.9, -0.8, 0.1], [-0.9, -0.8, 0.0], [0.9, 6.8, -0.2]]);
        v
    }

    /// The fixed-point kernel is the paper's formula in f64 within 8 LSB
    /// for V and 384 LSB for ∇V (|∇V| reaches 100 here: 6.5·10⁶ LSB;
    /// measured 5.5 and 267) beyond the relative error that the
    /// rounding of a distance d to ½ LSB brings (V·½ LSB/d, 2|∇V|·½
    /// LSB/d), at points from 0.1 to tens of units from the skeleton;
    /// the f64 reference is the formula itself within 1e-12.
    #[test]
    fn the_kernel_is_the_papers_formula() {
        let vf = shaft();
        let vx: std::vec::Vec<[Fx; 3]> = vf.iter().map(|x| fx3(x[0], x[1], x[2])).collect();
        let vf: std::vec::Vec<[f64; 3]> = vx.iter().map(|x| x.map(f64::from_fx)).collect();
        let lsb = 1.0 / 65_536.0;
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let (mut worst_v, mut worst_g) = (0.0f64, 0.0f64);
        for k in 0..4_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let spread = [0.5, 1.5, 4.0, 20.0][k % 4];
            let c = |s: u32| ((state >> s) as u16 as f64 / 65_536.0 - 0.5) * spread;
            let r = fx3(c(0), 3.0 + c(16), c(32));
            let rf = r.map(f64::from_fx);
            let rv = Vector3::from(r);
            // Nearer a vertex, V ≈ 1/d and the rounding of d (½ LSB)
            // is relative: 1/d² LSB.
            let nearest = vf
                .iter()
                .map(|x| f64::norm(&(Vector3::from(rf) - Vector3::from(*x))))
                .fold(f64::MAX, f64::min);
            if nearest < 0.1 {
                continue;
            }
            let (v, g) = normalised_fx(&vx, &rv, true);
            let (v64, g64) = normalised(&vf, &Vector3::from(rf), true);
            assert!((v64 - paper(&vf, rf)).abs() < 1e-12);
            assert_eq!(normalised_fx(&vx, &rv, false).0, v);
            // In LSB beyond the relative error of d's rounding, ½ LSB
            // in d: V/d·½ LSB for V, 2|∇V|/d·½ LSB for ∇V.
            let slack = 0.5 * lsb / nearest;
            worst_v = worst_v.max(((v.to_f64() - v64).abs() - v64 * slack) / lsb);
            for i in 0..3 {
                let allowed = 2.0 * f64::norm(&g64) * slack;
                worst_g = worst_g.max(((g[i].to_f64() - g64[i]).abs() - allowed) / lsb);
            }
        }
        assert!(worst_v <= 8.0, "V off by {worst_v} LSB");
        assert!(worst_g <= 384.0, "∇V off by {worst_g} LSB");
    }

    /// ∇V of the reference is the derivative of V (central differences).
    #[test]
    fn the_gradient_is_the_derivative() {
        let v = shaft();
        for r in [[1.2, 2.0, 0.3], [-0.8, 6.0, -0.5], [0.3, -1.1, 0.9]] {
            let r = Vector3::from(r);
            let (_, g) = normalised(&v, &r, true);
            for k in 0..3 {
                let mut dr = Vector3::zeros();
                dr[k] = 1e-6;
                let numeric = (normalised(&v, &(r + dr), false).0
                    - normalised(&v, &(r - dr), false).0)
                    / 2e-6;
                assert!((numeric - g[k]).abs() < 1e-6, "{numeric} vs {}", g[k]);
            }
        }
    }

    /// What the constant weights lack: the ρ_i(r) sum to 1, so V is a
    /// mean of the 1/|r − R_i| and lies between the least and the largest
    /// of them, and a vertex met again (a joint) adds nothing; the
    /// constant-weight sum grows with every element.
    #[test]
    fn v_is_a_mean_of_the_inverse_distances() {
        let v = shaft();
        let r = Vector3::new(0.4, 3.1, 0.2);
        let u: std::vec::Vec<f64> = v
            .iter()
            .map(|x| 1.0 / f64::norm(&(r - Vector3::from(*x))))
            .collect();
        let (value, _) = normalised(&v, &r, false);
        let most = u.iter().copied().fold(0.0, f64::max);
        let least = u.iter().copied().fold(f64::MAX, f64::min);
        assert!(least < value && value < most);
        // The constant-weight sum with ρ = 1 is Σ u_i, 4 times more here.
        assert!(u.iter().sum::<f64>() > 4.0 * value);
        // A skeleton whose every segment is drawn twice: the same vertices.
        let segments: std::vec::Vec<Element<f64>> = v
            .windows(2)
            .flat_map(|w| {
                let s = Element::segment(Vector3::from(w[0]), Vector3::from(w[1]), 1.0);
                [s, s]
            })
            .collect();
        let mut collected = Vec::new();
        assert!(collect_vertices(&segments, &mut collected).is_ok());
        assert_eq!(&collected[..], &v[..]);
        assert!(vertices_hold(&segments, &collected));
        assert!(!vertices_hold(&segments[2..], &collected));
    }

    /// A single vertex's surface is the sphere of radius 1/V0; far
    /// vertices, saturated offsets and a vertex at r itself stay finite.
    #[test]
    fn one_vertex_and_the_edges_of_the_range() {
        let one = [fx3(1.0, 2.0, 3.0)];
        let (v, g) = normalised_fx(&one, &Vector3::from(fx3(1.0, 6.0, 3.0)), true);
        assert_eq!(v, Fx::from_ratio(1, 4));
        assert_eq!(
            Vector3::from([g.x, g.y, g.z]),
            Vector3::from(fx3(0.0, -0.0625, 0.0))
        );
        let far = [fx3(-32_000.0, 32_000.0, 0.0), fx3(0.0, 0.0, 0.0)];
        for r in [fx3(32_000.0, -32_000.0, 9.0), fx3(0.0, 0.0, 0.0)] {
            let (v, g) = normalised_fx(&far, &Vector3::from(r), true);
            assert!(v > Fx::ZERO && g.iter().all(|c| c.to_bits() > i32::MIN));
        }
        assert_eq!(normalised_fx(&[], &Vector3::zeros(), true).0, Fx::ZERO);
    }
}
