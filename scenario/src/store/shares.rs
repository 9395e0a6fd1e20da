//! Work shared out among threads: a step's pair sums in shares of the
//! grid slots, and the counting sort of cells into bins in parts side by
//! side.

use std::ops::Range;

use rayon::prelude::*;

/// Cells a thread takes at a time: small enough to share out a 2 000-cell
/// step, large enough that handing out chunks costs little. Fewer cells
/// than this relax in index order, a step at a time.
pub(super) const RELAX_CHUNK: usize = 512;

/// Shares of the grid slots per thread when threads find pairs side by
/// side: more than one, so that a thread done early takes another.
const SHARES_PER_THREAD: usize = 4;

/// The pushes (`D` axes) of every pair of neighbours summed into `sums`,
/// one a grid slot, on all threads: each takes shares of the slots with
/// their part of the sums (`pair_sums(slots, part, past)`, the pushes on
/// slots past a share's end put in `past`), which are added after.
pub(super) fn sum_in_shares<const D: usize>(
    sums: &mut [[i64; D]],
    pair_sums: impl Fn(Range<usize>, &mut [[i64; D]], &mut Vec<(usize, [i64; D])>) + Sync,
) {
    // One thread: one share, all the slots in one pass (nothing beyond).
    let shares = match rayon::current_num_threads() {
        1 => 1,
        threads => threads * SHARES_PER_THREAD,
    };
    let share = sums.len().div_ceil(shares).max(1);
    let past: Vec<Vec<(usize, [i64; D])>> = sums
        .par_chunks_mut(share)
        .enumerate()
        .map(|(part, sums)| {
            sums.fill([0; D]);
            let mut past = Vec::new();
            let first = part * share;
            pair_sums(first..first + sums.len(), sums, &mut past);
            past
        })
        .collect();
    for (slot, push) in past.into_iter().flatten() {
        if let Some(sum) = sums.get_mut(slot) {
            for (s, p) in sum.iter_mut().zip(push) {
                *s += p;
            }
        }
    }
}

/// The counting sort of [`Grid::place`] (each bin's first slot into
/// `bins`, the cells' number after the last; each slot's cell, by
/// `put(slot, cell)`, into `slots`) of cells nearly in bin order (carried
/// from the last step) in `parts` parts side by side: each part takes a
/// range of the `nb` bins, split where the cells' order splits evenly, and
/// the range of slots they fill. Each part reads every cell's bin
/// (`bin_of`) twice, to count and to place those in its bins (in the
/// cells' order, as `Grid::place`: the same slots), and writes only its
/// own bins and slots.
pub(super) fn place_in_parts<T: Send>(
    parts: usize,
    nb: usize,
    bin_of: &[u32],
    bins: &mut [u32],
    slots: &mut [T],
    put: impl Fn(&mut T, u32) + Sync,
) {
    let n = bin_of.len();
    let Some(bins) = bins.get_mut(..=nb) else {
        return;
    };
    bins[nb] = n as u32;
    // Where the bin ranges split: the bins of evenly spaced cells.
    let mut splits: Vec<usize> = (1..parts)
        .map(|k| (bin_of[k * n / parts] as usize).min(nb))
        .collect();
    splits.insert(0, 0);
    splits.push(nb);
    for k in 1..splits.len() {
        splits[k] = splits[k].max(splits[k - 1]);
    }
    let mut ranges: Vec<(usize, &mut [u32])> = Vec::with_capacity(parts);
    let mut rest = &mut bins[..nb];
    for w in splits.windows(2) {
        let (part, tail) = rest.split_at_mut(w[1] - w[0]);
        ranges.push((w[0], part));
        rest = tail;
    }
    // Each range's cells, counted into its bins.
    let counts: Vec<u32> = ranges
        .par_iter_mut()
        .map(|(first, bins)| {
            bins.fill(0);
            let mut count = 0;
            for &b in bin_of {
                if let Some(c) = (b as usize)
                    .checked_sub(*first)
                    .and_then(|k| bins.get_mut(k))
                {
                    *c += 1;
                    count += 1;
                }
            }
            count
        })
        .collect();
    // Each range's slots, then its cells placed into them.
    let mut parts_of_sorted = Vec::with_capacity(parts);
    let mut rest = slots;
    for &count in &counts {
        let (part, tail) = rest.split_at_mut(count as usize);
        parts_of_sorted.push(part);
        rest = tail;
    }
    let mut start = 0u32;
    let starts: Vec<u32> = counts
        .iter()
        .map(|c| {
            start += c;
            start - c
        })
        .collect();
    ranges
        .into_par_iter()
        .zip(parts_of_sorted)
        .zip(starts)
        .for_each(|(((first, bins), sorted), start)| {
            let mut end = start;
            for b in bins.iter_mut() {
                end += *b;
                *b = end; // end of the bin
            }
            for (i, &b) in bin_of.iter().enumerate().rev() {
                if let Some(end) = (b as usize)
                    .checked_sub(first)
                    .and_then(|k| bins.get_mut(k))
                {
                    *end -= 1; // ends as the start of the bin
                    if let Some(slot) = sorted.get_mut((*end - start) as usize) {
                        put(slot, i as u32); // i < n ≤ u32::MAX
                    }
                }
            }
        });
}
