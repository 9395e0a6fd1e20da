//! The host's cell store ([`VecStore`]): a mosaic's cells on the heap,
//! their number chosen at run time, relaxed on all cores (rayon), each pair
//! of neighbours found once (MClone thesis Sec. 3.2.1). One store for both
//! grounds, the plane ([`VecStore`]) and a mesh ([`VecStore<OnMesh>`]):
//! what differs is a ground's step over the cells carried from one step of
//! a day to the next ([`AllCores`]: `plane`, `mesh`), built from the
//! shares of `shares`.

mod mesh;
mod plane;
mod shares;

use std::fmt::Debug;

#[cfg(doc)]
use morphogen::mosaic::OnMesh;
use morphogen::mosaic::{CellSlices, CellStore, Ground, Plane, Relax};

use shares::RELAX_CHUNK;

/// A ground whose cells relax on all cores: the one-thread step for a few
/// cells, and the step over the cells carried in grid order between the
/// steps of a day.
pub trait AllCores: Ground + Debug {
    /// The pushes on one cell summed over its neighbours (64-bit, an axis
    /// each).
    type Sum: Copy + Debug + Default + Send + Sync;
    /// What the carried step keeps between calls besides each cell's
    /// index, place and last move.
    type Scratch: Debug + Default + Send;

    /// Grid bin offsets for a store of `cells` cells.
    fn bins(cells: usize) -> usize;

    /// Whether the cells move with momentum (their last moves carried).
    fn momentum(forces: &Self::Forces<'_>) -> bool;

    /// One step over the first `n` cells in index order, on one thread,
    /// each pair once (`sums`: at least `n`).
    fn relax_pairs(
        cells: &mut CellSlices<'_, Self>,
        n: usize,
        forces: &Self::Forces<'_>,
        sums: &mut [Self::Sum],
    );

    /// One step over the `n` carried cells: the grid built from their
    /// order, each pair of neighbours once into the slots' sums (in
    /// shares on several threads), the cells moved and carried on in the
    /// new slot order, whose cell indices it leaves in `cells.order`.
    fn relax_carried(
        cells: &mut CellSlices<'_, Self>,
        carried: &mut Carried<Self>,
        sums: &mut [Self::Sum],
        forces: &Self::Forces<'_>,
        momentum: bool,
    );
}

/// A cell store on the heap, its capacity chosen at run time, relaxed on
/// all cores, the cells kept in grid order between the steps of a day.
#[derive(Debug)]
pub struct VecStore<G: AllCores = Plane> {
    cells: Cells<G>,
    carried: Carried<G>,
    /// The sums of pair pushes of a relaxation step, one a grid slot,
    /// grown on first use.
    sums: Vec<G::Sum>,
}

/// The arrays of a [`VecStore`].
#[derive(Debug)]
struct Cells<G: Ground> {
    pos: Vec<G::At>,
    kind: Vec<u8>,
    next_division: Vec<u16>,
    order: Vec<u32>,
    sorted: Vec<G::Point>,
    bins: Vec<u32>,
    velocity: Vec<G::Point>,
}

impl<G: Ground> Cells<G> {
    fn slices(&mut self) -> CellSlices<'_, G> {
        CellSlices {
            pos: &mut self.pos,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.sorted,
            bins: &mut self.bins,
            velocity: &mut self.velocity,
        }
    }
}

/// The cells between the relaxation steps of a day, in the grid order of
/// the last step: each step's counting sort then starts from cells that
/// are almost in place, and the cells move in slot order, so that every
/// pass reads and writes its arrays in sequence. (Moving them in index
/// order read each one's sum through the grid's permutation: on two
/// cores that took as long as the whole move on one.) They go back to
/// index order after the day's last step.
#[derive(Debug)]
pub struct Carried<G: AllCores> {
    /// Each cell's index.
    id: Vec<u32>,
    /// Each cell's place.
    at: Vec<G::At>,
    /// Each cell's last move (with momentum).
    velocity: Vec<G::Point>,
    /// The ground's own.
    scratch: G::Scratch,
}

