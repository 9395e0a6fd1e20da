//! Sigmoidal growth over a module's life, with the seasonal timing of the
//! horn paper (Sec. 2: ram horns grow fastest in May and June and almost
//! stop between October and February; Sec. 6: α(t) = α(T)·f(t) with f
//! sigmoidal, Fig. 7c).

use serde::{Deserialize, Serialize};

use crate::fx::{Fx, Real};

/// A normalised logistic growth curve on `[0, span]`:
///
/// `f(t) = (σ((t − c)/w) − σ(−c/w)) / (σ((span − c)/w) − σ(−c/w))`
///
/// so that `f(0) = 0`, `f(span) = 1`, and growth is fastest at `c`. All
/// three parameters are in the same time unit (days here).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sigmoid {
    /// When growth is fastest (`c`).
    pub centre: Fx,
    /// The logistic's time scale (`w`); growth falls to 10 % of its peak
    /// about `3.5·w` away from the centre.
    pub width: Fx,
    /// The length of the life (`span`), e.g. one year T.
    pub span: Fx,
}

/// Days in the simulated year.
pub const YEAR_DAYS: i32 = 365;

impl Sigmoid {
    /// The seasonal growth of a horn module over one year starting on
    /// 1 January: fastest at the turn of May and June (day 151.5),
    /// width 22 days, so May and June together add 60 % of the year's
    /// growth while October to February add under 6 % (horn paper, Sec. 2;
    /// the `growth-curve` and `ram-horn` scenarios' sigmoid).
    #[cfg(test)]
    pub const SEASONAL_YEAR: Sigmoid = Sigmoid {
        centre: Fx::from_ratio(303, 2),
        width: Fx::from_int(22),
        span: Fx::from_int(YEAR_DAYS),
    };

    /// The growth of a life of `days` days: `span` is `days`, as a horn
    /// module's must be (its life is the delay T between modules,
    /// [`HornParams::delay_days`](crate::horn::HornParams::delay_days);
    /// horn paper Sec. 6). A scenario file gives a horn's `centre` and
    /// `width` only and its reader builds the sigmoid so; a horn whose
    /// sigmoid spans anything else is refused with
    /// [`HornError::SpanMismatch`](crate::horn::HornError::SpanMismatch).
    ///
    /// ```
    /// use morphogen::fx::Fx;
    /// use morphogen::growth::Sigmoid;
    /// // The ram horn's seasonal growth over T = 365 days (Sec. 2).
    /// let growth = Sigmoid::over_life(Fx::from_ratio(303, 2), Fx::from_int(22), 365);
    /// assert_eq!(growth.span, Fx::from_int(365));
    /// ```
    #[must_use]
    pub const fn over_life(centre: Fx, width: Fx, days: u16) -> Sigmoid {
        Sigmoid {
            centre,
            width,
            span: Fx::from_int(days as i32),
        }
    }

    /// A plain sigmoid over `span` without seasons: centred on the middle of
    /// the life, width a twelfth of it.
    #[must_use]
    pub const fn plain(span: Fx) -> Sigmoid {
        Sigmoid {
            centre: Fx::from_bits(span.to_bits() / 2),
            width: Fx::from_bits(span.to_bits() / 12),
            span,
        }
    }

    /// `f(t)`, clamped to `[0, 1]` outside `[0, span]`.
    #[must_use]
    pub fn fraction<R: Real>(&self, t: R) -> R {
        let (c, w, span) = (
            R::from_fx(self.centre),
            R::from_fx(self.width),
            R::from_fx(self.span),
        );
        if t <= R::zero() {
            return R::zero();
        }
        if t >= span {
            return R::one();
        }
        let logistic = |x: R| (x - c).div(w).sigmoid();
        let (low, high) = (logistic(R::zero()), logistic(span));
        (logistic(t) - low).div(high - low)
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn growth_in(days: core::ops::Range<i32>) -> f64 {
        let f = |d| Sigmoid::SEASONAL_YEAR.fraction(d as f64);
        f(days.end) - f(days.start)
    }

    #[test]
    fn seasonal_year_matches_the_horn_paper() {
        // Fastest in May–June (days 120..181), almost nothing Oct–Feb.
        assert!(
            growth_in(120..181) > 0.55,
            "May–June {}",
            growth_in(120..181)
        );
        let dormant = growth_in(0..59) + growth_in(273..365);
        assert!(dormant < 0.07, "October–February {dormant}");
        let fastest = (0..365)
            .max_by_key(|&d| (growth_in(d..d + 1) * 1e9) as i64)
            .unwrap();
        assert!((120..181).contains(&fastest), "fastest day {fastest}");
    }

    #[test]
    fn ends_are_exact_and_monotone() {
        let s = Sigmoid::SEASONAL_YEAR;
        assert_eq!(s.fraction(Fx::ZERO), Fx::ZERO);
        assert_eq!(s.fraction(Fx::from_int(365)), Fx::ONE);
        assert_eq!(s.fraction(Fx::from_int(-3)), Fx::ZERO);
        let mut last = Fx::ZERO;
        for d in 0..=365 {
            let v = s.fraction(Fx::from_int(d));
            assert!(v >= last, "not monotone at day {d}");
            last = v;
        }
    }

    #[test]
    fn fixed_point_within_eight_lsb_of_the_reference() {
        for s in [
            Sigmoid::SEASONAL_YEAR,
            Sigmoid::plain(Fx::from_int(365)),
            Sigmoid::plain(Fx::ONE),
        ] {
            for i in 0..=3650 {
                let t = s.span * Fx::from_ratio(i, 3650);
                let err = (s.fraction(t).to_f64() - s.fraction(t.to_f64())).abs() * 65_536.0;
                assert!(err <= 8.0, "{err} LSB at {t} for {s:?}");
            }
        }
    }
}
