//! The surface the cells live on: a rectangle (each axis periodic or
//! walled) or the lateral surface of a cylinder (u around, periodic; v
//! along, walled) — the thesis's control cylinder unrolled (Sec. 3.2.2).
//! Distances respect periodicity (minimum image).

use serde::Serialize;

use crate::fx::Fx;

/// A rectangle `[0, size_u) × [0, size_v)` whose axes may wrap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Domain {
    /// Extent along u and v (positive, at most 16 384).
    pub size: [Fx; 2],
    /// Whether u and v wrap around.
    pub periodic: [bool; 2],
}

impl Domain {
    /// A torus-like rectangle, periodic on both axes (no edges).
    #[must_use]
    pub const fn periodic(u: Fx, v: Fx) -> Domain {
        Domain {
            size: [u, v],
            periodic: [true, true],
        }
    }

    /// A rectangle with walls on all four sides (a flat leaf).
    #[must_use]
    pub const fn walled(u: Fx, v: Fx) -> Domain {
        Domain {
            size: [u, v],
            periodic: [false, false],
        }
    }

    /// The lateral surface of a cylinder of `circumference` and `length`:
    /// u wraps, v is walled (fruits, stems, caps).
    #[must_use]
    pub const fn cylinder(circumference: Fx, length: Fx) -> Domain {
        Domain {
            size: [circumference, length],
            periodic: [true, false],
        }
    }

    /// The area as Q32 bits.
    #[must_use]
    pub const fn area_q32(&self) -> i64 {
        self.size[0].to_bits() as i64 * self.size[1].to_bits() as i64
    }

    /// The displacement `a − b` along `axis` (Q16 bits), the shortest one
    /// on a periodic axis.
    #[inline]
    #[must_use]
    pub fn delta(&self, axis: usize, a: i32, b: i32) -> i32 {
        // Positions are in [0, size) and size ≤ 2^30, so a − b cannot overflow.
        let d = a - b;
        if !self.periodic[axis] {
            return d;
        }
        let size = self.size[axis].to_bits();
        let half = size >> 1;
        if d > half {
            d - size
        } else if d < -half {
            d + size
        } else {
            d
        }
    }

    /// `p` moved back into the domain along `axis`: wrapped on a periodic
    /// axis, held against the wall (inside, one LSB off the far wall)
    /// otherwise.
    #[inline]
    #[must_use]
    pub fn confine(&self, axis: usize, p: i64) -> i32 {
        // At least 1 (a valid size is): the remainder below cannot fail.
        let size = i64::from(self.size[axis].to_bits().max(1));
        let q = if (0..size).contains(&p) {
            p // already inside: no division (a library call on a Cortex-M)
        } else if self.periodic[axis] {
            p.rem_euclid(size)
        } else {
            // max/min, not clamp: the same for a validated size ≥ 1, and
            // no panic path (with its formatting code) for reversed bounds.
            p.max(0).min(size - 1)
        };
        q as i32 // in [0, size) ⊂ i32
    }

    /// Whether the sizes are usable (positive, at most 16 384).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.size
            .iter()
            .all(|s| *s > Fx::ZERO && *s <= Fx::from_int(16_384))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_delta_is_the_minimum_image() {
        let d = Domain::cylinder(Fx::from_int(10), Fx::from_int(4));
        let a = Fx::from_ratio(1, 2).to_bits();
        let b = Fx::from_ratio(19, 2).to_bits();
        assert_eq!(d.delta(0, a, b), Fx::ONE.to_bits());
        assert_eq!(d.delta(0, b, a), -Fx::ONE.to_bits());
        // v is walled: no wrap.
        assert_eq!(d.delta(1, a, b), -Fx::from_int(9).to_bits());
        assert_eq!(d.confine(0, -1), Fx::from_int(10).to_bits() - 1);
        assert_eq!(d.confine(1, -5), 0);
        assert_eq!(d.confine(1, 1 << 40), Fx::from_int(4).to_bits() - 1);
        assert_eq!(d.area_q32(), 40i64 << 32);
    }
}
