//! A uniform grid for the neighbour search of the relaxation (MClone
//! thesis, Sec. 3.2.1.1: the neighbours within the repulsion radius): cells are
//! counting-sorted into square-ish bins at least one repulsion radius wide,
//! so every neighbour of a cell lies in its bin or the 8 around it. O(N)
//! per build, no allocation: the bins and the permutation live in the
//! caller's [`CellStore`](super::store::CellStore).

use super::domain::Domain;

/// Consecutive bins `first..end` along one axis whose cells all lie
/// `shift` (Q16 bits) away from where they are stored ([`Grid::span`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BinRun {
    /// The first bin.
    pub first: u32,
    /// One past the last bin.
    pub end: u32,
    /// What to add to the cells' coordinates: 0, or ±size across the wrap.
    pub shift: i32,
}

/// Bin layout for one relaxation step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Bins along u.
    pub cols: u32,
    /// Bins along v.
    pub rows: u32,
    /// `⌊2^32·cols/size_u⌋` and the same for v: bin = `(p·scale) >> 32`.
    scale: [u64; 2],
    periodic: [bool; 2],
}

impl Grid {
    /// The finest grid whose bins are wider than `radius` (Q16 bits) with at
    /// most `max_bins` bins.
    #[must_use]
    pub fn plan(domain: &Domain, radius: i32, max_bins: usize) -> Grid {
        let size = [domain.size[0].to_bits(), domain.size[1].to_bits()];
        // A margin of 1/64 + 1 LSB keeps every bin wider than the radius
        // despite the truncated scale factors below.
        let side = i64::from(radius.max(1)) + i64::from(radius.max(1) >> 6) + 1;
        let count = |s: i32| (i64::from(s) / side).clamp(1, 1 << 15) as u32;
        let (mut cols, mut rows) = (count(size[0]), count(size[1]));
        let max_bins = max_bins.max(1) as u64;
        while u64::from(cols) * u64::from(rows) > max_bins {
            if cols >= rows {
                cols -= 1;
            } else {
                rows -= 1;
            }
        }
        let scale = |n: u32, s: i32| (u64::from(n) << 32) / (s.max(1) as u64);
        Grid {
            cols,
            rows,
            scale: [scale(cols, size[0]), scale(rows, size[1])],
            periodic: domain.periodic,
        }
    }

    /// Number of bins.
    #[must_use]
    pub const fn bins(&self) -> usize {
        self.cols as usize * self.rows as usize
    }

    /// Column and row of a position.
    #[inline]
    #[must_use]
    pub fn cell_of(&self, p: [i32; 2]) -> (u32, u32) {
        // p ∈ [0, size): (p·scale) >> 32 < cols; the min guards rounding.
        let c = ((p[0].max(0) as u64 * self.scale[0]) >> 32) as u32;
        let r = ((p[1].max(0) as u64 * self.scale[1]) >> 32) as u32;
        (c.min(self.cols - 1), r.min(self.rows - 1))
    }

    /// Bin index of a position.
    #[inline]
    #[must_use]
    pub fn bin_of(&self, p: [i32; 2]) -> usize {
        let (c, r) = self.cell_of(p);
        r as usize * self.cols as usize + c as usize
    }

    /// Counting sort of `pos` into `order`, and the positions gathered in
    /// that order into `sorted`; afterwards the cells of bin `b` are
    /// `order[bins[b]..bins[b + 1]]`, in increasing index order. `bins`
    /// needs `self.bins() + 1` entries, `order` and `sorted` `pos.len()`.
    /// Each cell's bin is computed once: `order` holds it until the cells
    /// are placed, `sorted` holds the placed indices until the gather. A
    /// computer that keeps its cells in grid order between steps runs the
    /// first two phases, [`Grid::bin_cells`] and [`Grid::place`], itself.
    pub fn build(
        &self,
        pos: &[[i32; 2]],
        order: &mut [u32],
        bins: &mut [u32],
        sorted: &mut [[i32; 2]],
    ) {
        self.bin_cells(pos, order);
        self.place(order, bins, sorted);
        Grid::gather(pos, order, sorted);
    }

    /// The first phase of [`Grid::build`]: the bin of each position of
    /// `pos` into `bins_of` (as many), in any slices of them.
    pub fn bin_cells(&self, pos: &[[i32; 2]], bins_of: &mut [u32]) {
        for (b, p) in bins_of.iter_mut().zip(pos) {
            // bin_of < bins() ≤ u32::MAX (cols, rows ≤ 2^15).
            *b = self.bin_of(*p) as u32;
        }
    }

    /// The second phase of [`Grid::build`]: from the bin of each cell in
    /// `order` ([`Grid::bin_cells`]), each bin's first slot into `bins`
    /// (the cells' number after the last) and each slot's cell index into
    /// `sorted[slot][0]`, the cells of a bin in index order.
    pub fn place(&self, order: &[u32], bins: &mut [u32], sorted: &mut [[i32; 2]]) {
        let nb = self.bins();
        let Some(bins) = bins.get_mut(..=nb) else {
            return;
        };
        bins.fill(0);
        for &b in order {
            if let Some(count) = bins.get_mut(b as usize) {
                *count += 1;
            }
        }
        let mut sum = 0u32;
        for b in bins.iter_mut().take(nb) {
            sum += *b;
            *b = sum; // end of the bin
        }
        bins[nb] = sum;
        for (i, &b) in order.iter().enumerate().rev() {
            if let Some(end) = bins.get_mut(b as usize) {
                *end -= 1; // ends as the start of the bin
                if let Some(slot) = sorted.get_mut(*end as usize) {
                    slot[0] = i as i32; // i < pos.len() ≤ u32::MAX: lossless
                }
            }
        }
    }