impl<G: AllCores> Default for Carried<G> {
    fn default() -> Self {
        Carried {
            id: Vec::new(),
            at: Vec::new(),
            velocity: Vec::new(),
            scratch: G::Scratch::default(),
        }
    }
}

impl<G: AllCores> Carried<G> {
    /// The first `n` cells of `cells` taken in index order (their last
    /// moves too with `momentum`); `id` as long as the cells' `order`,
    /// which each step swaps it with.
    fn load(&mut self, cells: &Cells<G>, n: usize, momentum: bool) {
        if self.at.len() < n {
            self.at.resize(n, G::NO_PLACE);
            self.velocity.resize(n, G::ZERO);
        }
        self.id.resize(cells.order.len(), 0);
        self.at[..n].copy_from_slice(&cells.pos[..n]);
        if momentum {
            self.velocity[..n].copy_from_slice(&cells.velocity[..n]);
        }
        for (k, id) in (0u32..).zip(&mut self.id[..n]) {
            *id = k;
        }
    }

    /// The `n` carried cells put back in index order.
    fn unload(&self, cells: &mut Cells<G>, n: usize, momentum: bool) {
        for ((&i, at), v) in self.id[..n].iter().zip(&self.at).zip(&self.velocity) {
            let i = i as usize;
            cells.pos[i] = *at;
            if momentum {
                cells.velocity[i] = *v;
            }
        }
    }
}

impl<G: AllCores> VecStore<G> {
    /// A store of `cells` cells (with their last moves, for momentum) and
    /// the ground's grid bin offsets ([`AllCores::bins`]).
    #[must_use]
    pub fn new(cells: usize) -> VecStore<G> {
        VecStore {
            cells: Cells {
                pos: vec![G::NO_PLACE; cells],
                kind: vec![0; cells],
                next_division: vec![0; cells],
                order: vec![0; cells],
                sorted: vec![G::ZERO; cells],
                bins: vec![0; G::bins(cells)],
                velocity: vec![G::ZERO; cells],
            },
            carried: Carried::default(),
            sums: Vec::new(),
        }
    }
}

impl<G: AllCores> CellStore<G> for VecStore<G> {
    fn capacity(&self) -> usize {
        self.cells.pos.len()
    }

    fn slices(&mut self) -> CellSlices<'_, G> {
        self.cells.slices()
    }

    fn positions(&self) -> &[G::At] {
        &self.cells.pos
    }

    fn kinds(&self) -> &[u8] {
        &self.cells.kind
    }
}

impl<G: AllCores> Relax<G> for VecStore<G> {
    /// Each pair of neighbours once, the cells kept in the grid order of
    /// the last step from one step to the next (so that every pass reads
    /// and writes in sequence) and put back in index order after the
    /// last; on several threads the grid's per-cell phases, the pairs
    /// (each thread a share of the grid slots into that share of the
    /// sums, the few pushes past its end kept aside and added after) and
    /// the moves run side by side. Integer sums: the same bits in any
    /// order of the cells and on any number of threads.
    fn relax(&mut self, n: usize, forces: &G::Forces<'_>, times: u16) {
        if self.sums.len() < n {
            self.sums.resize(n, G::Sum::default());
        }
        if n < RELAX_CHUNK {
            for _ in 0..times {
                G::relax_pairs(&mut self.cells.slices(), n, forces, &mut self.sums);
            }
            return;
        }
        let momentum = G::momentum(forces) && self.cells.velocity.len() >= n;
        self.carried.load(&self.cells, n, momentum);
        for _ in 0..times {
            let sums = &mut self.sums[..n];
            G::relax_carried(
                &mut self.cells.slices(),
                &mut self.carried,
                sums,
                forces,
                momentum,
            );
            // The slots' cell indices are the carried order of the next step.
            std::mem::swap(&mut self.carried.id, &mut self.cells.order);
        }
        self.carried.unload(&mut self.cells, n, momentum);
    }
}
