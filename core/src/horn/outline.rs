//! The cross-section L_i(θ): a closed outline resampled to a fixed number
//! of points (horn paper, Sec. 6 and Fig. 7b: "a closed line resembling a
//! triangle"), scaled from the positioner's size to the lower base's.

use super::{HornError, MAX_RING_POINTS};
use crate::Error;
use crate::fx::{Fx, Real};

#[cfg(test)]
const fn pt(y: i32, z: i32) -> [Fx; 2] {
    [Fx::from_ratio(y, 10_000), Fx::from_ratio(z, 10_000)]
}

/// The default cross-section, the paper's rounded triangle at the size of
/// L_1(T): an equilateral triangle of circumradius 2 cm offset by 1.5 cm
/// (corners are 120° arcs of radius 1.5 cm, 7 vertices each), so it spans
/// 3.5 cm from the centre to a corner and 2.5 cm to a side; a corner points
/// along +z. Counter-clockwise in (y, z). (The `ram-horn` scenarios'
/// outline.)
#[cfg(test)]
pub static ROUNDED_TRIANGLE: [[Fx; 2]; 21] = [
    pt(12_990, 27_500),
    pt(9_642, 31_491),
    pt(5_130, 34_095),
    pt(0, 35_000),
    pt(-5_130, 34_095),
    pt(-9_642, 31_491),
    pt(-12_990, 27_500),
    pt(-30_311, -2_500),
    pt(-32_093, -7_395),
    pt(-32_093, -12_605),
    pt(-30_311, -17_500),
    pt(-26_962, -21_491),
    pt(-22_451, -24_095),
    pt(-17_321, -25_000),
    pt(17_321, -25_000),
    pt(22_451, -24_095),
    pt(26_962, -21_491),
    pt(30_311, -17_500),
    pt(32_093, -12_605),
    pt(32_093, -7_395),
    pt(30_311, -2_500),
];

/// A cross-section of `len` points equally spaced along a closed polyline,
/// at scale 1; the points start at the polyline's first vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline<R: Real> {
    points: [[R; 2]; MAX_RING_POINTS],
    len: u16,
}

impl<R: Real> Outline<R> {
    /// Resamples `polyline` (closed: the last vertex joins the first) to
    /// `count` points spaced equally by arc length.
    ///
    /// # Errors
    /// `MAX_RING_POINTS` exceeded, or a polyline with fewer than 3 vertices
    /// or zero length ([`HornError::DegenerateOutline`]).
    pub fn resample(polyline: &[[Fx; 2]], count: u16) -> Result<Outline<R>, Error> {
        if count as usize > MAX_RING_POINTS {
            return Err(Error::Capacity {
                limit: "horn::MAX_RING_POINTS",
                capacity: MAX_RING_POINTS as u32,
            });
        }
        if polyline.len() < 3 || count == 0 {
            return Err(HornError::DegenerateOutline.into());
        }
        let vertex = |i: usize| {
            let [y, z] = polyline[i % polyline.len()];
            [R::from_fx(y), R::from_fx(z)]
        };
        let edge_length = |i: usize| {
            let (a, b) = (vertex(i), vertex(i + 1));
            let (dy, dz) = (b[0] - a[0], b[1] - a[1]);
            (dy * dy + dz * dz).sqrt()
        };
        let mut perimeter = R::zero();
        for i in 0..polyline.len() {
            perimeter += edge_length(i);
        }
        if perimeter <= R::zero() {
            return Err(HornError::DegenerateOutline.into());
        }
        let mut points = [[R::zero(); 2]; MAX_RING_POINTS];
        // Walk the edges once; `start` is the arc length at edge `edge`'s
        // first vertex. Range: perimeter ≤ a few hundred cm, well inside Fx.
        let (mut edge, mut start) = (0usize, R::zero());
        let mut length = edge_length(0);
        for (k, slot) in points.iter_mut().take(count as usize).enumerate() {
            let target = perimeter * R::from_ratio(k as i32, count as i32);
            while start + length < target && edge + 1 < polyline.len() {
                start += length;
                edge += 1;
                length = edge_length(edge);
            }
            let (a, b) = (vertex(edge), vertex(edge + 1));
            let along = if length > R::zero() {
                (target - start).div(length)
            } else {
                R::zero()
            };
            *slot = [a[0] + (b[0] - a[0]) * along, a[1] + (b[1] - a[1]) * along];
        }
        Ok(Outline { points, len: count })
    }

    /// The points, (y, z) at scale 1.
    #[must_use]
    pub fn points(&self) -> &[[R; 2]] {
        &self.points[..self.len as usize]
    }

    /// Number of points.
    #[must_use]
    pub const fn len(&self) -> u16 {
        self.len
    }

    /// Whether there are no points (never, once resampled).
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    #[test]
    fn equal_spacing_on_the_rounded_triangle() {
        let o = Outline::<f64>::resample(&ROUNDED_TRIANGLE, 24).unwrap();
        let p = o.points();
        assert_eq!(p.len(), 24);
        assert_eq!(
            p[0],
            [1.2990, 2.75].map(|v| (v * 65536.0_f64).round() / 65536.0)
        );
        // Chords between neighbours are nearly equal (arc-length spacing).
        let chords: Vec<f64> = (0..24)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % 24]);
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
            })
            .collect();
        let (lo, hi) = chords
            .iter()
            .fold((f64::MAX, 0.0f64), |(l, h), &c| (l.min(c), h.max(c)));
        assert!(hi - lo < 0.05, "chords {lo}..{hi}");
        // Perimeter of the rounded triangle: 3 sides of 2√3 + a circle of
        // r = 1.5 (≈ 19.81 cm); 24 chords cut its corners a little.
        let expected = 3.0 * 2.0 * 3f64.sqrt() + 2.0 * core::f64::consts::PI * 1.5;
        let perimeter: f64 = chords.iter().sum();
        assert!(
            perimeter < expected && perimeter > expected - 0.25,
            "{perimeter}"
        );
        // Counter-clockwise: positive signed area.
        let area: f64 = (0..24)
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % 24]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum();
        assert!(area > 0.0);
    }

    #[test]
    fn fixed_point_resampling_tracks_f64() {
        let f = Outline::<Fx>::resample(&ROUNDED_TRIANGLE, 24).unwrap();
        let d = Outline::<f64>::resample(&ROUNDED_TRIANGLE, 24).unwrap();
        for (a, b) in f.points().iter().zip(d.points()) {
            for c in 0..2 {
                let lsb = (a[c].to_f64() - b[c]).abs() * 65536.0;
                assert!(lsb <= 16.0, "{lsb} LSB");
            }
        }
    }

    #[test]
    fn limits_are_errors() {
        assert!(matches!(
            Outline::<Fx>::resample(&ROUNDED_TRIANGLE, 65),
            Err(Error::Capacity { .. })
        ));
        assert_eq!(
            Outline::<Fx>::resample(&ROUNDED_TRIANGLE[..2], 8),
            Err(HornError::DegenerateOutline.into())
        );
        let flat = [[Fx::ONE, Fx::ONE]; 4];
        assert_eq!(
            Outline::<Fx>::resample(&flat, 8),
            Err(HornError::DegenerateOutline.into())
        );
    }
}
