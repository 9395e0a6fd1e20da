//! Clonal mosaics: the MClone model of Walter et al. as used for plant
//! patterns in the MClone thesis (Secs. 3.2 and 4.1; docs/mosaics.md), in
//! bounded memory and fixed point.
//!
//! Cells are points with a type on a [`Ground`]: the [`Plane`] of a
//! [`Domain`] ([`Mosaic`]) or a triangle mesh ([`OnMesh`],
//! [`SurfaceMosaic`]). Day 0 spreads [`Params::initial_cells`] cells
//! uniformly at random (types by their initial probabilities, foreground
//! only where the [`Mask`] allows) and relaxes them ρ_i times ignoring
//! adhesion. Each following day first divides the cells whose division day
//! has come, then recomputes the repulsion radius r = w_r·√(area/N) and
//! relaxes ρ_s times (Sec. 3.2.1.1). One [`Mosaic`] runs that day on
//! either ground: its [`Terrain`] ([`PlaneTerrain`], [`MeshTerrain`]) says
//! where cells land, how large the ground is and where the mask is read;
//! both keep their cells in one kind of store ([`CellStore`], inline:
//! [`ArrayStore`]) and relax them through one trait ([`Relax`]) with one
//! force law; only the neighbour search and how a cell moves differ.
//! Selected days are streamed as frames of cell records
//! ([`Record::Cell`](crate::stream::Record::Cell); on a mesh,
//! [`Record::SurfaceCell`](crate::stream::Record::SurfaceCell) after the
//! mesh); the host draws them as Voronoi regions.
//!
//! ```
//! use morphogen::fx::Fx;
//! use morphogen::mosaic::{CellType, Domain, Frames, McuStore, Mosaic, NO_MUTATION, Params};
//! use morphogen::mosaic::{ORIGINAL_PUSH_WEIGHT, pair_table};
//! use morphogen::sim::{Simulation, Start};
//! use morphogen::stream::{Record, Sink, SinkError};
//!
//! /// Counts cell records.
//! struct Cells(usize);
//! impl Sink for Cells {
//!     fn record(&mut self, r: &Record) -> Result<(), SinkError> {
//!         self.0 += usize::from(matches!(r, Record::Cell { .. }));
//!         Ok(())
//!     }
//! }
//!
//! // A croton leaf (thesis Table 4.1) on a small torus: background B and
//! // foreground F, both dividing every 10 days on average.
//! const TYPES: [CellType; 2] = [
//!     CellType { colour: [40, 105, 45], division_days: 10, initial_probability: Fx::from_ratio(7, 10) },
//!     CellType { colour: [236, 200, 48], division_days: 10, initial_probability: Fx::from_ratio(3, 10) },
//! ];
//! // α_BB 0.8, α_FF 0.5, α_BF 0.
//! let alpha = [Fx::from_ratio(8, 10), Fx::from_ratio(5, 10), Fx::ZERO, Fx::ZERO];
//! let params = Params {
//!     domain: Domain::periodic(Fx::from_int(15), Fx::from_int(12)),
//!     initial_cells: 180,
//!     types: &TYPES,
//!     adhesion: pair_table(alpha, Fx::ZERO),
//!     mutation: NO_MUTATION,
//!     radius_weight: Fx::ONE,
//!     push_weight: ORIGINAL_PUSH_WEIGHT,
//!     initial_relaxations: 40,
//!     daily_relaxations: 8,
//!     momentum: Fx::ZERO,
//!     days: 35,
//!     mask: None,
//!     anisotropy: None,
//!     frames: Frames::EveryDay,
//!     surface: None,
//! };
//! let mut m = Mosaic::new(McuStore::EMPTY);
//! m.start(&params, 7).unwrap();
//! let mut sink = Cells(0);
//! while !m.step(&mut sink).unwrap().finished() {}
//! assert!(m.len() > params.initial_cells as usize * 5);
//! assert!(sink.0 > m.len());
//! ```

