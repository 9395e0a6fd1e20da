//! What a clonal mosaic's cells grow on for a run (thesis Secs. 3.2 and
//! 4.1): the plane of a [`Domain`](super::Domain) ([`PlaneTerrain`]) or a
//! triangle mesh ([`MeshTerrain`](super::MeshTerrain)). The day —
//! division, the radius r = w_r·√(area/N), ρ relaxations — is the same on
//! both ([`Mosaic`](super::Mosaic)); a terrain says only where a new cell
//! lands, how large the ground is, where a cell reads the control image
//! (Sec. 3.2.2) and how one relaxation step is set up there.

use super::MosaicError;
use super::control::Field;
use super::grid::Grid;
use super::ground::Ground;
use super::params::{MAX_TYPES, Params};
use super::relaxation::{Forces, Plane};
use super::store::Relax;
use crate::Error;
use crate::fx::Fx;
use crate::rng::KeyedRng;
use crate::stream::{Record, Sink};

/// The weights of one relaxation that are the same on every ground
/// (Sec. 3.2.1.1): the radius r, the repulsion 1 − α of each pair of
/// types, w_d, w_a and the momentum β, all Q16 bits.
#[derive(Clone, Copy, Debug)]
pub struct Push {
    /// The repulsion radius r.
    pub radius: i32,
    /// The repulsion of each pair of types (1 during the initial
    /// relaxation, which ignores adhesion).
    pub repel: [[i32; MAX_TYPES]; MAX_TYPES],
    /// w_d.
    pub push_weight: i32,
    /// w_a.
    pub anisotropy_weight: i32,
    /// β.
    pub momentum: i32,
}

/// Where a mosaic's cells grow, with what a run keeps of it (the
/// anisotropy field, the mesh): what differs between the plane and a mesh.
pub trait Terrain {
    /// The cells' ground: what a cell's place is and how a step moves it.
    type Ground: Ground;

    /// Gets ready for a run of `params` (interpolates the anisotropy
    /// field; on a mesh, builds the mesh).
    ///
    /// # Errors
    /// An unusable field or mesh.
    fn prepare(&mut self, params: &Params) -> Result<(), Error>;

    /// r = w_r·√(area/N) for `cells` cells (Q16 bits), clamped to what the
    /// ground allows.
    fn radius(&self, params: &Params, cells: u32) -> i32;

    /// Draws places uniformly at random on the ground (day 0).
    fn scatter(&self, params: &Params)
    -> impl FnMut(&mut KeyedRng) -> <Self::Ground as Ground>::At;

    /// Where a daughter cell lands: `offset` (Q16, in the disc of
    /// division) from its mother at `at`.
    fn offspring(
        &self,
        params: &Params,
    ) -> impl Fn(<Self::Ground as Ground>::At, [i32; 2]) -> <Self::Ground as Ground>::At;

    /// The (u, v) in the domain at which a cell at `at` reads the mask.
    fn control_uv(&self, params: &Params, at: &<Self::Ground as Ground>::At) -> [i32; 2];

    /// `times` relaxation steps of the first `n` cells of `store` with
    /// `push`, the ground's grid and the anisotropy field.
    fn relax<S: Relax<Self::Ground>>(
        &self,
        store: &mut S,
        n: usize,
        push: Push,
        params: &Params,
        times: u16,
    );

    /// The records of a streamed frame `frame` before its cells (the mesh,
    /// once).
    ///
    /// # Errors
    /// The sink's.
    fn records(&self, frame: u32, sink: &mut dyn Sink) -> Result<(), Error>;

    /// The record of cell `id` of type `kind` at `at`.
    fn cell(id: u32, kind: u8, at: &<Self::Ground as Ground>::At) -> Record;
}

/// The plane of a domain (periodic or walled) with the anisotropy field
/// interpolated over it ([`Field`]).
#[derive(Debug)]
pub struct PlaneTerrain {
    field: Field,
}

impl PlaneTerrain {
    /// No field yet (all zero bytes).
    pub const EMPTY: PlaneTerrain = PlaneTerrain {
        field: Field::zero(),
    };
}

impl Terrain for PlaneTerrain {
    type Ground = Plane;

    fn prepare(&mut self, params: &Params) -> Result<(), Error> {
        // Without anisotropy the field is not read.
        if let Some(a) = &params.anisotropy {
            self.field = Field::interpolate(&params.domain, a).map_err(MosaicError::Control)?;
        }
        Ok(())
    }

    /// Held below half the smallest side, so that the minimum image is
    /// unique.
    fn radius(&self, params: &Params, cells: u32) -> i32 {
        let n = i64::from(cells.max(1));
        let spacing = ((params.domain.area_q32() / n) as u64).isqrt() as i64; // Q16
        let r = (spacing * i64::from(params.radius_weight.to_bits())) >> 16;
        let half = i64::from(params.domain.size[0].min(params.domain.size[1]).to_bits() / 2 - 1);
        r.clamp(1, half.max(1)) as i32
    }

    fn scatter(&self, params: &Params) -> impl FnMut(&mut KeyedRng) -> [i32; 2] {
        let size = params.domain.size.map(|s| s.to_bits() as u32);
        move |rng| [rng.below(size[0]) as i32, rng.below(size[1]) as i32]
    }

    fn offspring(&self, params: &Params) -> impl Fn([i32; 2], [i32; 2]) -> [i32; 2] {
        let domain = &params.domain;
        move |p, off| {
            [
                domain.confine(0, i64::from(p[0]) + i64::from(off[0])),
                domain.confine(1, i64::from(p[1]) + i64::from(off[1])),
            ]
        }
    }

    fn control_uv(&self, _: &Params, at: &[i32; 2]) -> [i32; 2] {
        *at
    }

    fn relax<S: Relax<Plane>>(
        &self,
        store: &mut S,
        n: usize,
        push: Push,
        params: &Params,
        times: u16,
    ) {
        let max_bins = store.slices().bins.len().saturating_sub(1);
        let grid = Grid::plan(&params.domain, push.radius, max_bins);
        let forces = Forces {
            domain: &params.domain,
            grid: &grid,
            radius: push.radius,
            repel: push.repel,
            push_weight: push.push_weight,
            anisotropy_weight: push.anisotropy_weight,
            field: params.anisotropy.as_ref().map(|_| &self.field),
            momentum: push.momentum,
        };
        store.relax(n, &forces, times);
    }

    fn records(&self, _: u32, _: &mut dyn Sink) -> Result<(), Error> {
        Ok(())
    }

    fn cell(id: u32, kind: u8, at: &[i32; 2]) -> Record {
        Record::Cell {
            id,
            kind,
            p: [Fx::from_bits(at[0]), Fx::from_bits(at[1])],
        }
    }
}

/// The repulsion of each pair of types (Q16) for the adhesion `alpha`:
/// 1 − α_pq (thesis Sec. 3.2.1.1, as the original MClone code computes
/// it), or 1 for every pair without `adhesion` (the initial relaxation).
/// A type with a higher self-adhesion is softer, so a growing clone of
/// stiffer cells presses its softer neighbours into thin borders between
/// the clones (docs/mosaics.md).
pub(crate) fn repulsion(
    alpha: &[[Fx; MAX_TYPES]; MAX_TYPES],
    adhesion: bool,
) -> [[i32; MAX_TYPES]; MAX_TYPES] {
    if adhesion {
        alpha.map(|row| row.map(|a| (Fx::ONE - a.clamp(Fx::ZERO, Fx::ONE)).to_bits()))
    } else {
        [[1 << 16; MAX_TYPES]; MAX_TYPES]
    }
}
