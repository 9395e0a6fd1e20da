//! Checked values: a number within its range, or an [`Invalid`] naming
//! the dotted key it came from and what is allowed.

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

/// A real number as 16.16 fixed point, rounded to nearest, within
/// `lo..=hi`.
pub(crate) fn fx(key: &str, v: f64, lo: f64, hi: f64) -> Result<Fx> {
    if !v.is_finite() || v < lo || v > hi {
        return invalid(key, format!("{v} is out of range (allowed: {lo} to {hi})"));
    }
    // |v| < 32768, so v·65536 is exact in f64 and fits an i32 once rounded.
    Ok(Fx::from_bits((v * 65536.0).round() as i32))
}

/// A whole number within `lo..=hi`.
pub(crate) fn int<T: TryFrom<i64>>(key: &str, v: i64, lo: i64, hi: i64) -> Result<T> {
    if v < lo || v > hi {
        return invalid(key, format!("{v} is out of range (allowed: {lo} to {hi})"));
    }
    T::try_from(v).or_else(|_| invalid(key, format!("{v} is out of range")))
}
