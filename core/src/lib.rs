//! Morphogen's `no_std` core: fixed-point kernels that simulate growth
//! models and stream their results identically, bit for bit, on a
//! workstation and on a Cortex-M.
//!
//! ```
//! use morphogen::fx::Fx;
//! use morphogen::growth::Sigmoid;
//! use morphogen::growth_curve::{GrowthCurve, Params};
//! use morphogen::preset::{self, Model};
//! use morphogen::sim::Start;
//! use morphogen::stream::Encoder;
//!
//! // The horn paper's seasonal sigmoid (Sec. 2): fastest on day 151.5,
//! // 22 days wide, over a year of 365 days, sampled daily.
//! let params = Params {
//!     growth: Sigmoid {
//!         centre: Fx::from_ratio(303, 2),
//!         width: Fx::from_int(22),
//!         span: Fx::from_int(365),
//!     },
//!     days: 365,
//! };
//! let mut curve = GrowthCurve::IDLE;
//! curve.start(&params, 0).unwrap();
//! // Any `embedded_io::Write`: a `Vec<u8>` (the `std` feature), a UART on
//! // a device.
//! let mut encoder = Encoder::new(Vec::new());
//! let digest = Model::GrowthCurve(params).params_digest();
//! let header = preset::header("growth-curve", 0, digest);
//! preset::drive(&mut curve, &header, &mut encoder, &mut |_| {}).unwrap();
//! // The same bytes as the built-in preset's golden fixture
//! // (fixtures/growth-curve/summary.toml), on any target.
//! assert_eq!(encoder.digest(), 0x3796_d9cd_8193_fce1);
//! ```
//!
//! On a microcontroller the same loop runs over a UART: `docs/embedding.md`
//! drives one model directly (the horn with Table 1 written in Rust, in
//! 22 KB of flash and 1.4 KB of static RAM on a Cortex-M0+), through
//! [`preset::Runner`], from a scenario file turned into Rust at build time,
//! and streams while drawing (feature `rig`), with the programs in
//! `firmware-example/examples/` and the flash and RAM of each.
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
