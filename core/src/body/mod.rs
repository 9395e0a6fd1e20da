//! Growth data on bodies (growth paper, Secs. 5–8): a polygonal
//! body enclosed by a hierarchy of cylinders, each sized at every age by two
//! measured features, deformed continuously as the animal grows, and
//! animated through the same hierarchy by joint rotations.
//!
//! Its parts, one idea per (private) module:
//! - the hierarchy, placements and features: [`Cylinder`], [`Anchor`],
//!   [`Feature`], [`Drive`];
//! - growth tables and their interpolation: [`table`], [`GrowthTable`];
//! - the 2×2 system for L² and R² (growth matrix G): [`feature_target`];
//! - the transform chain `T_AB·G_A⁻¹·R_AB·R·S·G_B` and its [`Joint`]s;
//! - vertex weights over the cylinders containing a vertex (at most
//!   [`MAX_BINDINGS`]): [`binding_summary`];
//! - the surface, procedural tubes or an indexed [`Mesh`];
//! - the built-in horse and cow: [`quadruped`];
//! - joint angles over a stride (the trot): [`gait`];
//! - the supports, the trunk's pitch and the lift that keep the body
//!   standing, part of posing the [`Skeleton`], which is generic over
//!   [`Real`](crate::fx::Real) (the `f64` instance is the reference);
//! - the [`Body`] simulation and its [`BodyParams`] (the built-in bodies
//!   are the scenarios `horse-growth`, `cow-growth`, `horse-trot`,
//!   `cow-trot`, `horse-with-cow-growth`, `cow-walk`).
//!
//! ```
//! use morphogen::body::{Body, BodyParams, quadruped, table};
//! use morphogen::fx::Fx;
//! use morphogen::sim::{Simulation, Start};
//! use morphogen::stream::{Record, Sink, SinkError};
//!
//! struct Count(u32);
//! impl Sink for Count {
//!     fn record(&mut self, r: &Record) -> Result<(), SinkError> {
//!         if matches!(r, Record::MeshVertex { .. }) {
//!             self.0 += 1;
//!         }
//!         Ok(())
//!     }
//! }
//! // The built-in horse grown by the paper's quarter horse (Table 1),
//! // from birth to 60 months every 6 months (the `horse-growth` scenario).
//! static PARAMS: BodyParams<'static> = BodyParams {
//!     model: &quadruped::HORSE,
//!     table: &table::QUARTER_HORSE,
//!     frames: 11,
//!     first_age: Fx::ZERO,
//!     last_age: Fx::from_int(60),
//!     gait: None,
//!     frames_per_stride: 1,
//! };
//! let mut body: Body = Body::new();
//! body.start(&PARAMS, 0).unwrap();
//! let mut sink = Count(0);
//! body.step(&mut sink).unwrap(); // the newborn foal
//! assert_eq!(sink.0, quadruped::HORSE.mesh.vertex_count());
//! assert_eq!(PARAMS.age(10), Fx::from_int(60));
//! ```

mod binding;
mod chain;
mod cylinder;
mod error;
pub mod gait;
mod label;
mod mesh;
pub mod quadruped;
mod sim;
mod skeleton;
mod solve;
mod stance;
pub mod table;

use serde::Serialize;

pub use binding::MAX_BINDINGS;
pub use chain::Joint;
pub use cylinder::{Anchor, Cylinder, Drive, Feature, Rest};
pub use error::BodyError;
pub use label::{LABEL_BYTES, Label};
pub use mesh::Mesh;
pub use sim::{Body, BodyParams};
pub use skeleton::Skeleton;
pub use solve::feature_target;
pub use table::{GrowthTable, Interpolation};

/// Capacity: cylinders of the built-in bodies' simulation (the horse and
/// the cow have 18). The host runs user bodies with a larger `Body<C>`.
pub const MAX_CYLINDERS: usize = 24;

/// A body: its cylinder hierarchy and its surface, in model space at the
/// age `model_age`, in the unit of the tables it is grown with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BodyModel<'a> {
    /// The cylinders, root first, each after its parent.
    pub cylinders: &'a [Cylinder],
    /// The surface.
    pub mesh: Mesh<'a>,
    /// The age (months) the model shows: a feature that
    /// [follows](Drive::Follows) a column keeps its model length there.
    pub model_age: crate::fx::Fx,
}

/// How a body's vertices are bound (the same at every age and pose).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct BindingSummary {
    /// Vertices.
    pub vertices: u32,
    /// Vertices in no cylinder, following the nearest one.
    pub unbound: u32,
    /// `by_count[n]`: vertices blended from n cylinders.
    pub by_count: [u32; binding::MAX_BINDINGS + 1],
}

/// Binds every vertex of `model` and counts the outcomes.
///
/// # Errors
/// The model's errors (see [`Skeleton::load`]).
pub fn binding_summary<const C: usize>(
    model: &BodyModel<'_>,
    table: &GrowthTable<'_>,
) -> Result<BindingSummary, crate::Error> {
    let mut skeleton = Skeleton::<crate::fx::Fx, C>::new();
    skeleton.load(model, table)?;
    let mut s = BindingSummary::default();
    for i in 0..model.mesh.vertex_count() {
        let Some(p) = model.mesh.vertex(i) else {
            continue;
        };
        let b = skeleton.bind(&p)?;
        s.vertices += 1;
        if b.is_nearest() {
            s.unbound += 1;
        } else if let Some(n) = s.by_count.get_mut(b.len()) {
            *n += 1;
        }
    }
    Ok(s)
}
