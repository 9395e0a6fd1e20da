//! The host side of Morphogen: running scenarios into streams, decoding,
//! drawing and exporting them, and checking them against golden fixtures.
#![forbid(unsafe_code)]
// No function of the host over `too-many-lines-threshold` (clippy.toml).
#![deny(clippy::too_many_lines)]

pub mod atomic;
pub mod bless;
pub mod body_input;
pub mod capture;
pub mod ci_report;
pub mod decode;
pub mod exec;
pub mod fixture;
pub mod folder_lock;
pub mod golden;
pub mod list;
pub mod listen;
pub mod outputs;
pub mod provenance;
pub mod records;
pub mod report;
pub mod review;
pub mod rig;
pub mod run;
pub mod send;
pub mod serial;
pub mod serve;
pub mod stdout;
pub mod sweep;
pub mod verdict;
pub mod written;
pub mod ws2812;

/// How a command ended, mapped to the process exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Everything matched or was written (exit 0).
    Ok,
    /// A stream differs from its fixture (exit 1).
    Mismatch,
}
