//! What can be wrong with a horn's parameters.

/// A horn parameter set that cannot be grown; each names the parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum HornError {
    /// The horn has no module.
    NoModules,
    /// Module `module`'s positioner scale differs from the lower-base scale
    /// of module `module − 1`, so their bases could not coincide (Sec. 7).
    ScaleMismatch {
        /// The younger module (1-based, as in Table 1).
        module: u16,
    },
    /// The growth sigmoid's span differs from the delay T between modules
    /// (a module's life, Sec. 6), or T is above 32767 days (Fx's range);
    /// [`Sigmoid::over_life`](crate::growth::Sigmoid::over_life) builds
    /// the sigmoid of a life of T.
    SpanMismatch {
        /// The delay T, days (`HornParams::delay_days`).
        delay_days: u16,
    },
    /// The cross-section outline has fewer than 3 vertices or no length.
    DegenerateOutline,
    /// `rings_per_module` (J), `ring_points` or `frames_per_year` is zero.
    ZeroCount,
    /// The frames reach past k·T, when the last module is fully grown.
    PastLastModule,
}

impl core::fmt::Display for HornError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            HornError::NoModules => f.write_str("the horn has no module"),
            HornError::ScaleMismatch { module } => write!(
                f,
                "module {module}: positioner scale differs from the lower-base scale of module {}",
                module.saturating_sub(1)
            ),
            HornError::SpanMismatch { delay_days } => write!(
                f,
                "growth.span must equal delay_days (T = {delay_days} days, at most 32767): \
                 build it with Sigmoid::over_life(centre, width, delay_days)"
            ),
            HornError::DegenerateOutline => {
                f.write_str("the cross-section outline needs at least 3 distinct vertices")
            }
            HornError::ZeroCount => {
                f.write_str("rings_per_module, ring_points and frames_per_year must be positive")
            }
            HornError::PastLastModule => {
                f.write_str("years exceeds the number of modules (frames past k·T)")
            }
        }
    }
}

impl core::error::Error for HornError {}