mod control;
mod day;
mod division;
mod domain;
mod force;
mod grid;
mod ground;
mod mesh;
mod params;
mod relaxation;
mod scan;
mod shapes;
mod store;
mod surface;
mod terrain;

pub use control::{
    Anisotropy, ControlError, ControlVector, FIELD_LATTICE, Field, MAX_CONTROL_VECTORS, Mask,
};
pub use domain::Domain;
pub use ground::{CellSlices, Ground};
pub use mesh::{
    MAX_COORD, MAX_CROSSINGS, MAX_FACES, MAX_VERTICES, Mesh, MeshArrays, MeshError, MeshInfo,
    MeshParts, NO_FACE, Place,
};
pub use params::{
    CellType, Frames, MAX_MOMENTUM, MAX_SELF_ADHESION, MAX_TYPES, NO_MUTATION,
    ORIGINAL_PUSH_WEIGHT, Params, pair_table,
};
pub use relaxation::{Forces, Plane};
pub use shapes::{Shape, Tessellation};
pub use store::{ArrayStore, CellStore, Relax};
pub use surface::meshes::{ArrayMeshStore, MESH_FACE_LIMIT, MESH_VERTEX_LIMIT, MeshStore};
pub use surface::relaxation::{OnMesh, SurfaceForces};
pub use surface::{
    ControlMap, FIELD_LIMIT, McuMeshStore, McuSurfaceStore, MeshBuffers, MeshTerrain, Surface,
    SurfaceMesh, SurfaceMosaic, build_mesh,
};
pub use terrain::{PlaneTerrain, Push, Terrain};

/// The relaxation's kernels: one step on the plane ([`kernels::plane`])
/// or on a mesh ([`kernels::mesh`]), their grids and snapshots, and the
/// brute-force reference. Not part of the curated interface: public for
/// the benches, which time the grids against the reference, and for the
/// host's stores (`morphogen-scenario`), which run the same steps on
/// several threads; a [`Mosaic`] or [`SurfaceMosaic`] needs none of it.
#[doc(hidden)]
pub mod kernels {
    /// On the plane.
    pub mod plane {
        pub use crate::mosaic::grid::{BinRun, Grid};
        pub use crate::mosaic::relaxation::{
            Moves, Snapshot, relax, relax_naive, relax_pairs, snapshot, sorted_snapshot,
        };
        pub use crate::mosaic::store::{CELL_BYTES, bytes_per_cell_milli};
    }
    /// On a mesh.
    pub mod mesh {
        pub use crate::mosaic::surface::relaxation::{
            CubeGrid, Snapshot, relax, relax_pairs, snapshot, sorted_snapshot,
        };
    }
}

use crate::Error;
use crate::fx::Fx;
use crate::rng::KeyedRng;
use crate::sim::{Progress, Simulation, Start};
use crate::stream::Sink;
use day::Run;
use division::{Purpose, stream_id};

/// The name of the cell-store limit in [`Error::Capacity`].
pub const CELL_LIMIT: &str = "mosaic cell store (capacity of the preset's CellStore)";

/// The name of the limit in [`Error::Capacity`] when a run with momentum
/// meets a store that keeps no velocities (the MCU's [`McuStore`]).
pub const VELOCITY_LIMIT: &str =
    "mosaic velocities for momentum (the preset's CellStore keeps none; an MCU store has no room)";

/// An invalid mosaic setup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum MosaicError {
    /// A parameter is out of range; names it.
    Param(&'static str),
    /// The mask or the anisotropy field is unusable.
    Control(ControlError),
    /// The surface's mesh is unusable.
    Mesh(mesh::MeshError),
}

impl core::fmt::Display for MosaicError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MosaicError::Param(p) => write!(f, "mosaic parameter out of range: {p}"),
            MosaicError::Control(e) => write!(f, "mosaic control: {e}"),
            MosaicError::Mesh(e) => write!(f, "mosaic surface: {e}"),
        }
    }
}

impl core::error::Error for MosaicError {}

impl From<MosaicError> for Error {
    fn from(e: MosaicError) -> Error {
        Error::Mosaic(e)
    }
}