    /// The last phase of [`Grid::build`]: each slot's cell index from
    /// `sorted[slot][0]` ([`Grid::place`]) into `order`, and that cell's
    /// position from `pos` into `sorted`.
    fn gather(pos: &[[i32; 2]], order: &mut [u32], sorted: &mut [[i32; 2]]) {
        for (i, slot) in order.iter_mut().zip(sorted.iter_mut()) {
            *i = slot[0] as u32;
            *slot = pos.get(*i as usize).copied().unwrap_or_default();
        }
    }

    /// Whether the shifts of [`Grid::span`] give every displacement: not
    /// when a periodic axis has fewer than 3 bins, where one bin can hold
    /// neighbours on both sides of a cell (then `span` lists every bin of
    /// that axis and displacements need [`Domain::delta`]).
    #[must_use]
    pub fn shifts_exact(&self) -> bool {
        (!self.periodic[0] || self.cols >= 3) && (!self.periodic[1] || self.rows >= 3)
    }

    /// The bins along `axis` that hold every point within `radius` of
    /// coordinate `x` (periodic where the domain wraps), as at most two runs
    /// of consecutive bins `first..end`, each with the shift that takes its
    /// cells next to `x` (`−size` or `+size` for the run reached across the
    /// wrap, else 0), so that `x − (q + shift)` is the shortest displacement
    /// from any q within `radius` ([`Domain::delta`] without its branches).
    /// Returns how many runs are used. Needs `2·radius` below the domain
    /// size and bins wider than `radius`. `EXACT`: the caller knows
    /// [`Grid::shifts_exact`] holds (one test fewer per cell on 64-bit
    /// targets).
    #[inline]
    #[must_use]
    pub fn span<const EXACT: bool>(
        &self,
        axis: usize,
        x: i32,
        radius: i32,
        size: i32,
    ) -> ([BinRun; 2], usize) {
        let n = if axis == 0 { self.cols } else { self.rows };
        let run = |first, end, shift| BinRun { first, end, shift };
        // One copy for both on a 32-bit MCU, where flash is short.
        let exact = EXACT && cfg!(target_pointer_width = "64");
        if !exact && self.periodic[axis] && n < 3 {
            // Every bin, unshifted: see `Grid::shifts_exact`.
            return ([run(0, n, 0), run(0, 0, 0)], 1);
        }
        let at = |p: i32| {
            let c = ((p as u64 * self.scale[axis]) >> 32) as u32;
            c.min(n - 1)
        };
        if !self.periodic[axis] {
            let (lo, hi) = (at((x - radius).max(0)), at((x + radius).min(size - 1)));
            return ([run(lo, hi + 1, 0), run(0, 0, 0)], 1);
        }
        // x ∈ [0, size) and 2·radius < size ≤ 2^30: no sum below overflows.
        let (lo, shift) = if x < radius {
            (at(x - radius + size), -size)
        } else {
            (at(x - radius), 0)
        };
        let hi = if x >= size - radius {
            at(x + radius - size)
        } else {
            at(x + radius)
        };
        if hi >= lo {
            ([run(lo, hi + 1, shift), run(0, 0, 0)], 1)
        } else {
            // Across the wrap: the bins from 0 on lie one size further on.
            ([run(lo, n, shift), run(0, hi + 1, shift + size)], 2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fx::Fx;

    #[test]
    fn counting_sort_groups_cells_by_bin() {
        let d = Domain::periodic(Fx::from_int(10), Fx::from_int(10));
        let g = Grid::plan(&d, Fx::from_int(3).to_bits(), 100);
        assert_eq!((g.cols, g.rows), (3, 3));
        let pos = [[1, 1], [9 << 16, 9 << 16], [2 << 16, 1], [5 << 16, 5 << 16]];
        let mut order = [0u32; 4];
        let mut bins = [0u32; 10];
        let mut sorted = [[0; 2]; 4];
        g.build(&pos, &mut order, &mut bins, &mut sorted);
        assert_eq!(order, [0, 2, 3, 1]);
        assert_eq!(sorted, [pos[0], pos[2], pos[3], pos[1]]);
        assert_eq!(bins, [0, 2, 2, 2, 2, 3, 3, 3, 3, 4]);
        // Within 3 of u = 1 on a periodic axis: column 2 reached across the
        // wrap (its cells 10 further back), then columns 0 and 1.
        let run = |first, end, shift| BinRun { first, end, shift };
        let (one, three, ten) = (1 << 16, 3 << 16, 10 << 16);
        assert_eq!(
            g.span::<true>(0, one, three, ten),
            ([run(2, 3, -ten), run(0, 2, 0)], 2)
        );
        let w = Grid::plan(
            &Domain::walled(Fx::from_int(10), Fx::from_int(10)),
            3 << 16,
            4,
        );
        assert_eq!((w.cols, w.rows), (2, 2));
        // A walled axis stops at the wall: column 0 alone.
        assert_eq!(w.span::<true>(0, one, three, ten).1, 1);
        assert_eq!(w.span::<true>(0, one, three, ten).0[0], run(0, 1, 0));
    }
}
