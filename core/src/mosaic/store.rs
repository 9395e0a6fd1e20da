//! Fixed-capacity cell storage: structure-of-arrays slices that the
//! relaxation and division kernels borrow (MClone cells are points with a
//! type; thesis Sec. 3.2.1).
//!
//! Per cell: position (2 × i32, Q16 = [`Fx`](crate::fx::Fx) bits) 8 B, type
//! 1 B, next division day 2 B, grid order (counting-sort permutation) 4 B,
//! push scratch (2 × i32, every force is computed before any cell moves) 8 B
//! = 23 B, plus the grid's bin offsets (4 B each, a quarter as many bins as
//! cells in the presets) = **24 B per cell**. A store may also keep each
//! cell's last move (2 × i32) for the heavy-ball relaxation
//! ([`Params::momentum`](super::Params::momentum)); [`ArrayStore`] does
//! not, to stay within an MCU's RAM.

/// The arrays of a cell store, borrowed for one operation.
#[derive(Debug)]
pub struct CellSlices<'a> {
    /// Positions `(u, v)` as Q16 bits.
    pub pos: &'a mut [[i32; 2]],
    /// Type index of each cell.
    pub kind: &'a mut [u8],
    /// The day on which each cell next divides.
    pub next_division: &'a mut [u16],
    /// Cell indices sorted by grid bin (the counting sort's output).
    pub order: &'a mut [u32],
    /// Displacement of each cell in the current relaxation, Q16 bits.
    pub push: &'a mut [[i32; 2]],
    /// Grid bin offsets into `order` (`bins.len() − 1` bins at most).
    pub bins: &'a mut [u32],
    /// The last move of each cell, Q16 bits; empty in a store without
    /// momentum.
    pub velocity: &'a mut [[i32; 2]],
}

/// Storage for cells: capacity is fixed when the store is made.
pub trait CellStore {
    /// The largest number of cells.
    fn capacity(&self) -> usize;
    /// Borrows every array.
    fn slices(&mut self) -> CellSlices<'_>;
    /// The positions (Q16 bits), all `capacity` slots.
    fn positions(&self) -> &[[i32; 2]];
    /// The types, all `capacity` slots.
    fn kinds(&self) -> &[u8];
}

/// Bytes of RAM per cell for a store of `cells` cells and `bins` bin offsets
/// (the figure quoted in the benches: 23 B per cell plus 4 B per bin).
#[must_use]
pub const fn bytes_per_cell_milli(cells: usize, bins: usize) -> usize {
    (cells * CELL_BYTES + bins * 4) * 1000 / cells
}

/// Bytes per cell held in the per-cell arrays.
pub const CELL_BYTES: usize = 8 + 1 + 2 + 4 + 8;

/// A store held inline: `N` cells and `G` grid bin offsets (`G − 1` bins);
/// it lives in a `static` on the MCU.
pub struct ArrayStore<const N: usize, const G: usize> {
    pos: [[i32; 2]; N],
    kind: [u8; N],
    next_division: [u16; N],
    order: [u32; N],
    push: [[i32; 2]; N],
    bins: [u32; G],
}

impl<const N: usize, const G: usize> ArrayStore<N, G> {
    /// The cells it holds.
    pub const CAPACITY: usize = N;

    /// An empty store (all zeros, `const` so that it can be written in place).
    pub const EMPTY: Self = ArrayStore {
        pos: [[0; 2]; N],
        kind: [0; N],
        next_division: [0; N],
        order: [0; N],
        push: [[0; 2]; N],
        bins: [0; G],
    };
}

impl<const N: usize, const G: usize> core::fmt::Debug for ArrayStore<N, G> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "ArrayStore<{N}, {G}>")
    }
}

impl<const N: usize, const G: usize> CellStore for ArrayStore<N, G> {
    fn capacity(&self) -> usize {
        N
    }

    fn slices(&mut self) -> CellSlices<'_> {
        CellSlices {
            pos: &mut self.pos,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            push: &mut self.push,
            bins: &mut self.bins,
            velocity: &mut [],
        }
    }

    fn positions(&self) -> &[[i32; 2]] {
        &self.pos
    }

    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn array_store_is_24_bytes_per_cell() {
        assert_eq!(
            core::mem::size_of::<ArrayStore<2048, 513>>(),
            2048 * 23 + 513 * 4
        );
        assert!(bytes_per_cell_milli(2048, 513) <= 24_010);
        let mut s = ArrayStore::<4, 2>::EMPTY;
        assert_eq!(s.capacity(), 4);
        assert_eq!(s.slices().bins.len(), 2);
    }
}
