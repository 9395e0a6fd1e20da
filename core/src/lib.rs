//! Morphogen's `no_std` core: fixed-point kernels that simulate growth
//! models and stream their results identically, bit for bit, on a
//! workstation and on a Cortex-M.
//!
//! ```
//! use morphogen::preset::{self, Runner};
//! use morphogen::stream::Encoder;
//!
//! // A built-in scenario (`scenarios/growth-curve.toml`), read by the std
//! // crate `morphogen-scenario`; the firmware compiles its presets in.
//! let scenario = morphogen_scenario::builtin("growth-curve").unwrap();
//! scenario.with_preset(|preset| {
//!     // Any `embedded_io::Write`: a `Vec<u8>` (the `std` feature), a
//!     // UART on a device.
//!     let mut encoder = Encoder::new(Vec::new());
//!     preset::run(preset, 0, &mut Runner::new(), &mut encoder, &mut |_| {}).unwrap();
//!     assert!(encoder.frames() > 700);
//!     println!("digest {:016x}", encoder.digest());
//! });
//! ```
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
// The workspace's lints (Cargo.toml), and no floats in the kernels.
#![deny(clippy::float_arithmetic)]
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used, clippy::panic))]

pub mod body;
pub mod bones;
mod error;
pub mod fx;
pub mod geom;
pub mod growth;
pub mod growth_curve;
pub mod horn;
pub mod lsys;
pub mod mosaic;
pub mod preset;
#[cfg(feature = "rig")]
pub mod rig;
pub mod rng;
pub mod sent;
pub mod shrinkwrap;
pub mod sim;
pub mod stream;
pub mod turtle;

pub use error::Error;

/// The writer traits the [`stream::Encoder`] writes through, in the version
/// it implements them for.
pub use embedded_io;
/// The `std::io` adapters of `embedded_io`, for [`stream::Encoder`] on a
/// file (with the `std` feature).
#[cfg(feature = "std")]
pub use embedded_io_adapters;
/// The fixed-capacity types of the public API ([`stream::PresetName`]), in
/// the version it uses.
pub use heapless;
