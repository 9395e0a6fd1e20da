//! Global and local time (horn paper, Eq. 1): module i lives in
//! (i−1)T < t ≤ iT with local time τ_i = t − (i−1)T.
//!
//! Times are exact fractions of the delay T, so which module is the
//! youngest and which cross-sections already exist are decided in integers,
//! identically for the fixed-point kernel and its `f64` reference.

use crate::fx::Real;

/// A time as `num / den` of the delay T (years, in the presets).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Moment {
    /// Numerator.
    pub num: u32,
    /// Denominator (positive).
    pub den: u32,
}

/// Eq. 1 at a global time t: the youngest module and its local time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LocalTime {
    /// i with (i−1)T < t ≤ iT (1-based).
    pub youngest: u32,
    /// τ_i = t − (i−1)T, in (0, T\].
    pub tau: Moment,
}

impl Moment {
    /// `num / den` of T.
    #[must_use]
    pub const fn new(num: u32, den: u32) -> Moment {
        Moment { num, den }
    }

    /// Eq. 1; `None` at t ≤ 0 (no module exists yet) or when `den` is zero.
    #[must_use]
    pub const fn local(self) -> Option<LocalTime> {
        if self.num == 0 || self.den == 0 {
            return None;
        }
        let youngest = self.num.div_ceil(self.den);
        Some(LocalTime {
            youngest,
            tau: Moment::new(self.num - (youngest - 1) * self.den, self.den),
        })
    }

    /// Whether `self ≤ other` (exact, cross-multiplied in u64).
    #[must_use]
    pub const fn at_most(self, other: Moment) -> bool {
        self.num as u64 * other.den as u64 <= other.num as u64 * self.den as u64
    }

    /// Whether `self = other` as fractions.
    #[must_use]
    pub const fn same(self, other: Moment) -> bool {
        self.num as u64 * other.den as u64 == other.num as u64 * self.den as u64
    }

    /// The time in days for a delay of `delay_days` (rounded for `Fx`,
    /// exact for `f64`). The caller keeps `num · delay_days` within `i32`.
    #[must_use]
    pub fn days<R: Real>(self, delay_days: u16) -> R {
        let num = (self.num as i64 * delay_days as i64).min(i32::MAX as i64) as i32;
        let den = self.den.min(i32::MAX as u32) as i32;
        R::from_ratio(num, den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equation_one() {
        // t = 1.5 T: module 2, τ = T/2.
        let l = Moment::new(3, 2).local().unwrap();
        assert_eq!(l.youngest, 2);
        assert_eq!(l.tau, Moment::new(1, 2));
        // t = 2T exactly still belongs to module 2 with τ = T ((i−1)T < t ≤ iT).
        let l = Moment::new(24, 12).local().unwrap();
        assert_eq!((l.youngest, l.tau), (2, Moment::new(12, 12)));
        // Just after: module 3, τ = T/12.
        let l = Moment::new(25, 12).local().unwrap();
        assert_eq!((l.youngest, l.tau), (3, Moment::new(1, 12)));
        assert_eq!(Moment::new(0, 12).local(), None);
    }

    #[test]
    fn comparisons_are_exact() {
        assert!(Moment::new(1, 3).at_most(Moment::new(4, 12)));
        assert!(Moment::new(1, 3).same(Moment::new(4, 12)));
        assert!(!Moment::new(5, 12).at_most(Moment::new(1, 3)));
        assert_eq!(
            Moment::new(1, 2).days::<crate::fx::Fx>(365),
            crate::fx::Fx::from_ratio(365, 2)
        );
    }
}
