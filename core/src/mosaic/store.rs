//! Fixed-capacity cell storage, one for the plane and for a mesh:
//! structure-of-arrays slices that the relaxation and division kernels
//! borrow (MClone cells are points with a type; thesis Sec. 3.2.1). The
//! [`Ground`] says what a cell's place is there and how one relaxation
//! step runs on it.
//!
//! Per cell: where it is ([`Ground::At`]: a point of the plane, 2 × i32
//! Q16 = [`Fx`](crate::fx::Fx) bits, 8 B; a [`Place`](super::mesh::Place)
//! on a mesh, 16 B), type 1 B, next division day 2 B, grid order
//! (counting-sort permutation) 4 B, the points in grid order (scratch,
//! every force is computed before any cell moves; 8 B, 12 B on a mesh),
//! plus the grid's bin offsets (4 B each, a quarter as many bins as cells
//! in the plane's presets): **24 B per cell** on the plane, 35 B on a
//! mesh. A store may also keep each cell's last move for the heavy-ball
//! relaxation ([`Params::momentum`](super::Params::momentum));
//! [`ArrayStore`] does not, to stay within an MCU's RAM.

use core::fmt::Debug;

use super::ground::{CellSlices, Ground};
use super::relaxation::Plane;

/// Storage for cells on the ground `G`: capacity is fixed when the store
/// is made.
pub trait CellStore<G: Ground = Plane> {
    /// The largest number of cells.
    fn capacity(&self) -> usize;
    /// Borrows every array.
    fn slices(&mut self) -> CellSlices<'_, G>;
    /// Where the cells are, all `capacity` slots.
    fn positions(&self) -> &[G::At];
    /// The types, all `capacity` slots.
    fn kinds(&self) -> &[u8];
}

/// How a cell store runs relaxation steps: one cell after another (the
/// default, [`Ground::relax_step`]), or, on a computer, side by side on
/// several threads through the ground's snapshot, with the same result.
pub trait Relax<G: Ground = Plane>: CellStore<G> {
    /// `times` relaxation steps in a row over the first `n` cells: a day's
    /// ρ_s ([`Params::daily_relaxations`](super::Params)) or the initial
    /// ones. A store may keep the cells in an order of its own between
    /// them, as long as each cell ends where the steps one after another
    /// put it.
    fn relax(&mut self, n: usize, forces: &G::Forces<'_>, times: u16) {
        for _ in 0..times {
            G::relax_step(&mut self.slices(), n, forces);
        }
    }
}

/// Bytes of RAM per cell for a store of `cells` cells and `bins` bin offsets
/// on the plane (the figure quoted in the benches: 23 B per cell plus 4 B
/// per bin).
#[must_use]
pub const fn bytes_per_cell_milli(cells: usize, bins: usize) -> usize {
    (cells * CELL_BYTES + bins * 4) * 1000 / cells
}

/// Bytes per cell held in the per-cell arrays on the plane.
pub const CELL_BYTES: usize = 8 + 1 + 2 + 4 + 8;

/// A store held inline: `N` cells and `B` grid bin offsets (`B − 1`
/// bins) on the ground `G`; it lives in a `static` on the MCU.
pub struct ArrayStore<const N: usize, const B: usize, G: Ground = Plane> {
    pos: [G::At; N],
    kind: [u8; N],
    next_division: [u16; N],
    order: [u32; N],
    sorted: [G::Point; N],
    bins: [u32; B],
}

impl<const N: usize, const B: usize, G: Ground> ArrayStore<N, B, G> {
    /// The cells it holds.
    pub const CAPACITY: usize = N;

    /// An empty store (all zeros, `const` so that it can be written in place).
    pub const EMPTY: Self = ArrayStore {
        pos: [G::NO_PLACE; N],
        kind: [0; N],
        next_division: [0; N],
        order: [0; N],
        sorted: [G::ZERO; N],
        bins: [0; B],
    };
}

impl<const N: usize, const B: usize, G: Ground> Debug for ArrayStore<N, B, G> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "ArrayStore<{N}, {B}, {}>", G::NAME)
    }
}

impl<const N: usize, const B: usize, G: Ground> CellStore<G> for ArrayStore<N, B, G> {
    fn capacity(&self) -> usize {
        N
    }

    fn slices(&mut self) -> CellSlices<'_, G> {
        CellSlices {
            pos: &mut self.pos,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.sorted,
            bins: &mut self.bins,
            velocity: &mut [],
        }
    }

    fn positions(&self) -> &[G::At] {
        &self.pos
    }

    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}

impl<const N: usize, const B: usize, G: Ground> Relax<G> for ArrayStore<N, B, G> {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mosaic::OnMesh;

    #[test]
    fn array_store_is_24_bytes_per_cell_on_the_plane_and_35_on_a_mesh() {
        assert_eq!(
            core::mem::size_of::<ArrayStore<2048, 513>>(),
            2048 * 23 + 513 * 4
        );
        assert!(bytes_per_cell_milli(2048, 513) <= 24_010);
        assert_eq!(
            core::mem::size_of::<ArrayStore<1024, 257, OnMesh>>(),
            1024 * 35 + 257 * 4
        );
        let mut s = <ArrayStore<4, 2>>::EMPTY;
        assert_eq!(CellStore::<Plane>::capacity(&s), 4);
        assert_eq!(s.slices().bins.len(), 2);
    }
}
