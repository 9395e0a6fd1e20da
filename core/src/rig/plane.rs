//! The bytes a [`Rig`](super::Rig) borrows to draw in bounded memory (the
//! module documentation of [`crate::rig`], "Bounded memory"): in a frame
//! of cells, each pixel's distance to its nearest cell so far (a nibble,
//! in ½ px steps); in a frame of mesh records, the vertices' pixels.

use embedded_graphics::Pixel;
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Point as Px, Size};

use super::view::{PixelPos, SUBPIXEL_SHIFT};

/// How far a cell's colour reaches: to pixel centres less than
/// `CELL_REACH_PX + ½` px away. The cell plane holds distances in ½ px
/// steps, 0 to 14, and 15 for "no cell yet".
pub const CELL_REACH_PX: u32 = 7;
/// The cell plane's distance steps per pixel.
const STEPS_PER_PX: i64 = 2;
const _: () = assert!(NO_CELL as i64 == (2 * CELL_REACH_PX as i64 + 1) * STEPS_PER_PX / 2);
// `step_of` divides d² by 64 = (16 / STEPS_PER_PX)²: 1/16 px positions.
const _: () = assert!(SUBPIXEL_SHIFT == 4 && STEPS_PER_PX == 2);
/// The plane's "no cell within reach" (and the cap of every step).
const NO_CELL: u8 = 15;
/// Bytes of a vertex kept in the plane: its pixel `x`, `y` as `i16`.
const VERTEX_BYTES: usize = 4;

/// What the lent plane holds in the current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PlaneUse {
    /// Nothing of this frame yet.
    Stale,
    /// The distance of each pixel to its nearest cell.
    Cells,
    /// The pixels of this many vertices, by id.
    Vertices(u32),
}

/// Squared distances (in (1/16 px)²) ÷ 64 → ½ px steps: `⌊√(d²)/8⌋ =
/// ⌊√⌊d²/64⌋⌋`, tabulated up to the first square that is out of reach.
const STEPS: [u8; (NO_CELL as usize).pow(2)] = {
    let mut table = [0; (NO_CELL as usize).pow(2)];
    let mut i = 0;
    while i < table.len() {
        let mut step = 0;
        while (step + 1) * (step + 1) <= i {
            step += 1;
        }
        table[i] = step as u8;
        i += 1;
    }
    table
};

/// The ½ px step of a squared distance `d2` in (1/16 px)², or [`NO_CELL`]
/// when it is out of reach.
fn step_of(d2: i64) -> u8 {
    usize::try_from(d2 >> 6)
        .ok()
        .and_then(|i| STEPS.get(i))
        .copied()
        .unwrap_or(NO_CELL)
}

/// The bytes of cell plane a rig drawing on a target of `size` needs:
/// one nibble per pixel.
#[must_use]
pub const fn plane_bytes(size: Size) -> usize {
    (size.width as usize * size.height as usize).div_ceil(2)
}

/// The lent bytes and what they hold in the current frame.
#[derive(Debug)]
pub(super) struct Plane<'p> {
    bytes: &'p mut [u8],
    used: PlaneUse,
}

impl<'p> Plane<'p> {
    pub(super) const fn new(bytes: &'p mut [u8]) -> Plane<'p> {
        Plane {
            bytes,
            used: PlaneUse::Stale,
        }
    }

    /// A new frame: what the bytes hold is forgotten.
    pub(super) fn new_frame(&mut self) {
        self.used = PlaneUse::Stale;
    }

    /// Its length in bytes.
    pub(super) fn len(&self) -> usize {
        self.bytes.len()
    }

    /// Keeps vertex `id`'s pixel in the plane when it is the next vertex of
    /// the frame (ids count from 0) and there is room.
    pub(super) fn keep_vertex(&mut self, id: u32, at: PixelPos) {
        let count = match self.used {
            PlaneUse::Vertices(count) => count,
            _ => 0,
        };
        self.used = PlaneUse::Vertices(count);
        let start = VERTEX_BYTES * count as usize;
        let Some(slot) = self.bytes.get_mut(start..start + VERTEX_BYTES) else {
            return;
        };
        if id != count {
            return;
        }
        let [x, y] =
            at.0.map(|c| c.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16);
        slot[..2].copy_from_slice(&x.to_le_bytes());
        slot[2..].copy_from_slice(&y.to_le_bytes());
        self.used = PlaneUse::Vertices(count + 1);
    }

    /// The pixel kept for vertex `id`, if it was.
    pub(super) fn vertex(&self, id: u32) -> Option<Px> {
        let PlaneUse::Vertices(count) = self.used else {
            return None;
        };
        if id >= count {
            return None;
        }
        let start = VERTEX_BYTES * id as usize;
        let slot = self.bytes.get(start..start + VERTEX_BYTES)?;
        let x = i16::from_le_bytes([slot[0], slot[1]]);
        let y = i16::from_le_bytes([slot[2], slot[3]]);
        Some(Px::new(i32::from(x), i32::from(y)))
    }

    /// Paints, in `colour`, the pixels of `target` within reach of the cell
    /// at `at` (1/16 px) that are nearer to it than to every earlier cell of
    /// the frame, recording their distance. The caller has checked that the
    /// plane holds [`plane_bytes`] of the target.
    pub(super) fn paint_cell<D: DrawTarget>(
        &mut self,
        target: &mut D,
        at: [i64; 2],
        colour: D::Color,
    ) -> Result<(), D::Error> {
        let area = target.bounding_box();
        let (width, height) = (area.size.width as usize, area.size.height as usize);
        if self.used != PlaneUse::Cells {
            self.bytes.fill(NO_CELL << 4 | NO_CELL);
            self.used = PlaneUse::Cells;
        }
        // Pixel centres are at `16·i + 8` (1/16 px); reach is 15 steps of 8
        // (= (CELL_REACH_PX + ½) · 16).
        let one = 1 << SUBPIXEL_SHIFT;
        let reach = i64::from(NO_CELL) * one / STEPS_PER_PX;
        let origin = [i64::from(area.top_left.x), i64::from(area.top_left.y)];
        let span = |axis: usize, len: usize| {
            let lo = (at[axis] - reach - one / 2).div_euclid(one) + 1;
            let hi = (at[axis] + reach - one / 2).div_euclid(one);
            let first = lo.max(origin[axis]);
            let last = hi.min(origin[axis] + len as i64 - 1);
            first..=last
        };
        let (xs, ys) = (span(0, width), span(1, height));
        let plane = &mut *self.bytes;
        let pixels = ys
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter_map(|(x, y)| {
                let d = [x * one + one / 2 - at[0], y * one + one / 2 - at[1]];
                // |d| < 2^8 inside the spans: the square fits easily.
                let step = step_of(d[0] * d[0] + d[1] * d[1]);
                // Inside the target: 0 ≤ x − origin < width, likewise y.
                let index = (y - origin[1]) as usize * width + (x - origin[0]) as usize;
                let byte = plane.get_mut(index / 2)?;
                let shift = if index.is_multiple_of(2) { 4 } else { 0 };
                // Strictly nearer: ties stay with the earlier cell.
                if step < (*byte >> shift) & 0xF {
                    *byte = (*byte & !(0xF << shift)) | step << shift;
                    Some(Pixel(Px::new(x as i32, y as i32), colour))
                } else {
                    None
                }
            });
        target.draw_iter(pixels)
    }
}
