//! Checked values: a number within its range, or an [`Invalid`] naming
//! the dotted key it came from and what is allowed.

use std::cell::RefCell;

use morphogen::fx::Fx;

/// A value that is not allowed, with the dotted key it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Invalid {
    /// The dotted key (`mosaic.types[1].division_days`).
    pub key: String,
    /// What is wrong, with what is allowed.
    pub message: String,
}

/// A checked value, or why not.
pub(crate) type Result<T> = std::result::Result<T, Invalid>;

/// The error for `key`.
pub(crate) fn invalid<T>(key: impl Into<String>, message: impl Into<String>) -> Result<T> {
    Err(Invalid {
        key: key.into(),
        message: message.into(),
    })
}

/// `v` as a message shows it: as written for everyday sizes, in
/// scientific notation when very large or very small (`1e308`, not 309
/// digits).
pub(crate) fn shown(v: f64) -> String {
    let size = v.abs();
    if size != 0.0 && !(1e-4..1e9).contains(&size) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A real number as 16.16 fixed point, rounded to nearest, within
/// `lo..=hi`.
pub(crate) fn fx(key: &str, v: f64, lo: f64, hi: f64) -> Result<Fx> {
    note(key, v, lo, hi, false);
    if !v.is_finite() || v < lo || v > hi {
        let v = shown(v);
        return invalid(key, format!("{v} is out of range (allowed: {lo} to {hi})"));
    }
    // |v| < 32768, so v·65536 is exact in f64 and fits an i32 once rounded.
    Ok(Fx::from_bits((v * 65536.0).round() as i32))
}

/// The shortest decimal (at most 5 places, which always suffice for
/// 16.16) that [`fx`] rounds to `v`: a grammar's `delta = 25.7` is noted
/// as 25.7, not as the 25.699996948… its 16.16 value is.
pub(crate) fn decimal(v: Fx) -> f64 {
    let exact = f64::from(v.to_bits()) / 65536.0;
    (0..=5)
        .map(|places| {
            let scale = 10f64.powi(places);
            (exact * scale).round() / scale
        })
        .find(|d| (d * 65536.0).round() as i32 == v.to_bits())
        .unwrap_or(exact)
}

/// A whole number within `lo..=hi`.
pub(crate) fn int<T: TryFrom<i64>>(key: &str, v: i64, lo: i64, hi: i64) -> Result<T> {
    #[allow(clippy::cast_precision_loss)] // a control's bounds, not a value
    note(key, v as f64, lo as f64, hi as f64, true);
    if v < lo || v > hi {
        return invalid(key, format!("{v} is out of range (allowed: {lo} to {hi})"));
    }
    T::try_from(v).or_else(|_| invalid(key, format!("{v} is out of range")))
}

/// A number the check read, with the range it allows: what a control for
/// it (the web page's sliders) may offer.
#[derive(Debug, Clone, PartialEq)]
pub struct Range {
    /// The dotted key (`horn.modules[0].bend`).
    pub key: String,
    /// The value the scenario gives (or its default).
    pub value: f64,
    /// The lowest value allowed.
    pub lo: f64,
    /// The highest value allowed.
    pub hi: f64,
    /// Whether only whole numbers are allowed.
    pub whole: bool,
}

thread_local! {
    /// The ranges [`ranges`] collects on this thread, while it does.
    static NOTED: RefCell<Option<Vec<Range>>> = const { RefCell::new(None) };
}

/// Notes a checked number and its range, when [`ranges`] collects them.
pub(crate) fn note(key: &str, value: f64, lo: f64, hi: f64, whole: bool) {
    NOTED.with_borrow_mut(|noted| {
        if let Some(noted) = noted {
            noted.push(Range {
                key: key.to_string(),
                value,
                lo,
                hi,
                whole,
            });
        }
    });
}

/// Runs `check`, returning its result and every number it checked with
/// its range, in the order checked.
pub(crate) fn ranges<R>(check: impl FnOnce() -> R) -> (R, Vec<Range>) {
    NOTED.with_borrow_mut(|noted| *noted = Some(Vec::new()));
    let result = check();
    let noted = NOTED.with_borrow_mut(Option::take).unwrap_or_default();
    (result, noted)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_messages_are_short() {
        assert_eq!(shown(1e308), "1e308");
        assert_eq!(shown(-2.5e-7), "-2.5e-7");
        assert_eq!(shown(123_456.5), "123456.5");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(f64::NEG_INFINITY), "-inf");
        let e = fx("horn.length", 1e300, 0.0, 100.0).unwrap_err();
        assert_eq!(e.message, "1e300 is out of range (allowed: 0 to 100)");
    }

    #[test]
    fn a_fixed_point_value_is_noted_as_its_shortest_decimal() {
        for written in [25.7, 22.5, 0.1, -2.71, 0.0, 1.0 / 3.0, 32767.99998] {
            let v = fx("k", written, -32768.0, 32768.0).unwrap();
            let d = decimal(v);
            assert_eq!(fx("k", d, -32768.0, 32768.0).unwrap(), v, "{written}");
            assert!(
                format!("{d}").len() <= format!("{written}").len(),
                "{written} → {d}"
            );
        }
        assert_eq!(decimal(fx("k", 25.7, 0.0, 100.0).unwrap()), 25.7);
    }
}
