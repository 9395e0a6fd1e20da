//! Shrinkwrap (bones paper, Secs. 5–6): an adaptive triangle mesh pulled
//! onto the iso-surface V(r) = V0 of a skeleton's field
//! V(r) = Σ ρ_i / |r − R_i| (eq. (6)), from a sphere around the skeleton
//! inwards.
//!
//! - [`Weights`] says what the terms are: the paper's own (eqs. (1)–(2),
//!   the default): the skeleton's vertices, weighted by the normalised,
//!   point-dependent ρ_i(r) = (1/|r − R_i|) / Σ_j 1/|r − R_j|
//!   ([`normalised`]); or Sec. 6's points, segments and convex polygons,
//!   each with its own constant ρ ([`field`](fn@field));
//! - [`field`](fn@field) evaluates V and ∇V (wide accumulators in fixed point);
//! - [`Mesh`] is the closed triangle mesh: a UV sphere, refined by edge
//!   splits only, so it stays a genus-0 2-manifold by construction;
//! - [`Shrinkwrap`] is the iteration: raise V0 by ΔV, move every vertex,
//!   split every edge whose midpoint is off by more than 5 %.
//!
//! All of it is generic over [`crate::fx::Real`]: the `f64` instance is
//! the reference the fixed-point one is measured against.

mod element;
mod field;
mod kernel;
mod mesh;
mod polygon;
mod vertices;
mod wrap;

pub use element::Element;
pub use field::{
    FieldReal, PREPARED_ELEMENTS, PreparedElement, SkeletonField, field, potential, summed_field,
};
pub use mesh::{Mesh, VertexId};
pub use polygon::{MAX_POLYGON_EDGES, POLYGON_TOLERANCE, polygon_edges};
pub use vertices::{
    MAX_VERTICES, Weights, collect_vertices, normalised, normalised_fx, vertices_hold,
};
pub use wrap::{Phase, SPLIT_TOLERANCE, Shrinkwrap, WrapParams, worst_level_error};

#[cfg(test)]
pub(crate) use mesh::tests::{assert_closed_genus_0, signed_volume};

/// An error of a shrinkwrap run's set-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ShrinkwrapError {
    /// The initial sphere needs m a positive multiple of 4 and p odd.
    Sphere {
        /// m.
        meridians: u8,
        /// p.
        parallels: u8,
    },
    /// The target level and its step must be positive.
    Level,
    /// There is nothing to wrap.
    NoSkeleton,
    /// A polygon element with fewer than 3 vertices, an edge of no
    /// length, or no area.
    PolygonDegenerate,
    /// A polygon element's vertex lies off the plane of the polygon (its
    /// Newell normal, through the first vertex) by more than the
    /// tolerance ([`POLYGON_TOLERANCE`]): the farthest such vertex.
    PolygonNotPlanar {
        /// The vertex (from 0, in the polygon's order).
        vertex: u8,
    },
    /// A polygon element's vertex lies outside the line of one of its
    /// edges by more than the tolerance ([`POLYGON_TOLERANCE`]): the
    /// polygon is not convex (or winds more than once).
    PolygonNotConvex {
        /// The vertex (from 0, in the polygon's order).
        vertex: u8,
    },
}

impl core::fmt::Display for ShrinkwrapError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ShrinkwrapError::Sphere {
                meridians,
                parallels,
            } => write!(
                f,
                "initial sphere: {meridians} meridians must be a positive multiple of 4 and {parallels} parallels odd"
            ),
            ShrinkwrapError::Level => {
                f.write_str("the target level V0 and its step ΔV must be positive")
            }
            ShrinkwrapError::NoSkeleton => f.write_str("the skeleton has no elements"),
            ShrinkwrapError::PolygonDegenerate => {
                f.write_str("a polygon element needs at least 3 distinct vertices and an area")
            }
            ShrinkwrapError::PolygonNotPlanar { vertex } => write!(
                f,
                "polygon element: vertex {vertex} lies off the polygon's plane by more than 1/{POLYGON_TOLERANCE} of its size"
            ),
            ShrinkwrapError::PolygonNotConvex { vertex } => write!(
                f,
                "polygon element is not convex: vertex {vertex} lies outside an edge by more than 1/{POLYGON_TOLERANCE} of its size"
            ),
        }
    }
}

impl From<ShrinkwrapError> for crate::Error {
    fn from(e: ShrinkwrapError) -> crate::Error {
        crate::Error::Shrinkwrap(e)
    }
}
