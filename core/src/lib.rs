//! Morphogen's `no_std` core: fixed-point kernels that simulate growth
//! models and stream their results identically on a workstation and on a
//! Cortex-M.
#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]
#![deny(missing_docs, missing_debug_implementations, rustdoc::broken_intra_doc_links)]
#![deny(clippy::float_arithmetic, clippy::unwrap_used, clippy::expect_used, clippy::panic)]
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used, clippy::panic))]

pub mod fx;
pub mod geom;
pub mod rng;
