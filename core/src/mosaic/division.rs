//! Division and mutation (thesis Sec. 3.2.1.2): a cell of type T divides
//! after a Poisson-distributed number of days with mean D_T (at least one
//! day); the child lands uniformly at random in a disc of diameter 1 % of
//! the repulsion radius around its parent, and its type comes from the
//! parent's row of the mutation matrix.
//!
//! Every random draw comes from a [`KeyedRng`] stream named by (purpose,
//! day, cell id), so a cell's fate does not depend on the order in which
//! cells are visited.

use super::params::{CellType, MAX_TYPES, Params};
use crate::Error;
use crate::fx::Fx;
use crate::rng::KeyedRng;

/// What a random stream is for (the top byte of its id).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Purpose {
    /// Position, type and first division day of an initial cell.
    Place = 1,
    /// A division: the child's offset and type, both cells' next days.
    Divide = 2,
}

/// The stream id of `purpose` for cell `cell` on day `day`.
#[must_use]
pub const fn stream_id(purpose: Purpose, day: u16, cell: u32) -> u64 {
    ((purpose as u64) << 56) | ((day as u64) << 32) | cell as u64
}

/// A probability as a Q32 threshold for a 32-bit draw.
fn q32(p: Fx) -> u64 {
    (p.clamp(Fx::ZERO, Fx::ONE).to_bits() as u64) << 16
}

/// Picks an index with the given probabilities (cumulative, at 32-bit
/// resolution); draws past the total pick `fallback`.
fn pick(
    rng: &mut KeyedRng,
    probabilities: impl Iterator<Item = (usize, Fx)>,
    fallback: usize,
) -> usize {
    let u = u64::from(rng.next_u32());
    let mut acc = 0u64;
    for (i, p) in probabilities {
        acc += q32(p);
        if u < acc {
            return i;
        }
    }
    fallback
}

/// The type of an initial cell, by the types' initial probabilities (draws
/// beyond their sum give type 0).
pub fn initial_type(rng: &mut KeyedRng, types: &[CellType]) -> u8 {
    pick(
        rng,
        types.iter().map(|t| t.initial_probability).enumerate(),
        0,
    ) as u8
}

/// The type of a child of `parent`.
pub fn child_type(
    rng: &mut KeyedRng,
    parent: u8,
    mutation: &[[Fx; MAX_TYPES]; MAX_TYPES],
    types: usize,
) -> u8 {
    let row = &mutation[parent as usize % MAX_TYPES];
    let others = row
        .iter()
        .copied()
        .enumerate()
        .take(types)
        .filter(|(j, _)| *j != parent as usize);
    pick(rng, others, parent as usize) as u8
}

/// Days until the next division of a cell of `kind`: Poisson with mean
/// D_T, at least 1.
///
/// # Errors
/// A mean beyond the Poisson sampler's limit.
pub fn interval(rng: &mut KeyedRng, kind: &CellType) -> Result<u16, Error> {
    let k = rng.poisson(Fx::from_int(i32::from(kind.division_days)))?;
    Ok(k.clamp(1, u32::from(u16::MAX)) as u16)
}

/// A uniform point in the disc of radius `radius` (Q16 bits) around the
/// origin, by rejection from the square (at most 64 tries, then the
/// centre; the chance of that is below 10^-42).
pub fn offset_in_disc(rng: &mut KeyedRng, radius: i32) -> [i32; 2] {
    let r2 = i64::from(radius) * i64::from(radius);
    for _ in 0..64 {
        let x = rng.between(-radius, radius);
        let y = rng.between(-radius, radius);
        if i64::from(x) * i64::from(x) + i64::from(y) * i64::from(y) <= r2 {
            return [x, y];
        }
    }
    [0, 0]
}

/// What the division of a cell decides, drawn in this order from the
/// stream of (day, cell): the child's type, its offset from the parent in
/// the disc of radius `disc`, the child's and then the parent's next
/// division day.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// The child's type.
    pub child: u8,
    /// The child's offset from its parent (Q16 bits, in the plane of the
    /// parent's surface).
    pub offset: [i32; 2],
    /// The child's next division day.
    pub child_next: u16,
    /// The parent's next division day.
    pub parent_next: u16,
}

/// The division on `day` of cell `id` of type `parent` in a run of
/// `params` with `seed`.
///
/// # Errors
/// A mean beyond the Poisson sampler's limit.
pub fn split(
    seed: u64,
    day: u16,
    id: u32,
    parent: u8,
    params: &Params,
    disc: i32,
) -> Result<Split, Error> {
    let types = params.types;
    let mut rng = KeyedRng::new(seed, stream_id(Purpose::Divide, day, id));
    let child = child_type(&mut rng, parent, &params.mutation, types.len());
    let offset = offset_in_disc(&mut rng, disc);
    let mut later = |k: u8| -> Result<u16, Error> {
        let t = &types[k as usize % types.len().max(1)];
        Ok(day.saturating_add(interval(&mut rng, t)?))
    };
    let child_next = later(child)?;
    let parent_next = later(parent)?;
    Ok(Split {
        child,
        offset,
        child_next,
        parent_next,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stream_ids_separate_purpose_day_and_cell() {
        assert_eq!(stream_id(Purpose::Divide, 3, 7), (2 << 56) | (3 << 32) | 7);
        assert_ne!(
            stream_id(Purpose::Place, 0, 1),
            stream_id(Purpose::Divide, 0, 1)
        );
    }

    #[test]
    fn mutation_follows_the_matrix_row() {
        let mut m = [[Fx::ZERO; MAX_TYPES]; MAX_TYPES];
        m[1][0] = Fx::from_ratio(1, 4);
        m[1][2] = Fx::from_ratio(1, 10);
        let mut counts = [0u32; 3];
        for i in 0..40_000 {
            let mut rng = KeyedRng::new(9, stream_id(Purpose::Divide, 1, i));
            counts[child_type(&mut rng, 1, &m, 3) as usize] += 1;
        }
        // 10 000 ± 4σ (σ ≈ 87), 4 000 ± 4σ (σ ≈ 60).
        assert!((9_650..10_350).contains(&counts[0]), "{counts:?}");
        assert!((3_760..4_240).contains(&counts[2]), "{counts:?}");
    }

    #[test]
    fn children_land_in_the_disc() {
        let mut rng = KeyedRng::new(1, 1);
        let mut far = 0;
        for _ in 0..1000 {
            let [x, y] = offset_in_disc(&mut rng, 100);
            assert!(x * x + y * y <= 100 * 100);
            far += i32::from(x * x + y * y > 50 * 50);
        }
        // 3/4 of a uniform disc lies beyond half the radius.
        assert!((700..800).contains(&far), "{far}");
    }
}
