//! Which Morphogen made a file: its version, and the git commit when it
//! was built from a checkout (`summary.toml`'s `blessed_by`, `sweep.csv`'s
//! `morphogen` column, `morphogen --version`).

/// The git commit this was built from (none outside a checkout).
pub const COMMIT: Option<&str> = option_env!("MORPHOGEN_GIT_COMMIT");

/// `0.1.0`, or `0.1.0 (git 0123456789ab)` from a checkout.
#[must_use]
pub fn version() -> String {
    let version = env!("CARGO_PKG_VERSION");
    match COMMIT {
        Some(commit) => format!("{version} (git {})", &commit[..commit.len().min(12)]),
        None => version.to_string(),
    }
}

/// `morphogen 0.1.0 (git 0123456789ab)`: what a file records as its maker.
#[must_use]
pub fn maker() -> String {
    format!("morphogen {}", version())
}
