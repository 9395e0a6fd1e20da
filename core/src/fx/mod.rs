//! Fixed-point numbers: the I16F16 scalar [`Fx`], binary angles ([`Angle`]),
//! the table-driven elementary functions, and the [`Real`] trait that lets a
//! kernel run on [`Fx`] (what fixtures hold) or on `f64` (its accuracy
//! reference).
//!
//! # Overflow policy
//!
//! One policy, identical in debug and release: **every arithmetic operator on
//! [`Fx`] saturates** at [`Fx::MIN`] / [`Fx::MAX`]. Multiplication and
//! division round to nearest (ties away from zero on the magnitude, i.e.
//! `+0.5 LSB` then floor). Division by zero saturates to the signed extreme
//! (`0 / 0 = 0`). Kernels that need exact wrap-around use [`Angle`] or
//! integer accumulators (`i64`) instead.

mod angle;
pub(crate) mod func;
mod number;
mod real;
pub(crate) mod root;
mod tables;
mod wide;

#[cfg(test)]
mod accuracy;
#[cfg(test)]
mod tables_gen;

pub use angle::Angle;
pub use number::Fx;
pub use real::Real;
pub use wide::{dot_wide, length, length_of_squared};
