//! End-to-end tests across Morphogen's crates live in `tests/`; this is
//! what several of them share.

#![allow(
    clippy::expect_used,
    clippy::panic,
    reason = "test support: a failure stops the test that asked"
)]

use std::path::Path;
use std::process::Command;

/// The release `morphogen`: `$MORPHOGEN_RELEASE_BIN` when set (CI builds
/// it once for every check), else built here into `target/determinism`.
///
/// # Panics
/// When the build fails.
#[must_use]
pub fn release_binary() -> std::path::PathBuf {
    if let Some(path) = std::env::var_os("MORPHOGEN_RELEASE_BIN") {
        return path.into();
    }
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = workspace.join("target/determinism");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .args([
            "build",
            "--release",
            "--quiet",
            "-p",
            "morphogen-cli",
            "--target-dir",
        ])
        .arg(&target)
        .current_dir(&workspace)
        .status()
        .expect("start cargo");
    assert!(status.success(), "release build failed");
    target.join("release/morphogen")
}
