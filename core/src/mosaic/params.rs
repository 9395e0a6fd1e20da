//! The parameters of an MClone run (thesis Table 3.1 per type and pair of
//! types, Table 4.1 per figure).

use serde::Serialize;

use super::control::{Anisotropy, Mask};
use super::domain::Domain;
use super::surface::spec::Surface;
use crate::fx::Fx;

/// The most cell types a run may have (the thesis uses F, B and M).
pub const MAX_TYPES: usize = 4;

/// What a type of cell is (thesis Table 3.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CellType {
    /// Display colour (RGB).
    pub colour: [u8; 3],
    /// D_T: the mean number of days between divisions (1 to 1024).
    pub division_days: u16,
    /// Probability that an initial cell is of this type.
    pub initial_probability: Fx,
}

/// Which days become frames of the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Frames<'a> {
    /// Day 0 (after the initial relaxation) and every day after.
    EveryDay,
    /// Only these days (0 = after the initial relaxation).
    Days(&'a [u16]),
}

impl Frames<'_> {
    /// Whether day `day` of a run of `days` days is a frame.
    #[must_use]
    pub fn includes(&self, day: u16) -> bool {
        match self {
            Frames::EveryDay => true,
            Frames::Days(days) => days.contains(&day),
        }
    }
}

/// Everything that defines a run besides the seed.
///
/// Type 0 is the background B: cells of other types that the mask does not
/// allow start as type 0 (thesis Sec. 3.2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Params<'a> {
    /// The surface.
    pub domain: Domain,
    /// C_i: cells spread uniformly at random on day 0.
    pub initial_cells: u32,
    /// The cell types (1 to [`MAX_TYPES`]).
    pub types: &'a [CellType],
    /// α for each pair of types (symmetric, in [0, 1]; a type with itself
    /// at most [`MAX_SELF_ADHESION`]): a pair p, q repels with 1 − α_pq
    /// (thesis Sec. 3.2.1.1).
    pub adhesion: [[Fx; MAX_TYPES]; MAX_TYPES],
    /// `mutation[parent][child]`: probability that a child of `parent` is of
    /// type `child` (off the diagonal; the rest of the row keeps the
    /// parent's type).
    pub mutation: [[Fx; MAX_TYPES]; MAX_TYPES],
    /// w_r: the repulsion radius is w_r·√(area/N).
    pub radius_weight: Fx,
    /// w_d: the scale of the summed repulsion.
    pub push_weight: Fx,
    /// ρ_i: relaxations before day 1 (adhesion ignored).
    pub initial_relaxations: u16,
    /// ρ_s: relaxations per day.
    pub daily_relaxations: u16,
    /// β of the heavy-ball relaxation, 0 to [`MAX_MOMENTUM`]: each step
    /// also moves a cell β times its last move, so pressure crosses a
    /// clone in fewer steps to the same equilibrium (docs/mosaics.md,
    /// "Departures from the thesis"). 0 is the thesis's plain step and needs no velocities
    /// (and leaves the parameter digest as it was before β existed).
    #[serde(skip_serializing_if = "is_zero")]
    pub momentum: Fx,
    /// Days simulated after the initial relaxation.
    pub days: u16,
    /// Where foreground cells may start, if anywhere restricted.
    pub mask: Option<Mask<'a>>,
    /// The anisotropy field and its weight w_a, if any.
    pub anisotropy: Option<Anisotropy<'a>>,
    /// Which days are streamed.
    pub frames: Frames<'a>,
    /// The mesh the cells live on ([`SurfaceMosaic`](super::SurfaceMosaic)); `None` on the
    /// domain itself. The domain then gives the (u, v) the mask is read in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface<'a>>,
}

fn is_zero(x: &Fx) -> bool {
    *x == Fx::ZERO
}

/// The largest adhesion α of a type with itself: its cells must still
/// repel each other, or a child would never leave its parent's place.
pub const MAX_SELF_ADHESION: Fx = Fx::from_ratio(95, 100);

/// The largest momentum β: below 1, so that every move dies out.
pub const MAX_MOMENTUM: Fx = Fx::from_ratio(95, 100);

/// w_d of the original MClone code (docs/mosaics.md).
pub const ORIGINAL_PUSH_WEIGHT: Fx = Fx::from_ratio(66, 1000);

/// An adhesion (or mutation) table from the diagonal and one value for
/// every pair of distinct types.
#[must_use]
pub const fn pair_table(diagonal: [Fx; MAX_TYPES], off: Fx) -> [[Fx; MAX_TYPES]; MAX_TYPES] {
    let mut t = [[off; MAX_TYPES]; MAX_TYPES];
    let mut i = 0;
    while i < MAX_TYPES {
        t[i][i] = diagonal[i];
        i += 1;
    }
    t
}

/// No mutation at all.
pub const NO_MUTATION: [[Fx; MAX_TYPES]; MAX_TYPES] = [[Fx::ZERO; MAX_TYPES]; MAX_TYPES];
