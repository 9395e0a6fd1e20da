//! Horns grown from modules placed by time-dependent positioners (horn
//! paper, Stępień & Prolejko, Secs. 4–7, Algorithm 1, Table 1, Eq. 1).
//!
//! A horn is a linear hierarchy of modules E_1 … E_k; module i appears at
//! global time (i−1)T, grows while its local time τ runs over \[0, T\] and then
//! keeps its shape. Its positioner P_i(τ) = T_i(τ)·R_z·R_y·R_x
//! is used twice: it sweeps the cross-sections L_i(θ) into the module's
//! surface V_i(τ) = P_i(τ)·⋃_{θ∈\[0,τ\]} P_i(θ)⁻¹·L_i(θ) (a generalised
//! cylinder, Algorithm 1), and it carries the older horn:
//! Z_i(t) = V_i(τ) ∪ P_i(τ)·Ẑ_{i−1} ([`HornKernel`]). Only the youngest
//! positioner moves, and the upper base of module i is by construction the
//! lower base of module i−1, so the surface is continuous at every t.
//!
//! Conventions (pinned here, the paper's figures disagree with each other):
//! - the skull frame is module k's (the youngest's) frame: its active area
//!   (lower base) is the cross-section in the y–z plane at the origin, and
//!   the module grows along +x;
//! - the path K_i(θ) is an arc of radius r in the x–y plane bending towards
//!   +y: the bend α(θ) = α(T)·f(θ) is R_z; the twist β(θ) = β(T)·f(θ) turns
//!   the positioner about the path's tangent, which is R_x (innermost, so it
//!   is a roll about the tangent at K_i(θ)); R_y is the identity;
//! - lengths are centimetres as [`Fx`](crate::fx::Fx) (the full ram horn
//!   is about 111 cm along its path and its coordinates stay within
//!   ±45 cm), local and global times are days (T = 365), and the `time` of
//!   a frame in the stream is in years;
//! - scales are ratios relative to L_1(T) (Table 1 in %, divided by 100).
//!
//! The kernel is generic over [`Real`](crate::fx::Real): the [`Fx`](crate::fx::Fx)
//! instance writes the stream, the `f64` instance is its accuracy reference.

mod clock;
mod error;
mod kernel;
mod outline;
mod params;
mod positioner;
mod sim;

pub use clock::{LocalTime, Moment};
pub use error::HornError;
pub use kernel::{Emit, HornKernel};
pub use outline::Outline;
pub use params::{HornParams, Module, Percent};
pub use sim::Horn;

/// Capacity: modules per horn (the ram horn has 8).
pub const MAX_MODULES: usize = 16;

/// Capacity: points per cross-section (per ring).
pub const MAX_RING_POINTS: usize = 64;
