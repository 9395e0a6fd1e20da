//! Fixed-capacity cell storage for surface mosaics: per cell a [`Place`]
//! (face 4 B, point 12 B), type 1 B, next division day 2 B, grid order
//! 4 B, the sorted point scratch 12 B = 35 B, plus the cube grid's bucket
//! offsets (4 B each) and, with momentum, the last move (12 B).

use crate::mosaic::mesh::Place;

/// The arrays of a surface cell store, borrowed for one operation.
#[derive(Debug)]
pub struct SurfaceSlices<'a> {
    /// Where each cell is.
    pub place: &'a mut [Place],
    /// Type index of each cell.
    pub kind: &'a mut [u8],
    /// The day on which each cell next divides.
    pub next_division: &'a mut [u16],
    /// Cell indices sorted by grid bucket.
    pub order: &'a mut [u32],
    /// The points in bucket order (scratch).
    pub sorted: &'a mut [[i32; 3]],
    /// Bucket offsets into `order` (`buckets.len() − 1` buckets).
    pub buckets: &'a mut [u32],
    /// The last move of each cell (Q16); empty in a store without momentum.
    pub velocity: &'a mut [[i32; 3]],
}

/// Storage for the cells of a surface mosaic.
pub trait SurfaceStore {
    /// The largest number of cells.
    fn capacity(&self) -> usize;
    /// Borrows every array.
    fn slices(&mut self) -> SurfaceSlices<'_>;
    /// The places, all `capacity` slots.
    fn places(&self) -> &[Place];
    /// The types, all `capacity` slots.
    fn kinds(&self) -> &[u8];
}

/// A surface store held inline: `N` cells and `B − 1` grid buckets, no
/// velocities (no momentum).
pub struct ArraySurfaceStore<const N: usize, const B: usize> {
    place: [Place; N],
    kind: [u8; N],
    next_division: [u16; N],
    order: [u32; N],
    sorted: [[i32; 3]; N],
    buckets: [u32; B],
}

impl<const N: usize, const B: usize> ArraySurfaceStore<N, B> {
    /// The cells it holds.
    pub const CAPACITY: usize = N;

    /// An empty store (`const`, so that it can be written in place).
    pub const EMPTY: Self = ArraySurfaceStore {
        place: [Place { face: 0, p: [0; 3] }; N],
        kind: [0; N],
        next_division: [0; N],
        order: [0; N],
        sorted: [[0; 3]; N],
        buckets: [0; B],
    };
}

impl<const N: usize, const B: usize> core::fmt::Debug for ArraySurfaceStore<N, B> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "ArraySurfaceStore<{N}, {B}>")
    }
}

impl<const N: usize, const B: usize> SurfaceStore for ArraySurfaceStore<N, B> {
    fn capacity(&self) -> usize {
        N
    }

    fn slices(&mut self) -> SurfaceSlices<'_> {
        SurfaceSlices {
            place: &mut self.place,
            kind: &mut self.kind,
            next_division: &mut self.next_division,
            order: &mut self.order,
            sorted: &mut self.sorted,
            buckets: &mut self.buckets,
            velocity: &mut [],
        }
    }

    fn places(&self) -> &[Place] {
        &self.place
    }

    fn kinds(&self) -> &[u8] {
        &self.kind
    }
}