/// Checks `params` before a run.
///
/// # Errors
/// The first parameter out of range.
pub fn validate(params: &Params) -> Result<(), MosaicError> {
    let bad = |p| Err(MosaicError::Param(p));
    if !params.domain.is_valid() {
        return bad("domain size (0, 16384]");
    }
    if params.types.is_empty() || params.types.len() > MAX_TYPES {
        return bad("types (1 to MAX_TYPES)");
    }
    if params
        .types
        .iter()
        .any(|t| t.division_days == 0 || t.division_days > 1024)
    {
        return bad("division_days (1 to 1024)");
    }
    if params.radius_weight <= Fx::ZERO || params.radius_weight > Fx::from_int(16) {
        return bad("radius_weight (0, 16]");
    }
    if params.initial_cells == 0 {
        return bad("initial_cells (at least 1)");
    }
    if params.momentum < Fx::ZERO || params.momentum > MAX_MOMENTUM {
        return bad("momentum [0, 0.95]");
    }
    let n = params.types.len();
    if params.adhesion[..n]
        .iter()
        .flat_map(|row| &row[..n])
        .any(|a| *a < Fx::ZERO || *a > Fx::ONE)
        || (0..n).any(|i| params.adhesion[i][i] > MAX_SELF_ADHESION)
    {
        return bad("adhesion [0, 1], of a type with itself [0, 0.95]");
    }
    if params.mask.is_some_and(|m| !m.is_valid()) {
        return Err(MosaicError::Control(ControlError::BadMask));
    }
    Ok(())
}

/// The inline store of the MCU presets: 2 048 cells, 512 grid bins, 24 B
/// per cell (49 156 B).
pub type McuStore = ArrayStore<2048, 513>;

/// The capacity (cells) of a host preset's store: comfortably above the
/// final count of its runs (checked over seeds by the tests); a run that
/// outgrows it stops with [`crate::Error::Capacity`]. The
/// core has no heap: the big mosaics are host presets, run by the host CLI
/// on a `Vec`-backed
/// [`CellStore`] of this many cells and
/// `cells / 4 + 1` bin offsets.
#[must_use]
pub fn host_capacity(params: &Params) -> usize {
    // The largest growth of any type over the run, ×1.5 margin: a type
    // with D_T divides about days/D_T times (plus Poisson spread).
    let days = u32::from(params.days);
    let growth = params
        .types
        .iter()
        .map(|t| {
            let generations =
                (days + u32::from(t.division_days) / 2) / u32::from(t.division_days).max(1) + 1;
            1u64 << generations.min(20)
        })
        .max()
        .unwrap_or(1);
    (u64::from(params.initial_cells) * growth).min(1 << 24) as usize
}

/// The expected peak number of cells of a run of `params`: the initial
/// cells grown by the fastest type's mean doubling (2^(days / D_T)),
/// rounded up. Whether a mosaic fits an MCU's inline store is decided by
/// it ([`crate::preset::Model::fits_mcu`]); a run that outgrows its store
/// anyway stops with [`crate::Error::Capacity`].
#[must_use]
pub fn expected_peak_cells(params: &Params) -> u64 {
    let days = u64::from(params.days);
    // 2^(days/D) as Q16 through the integer part and a table of 2^(k/16).
    const FRACTION_Q16: [u64; 16] = [
        65536, 68438, 71468, 74632, 77936, 81386, 84990, 88752, 92682, 96785, 101070, 105545,
        110218, 115098, 120194, 125515,
    ];
    let growth_q16 = params
        .types
        .iter()
        .map(|t| {
            let d = u64::from(t.division_days.max(1));
            // days/D in sixteenths, rounded up.
            let sixteenths = (days * 16).div_ceil(d);
            let whole = (sixteenths / 16).min(24);
            FRACTION_Q16[(sixteenths % 16) as usize] << whole
        })
        .max()
        .unwrap_or(1 << 16);
    u64::from(params.initial_cells)
        .saturating_mul(growth_q16)
        .div_ceil(1 << 16)
}

