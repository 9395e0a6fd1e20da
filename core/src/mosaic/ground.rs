//! What a mosaic's cells live on, the plane or a mesh ([`Ground`]), and
//! the arrays of a cell store borrowed for one operation ([`CellSlices`]):
//! the one face the relaxation and division kernels of both grounds
//! work through (MClone thesis Sec. 3.2.1: cells are points with a type).

use core::fmt::Debug;

/// What a mosaic's cells live on — the plane with its grid of bins, or a
/// mesh with its grid of cubes — and one relaxation step there.
pub trait Ground: Sized {
    /// Where a cell is.
    type At: Copy + Debug;
    /// A point as the neighbour search reads it, and a move (Q16).
    type Point: Copy + Debug;
    /// What one relaxation step needs besides the cells: the radius, the
    /// repulsions and weights, the grid or mesh.
    type Forces<'f>: Debug;
    /// An empty [`Ground::At`].
    const NO_PLACE: Self::At;
    /// The zero [`Ground::Point`].
    const ZERO: Self::Point;
    /// The ground's name (in a store's `Debug`).
    const NAME: &'static str;

    /// One relaxation step over the first `n` cells, one cell after
    /// another.
    fn relax_step(cells: &mut CellSlices<'_, Self>, n: usize, forces: &Self::Forces<'_>);
}

/// The arrays of a cell store, borrowed for one operation.
#[derive(Debug)]
pub struct CellSlices<'a, G: Ground> {
    /// Where each cell is.
    pub pos: &'a mut [G::At],
    /// Type index of each cell.
    pub kind: &'a mut [u8],
    /// The day on which each cell next divides.
    pub next_division: &'a mut [u16],
    /// Cell indices sorted by grid bin (the counting sort's output).
    pub order: &'a mut [u32],
    /// The cells' points in grid-bin order during a relaxation step
    /// (scratch).
    pub sorted: &'a mut [G::Point],
    /// Grid bin offsets into `order` (`bins.len() − 1` bins at most).
    pub bins: &'a mut [u32],
    /// The last move of each cell, Q16 bits; empty in a store without
    /// momentum.
    pub velocity: &'a mut [G::Point],
}