/// A running mosaic over the cell store `S` on the terrain `T`: the plane
/// ([`PlaneTerrain`], the default) or a mesh ([`MeshTerrain`],
/// [`SurfaceMosaic`]).
///
/// `repr(C)`: the store first, at the offset where the MCU's relaxation
/// loops reach its arrays with the shortest immediates (Rust's own layout
/// put the run's counters first: croton-mcu 0.8 % more instructions).
#[derive(Debug)]
#[repr(C)]
pub struct Mosaic<'a, S: Relax<T::Ground>, T: Terrain = PlaneTerrain> {
    store: S,
    run: Run<'a>,
    terrain: T,
    divisions: [[u32; MAX_TYPES]; MAX_TYPES],
}

impl<'a, S: Relax> Mosaic<'a, S> {
    /// A mosaic on the plane over `store`, not yet started.
    pub const fn new(store: S) -> Mosaic<'a, S> {
        Mosaic::on(store, PlaneTerrain::EMPTY)
    }
}

impl<'a, S: Relax<T::Ground>, T: Terrain> Mosaic<'a, S, T> {
    /// A mosaic over `store` on `terrain`, not yet started.
    pub const fn on(store: S, terrain: T) -> Mosaic<'a, S, T> {
        Mosaic {
            store,
            run: Run::new(),
            terrain,
            divisions: [[0; MAX_TYPES]; MAX_TYPES],
        }
    }

    /// Number of cells.
    #[must_use]
    pub fn len(&self) -> usize {
        self.run.cells as usize
    }

    /// Whether there are no cells (before day 0).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.run.cells == 0
    }

    /// The cell store (for benches and tools that drive the kernels
    /// directly; the first [`Mosaic::len`] cells are live).
    pub fn store_mut(&mut self) -> &mut S {
        &mut self.store
    }

    /// The terrain (on a mesh: [`MeshTerrain::mesh`]).
    #[must_use]
    pub fn terrain(&self) -> &T {
        &self.terrain
    }

    /// The current repulsion radius (Q16 bits).
    #[must_use]
    pub fn radius(&self) -> Fx {
        Fx::from_bits(self.run.radius)
    }

    /// Where the cells are, by id (Q16 bits on the plane, a [`Place`] on
    /// a mesh).
    #[must_use]
    pub fn positions(&self) -> &[<T::Ground as Ground>::At] {
        &self.store.positions()[..self.len()]
    }

    /// The cells' types by id.
    #[must_use]
    pub fn kinds(&self) -> &[u8] {
        &self.store.kinds()[..self.len()]
    }

    /// Divisions so far, by parent type (row) and child type (column).
    #[must_use]
    pub fn divisions(&self) -> &[[u32; MAX_TYPES]; MAX_TYPES] {
        &self.divisions
    }

    /// The day last simulated (0 after the initial relaxation).
    #[must_use]
    pub fn day(&self) -> u16 {
        self.run.day
    }

    /// Checks `params` and the store and gets the terrain ready for them.
    fn prepare(&mut self, params: &Params) -> Result<(), Error> {
        validate(params)?;
        let velocities = self.store.slices().velocity.len();
        day::check_store(params, self.store.capacity(), velocities)?;
        self.terrain.prepare(params)?;
        self.divisions = [[0; MAX_TYPES]; MAX_TYPES];
        Ok(())
    }

    /// Works out r = w_r·√(area/N) for the cells there are.
    #[inline(never)]
    fn update_radius(&mut self, params: &Params) {
        self.run.radius = self.terrain.radius(params, self.run.cells);
    }

    /// Spreads the initial cells uniformly at random (day 0).
    fn place(&mut self, params: &Params) -> Result<(), Error> {
        let mut scatter = self.terrain.scatter(params);
        let cells = self.store.slices();
        cells.velocity.fill(<T::Ground as Ground>::ZERO);
        for id in 0..params.initial_cells {
            let mut rng = KeyedRng::new(self.run.seed, stream_id(Purpose::Place, 0, id));
            let at = scatter(&mut rng);
            // By the initial probabilities; the background where the mask
            // does not allow the foreground.
            let mut kind = division::initial_type(&mut rng, params.types);
            let uv = |at| self.terrain.control_uv(params, at);
            if kind != 0
                && params
                    .mask
                    .is_some_and(|m| !m.allows(&params.domain, uv(&at)))
            {
                kind = 0;
            }
            let i = id as usize;
            cells.pos[i] = at;
            cells.kind[i] = kind;
            cells.next_division[i] = division::interval(&mut rng, &params.types[kind as usize])?;
        }
        self.run.cells = params.initial_cells;
        Ok(())
    }

    /// Divides every cell whose day has come (in id order; children are
    /// appended and divide on later days only).
    fn divide(&mut self, params: &Params) -> Result<(), Error> {
        let (seed, day) = (self.run.seed, self.run.day);
        let capacity = self.store.capacity();
        let disc = self.run.radius / 200; // diameter 1 % of r
        let offspring = self.terrain.offspring(params);
        let cells = self.store.slices();
        let existing = self.run.cells as usize;
        let mut n = existing;
        for id in 0..existing {
            if cells.next_division[id] > day {
                continue;
            }
            if n >= capacity {
                return Err(Error::Capacity {
                    limit: CELL_LIMIT,
                    capacity: capacity as u32,
                });
            }
            let parent = cells.kind[id];
            let split = division::split(seed, day, id as u32, parent, params, disc)?;
            cells.pos[n] = offspring(cells.pos[id], split.offset);
            cells.kind[n] = split.child;
            if let Some(v) = cells.velocity.get_mut(n) {
                *v = <T::Ground as Ground>::ZERO; // a newborn cell has not moved
            }
            cells.next_division[n] = split.child_next;
            cells.next_division[id] = split.parent_next;
            self.divisions[parent as usize % MAX_TYPES][split.child as usize % MAX_TYPES] += 1;
            n += 1;
        }
        self.run.cells = n as u32;
        Ok(())
    }

    /// `times` relaxation steps at the current radius, with or without
    /// adhesion.
    fn relax(&mut self, params: &Params, times: u16, adhesion: bool) {
        let push = Push {
            radius: self.run.radius,
            repel: terrain::repulsion(&params.adhesion, adhesion),
            push_weight: params.push_weight.to_bits(),
            anisotropy_weight: params
                .anisotropy
                .map_or(0, |a| a.weight.clamp(Fx::ZERO, Fx::ONE).to_bits()),
            momentum: params.momentum.to_bits(),
        };
        let n = self.run.cells as usize;
        self.terrain.relax(&mut self.store, n, push, params, times);
    }

    /// The records of a streamed day between its frame's start and end.
    fn records(&mut self, sink: &mut dyn Sink) -> Result<(), Error> {
        self.terrain.records(self.run.frame, sink)?;
        let n = self.len();
        let (pos, kind) = (self.store.positions(), self.store.kinds());
        for (id, (at, k)) in pos[..n].iter().zip(&kind[..n]).enumerate() {
            sink.record(&T::cell(id as u32, *k, at))?;
        }
        Ok(())
    }
}

impl<'a, S: Relax<T::Ground>, T: Terrain> Start<'a> for Mosaic<'a, S, T> {
    type Params = Params<'a>;

    /// (Re)starts a run of `params` with `seed`, in place.
    ///
    /// # Errors
    /// Invalid parameters, an unusable mesh, or more initial cells than
    /// the store holds; the error is also kept and returned by the next
    /// [`Simulation::step`].
    fn start(&mut self, params: &'a Params<'a>, seed: u64) -> Result<(), Error> {
        self.start_run(params, seed)
    }
}

impl<S: Relax<T::Ground>, T: Terrain> Simulation for Mosaic<'_, S, T> {
    /// Step 0 places and relaxes the initial cells; step d ≥ 1 simulates
    /// day d. A step streams its day if [`Params::frames`] selects it.
    fn step(&mut self, sink: &mut dyn Sink) -> Result<Progress, Error> {
        self.step_day(sink)
    }
}

#[cfg(test)]
mod tests;
