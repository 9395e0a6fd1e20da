//! Lines and triangles in whole pixels, clipped to the target first so
//! that far-away geometry costs no more than visible geometry.

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Point as Px, Size};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Line, PrimitiveStyle, Rectangle};

use super::view::PixelPos;

/// Fills the pixels whose centres lie inside triangle `t` (or on a left or
/// top edge: each row's span is half-open), one row at a time, clipped to
/// the target. Hand-written rather than `embedded-graphics`' `Triangle`,
/// whose general scanline code costs 7 KB of flash on a Cortex-M3 for the
/// same picture's worth of work.
pub(super) fn fill_triangle<D: DrawTarget>(
    target: &mut D,
    t: [Px; 3],
    colour: D::Color,
) -> Result<(), D::Error> {
    let area = target.bounding_box();
    let Some(bottom_right) = area.bottom_right() else {
        return Ok(());
    };
    // Doubled coordinates: pixel (x, y) has its centre at (2x + 1, 2y + 1).
    // The vertices are pixels too: their centres.
    let p = t.map(|q| [2 * i64::from(q.x) + 1, 2 * i64::from(q.y) + 1]);
    let rows = |lo: i64, hi: i64| {
        (
            lo.max(i64::from(area.top_left.y)),
            hi.min(i64::from(bottom_right.y)),
        )
    };
    let (ys, ye) = rows(
        (p.iter().map(|q| q[1]).min().unwrap_or(0) - 1).div_euclid(2),
        (p.iter().map(|q| q[1]).max().unwrap_or(0) - 1).div_euclid(2),
    );
    for y in ys..=ye {
        let centre = 2 * y + 1;
        // Where the row's centre line crosses the edges that span it
        // (each edge half-open in y, so a vertex is counted once).
        let mut span = [i64::MAX, i64::MIN];
        for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
            let (top, bottom) = if a[1] <= b[1] { (a, b) } else { (b, a) };
            if !(top[1] <= centre && centre < bottom[1]) {
                continue;
            }
            let x =
                top[0] + ((centre - top[1]) * (bottom[0] - top[0])).div_euclid(bottom[1] - top[1]);
            span = [span[0].min(x), span[1].max(x)];
        }
        if span[0] >= span[1] {
            continue;
        }
        // Pixels with centres in [span₀, span₁): 2x + 1 ≥ span₀, < span₁.
        let first = span[0].div_euclid(2).max(i64::from(area.top_left.x));
        let last = (span[1] - 2).div_euclid(2).min(i64::from(bottom_right.x));
        if first > last {
            continue;
        }
        // Inside the target: the casts cannot truncate.
        let row = Rectangle::new(
            Px::new(first as i32, y as i32),
            Size::new((last - first + 1) as u32, 1),
        );
        target.fill_solid(&row, colour)?;
    }
    Ok(())
}

/// Draws a line of width `w` from `a` to `b`, clipped to the target first
/// so that far-away endpoints cost no more than visible ones.
pub(super) fn line<D: DrawTarget>(
    target: &mut D,
    a: PixelPos,
    b: PixelPos,
    colour: D::Color,
    w: u32,
) -> Result<(), D::Error> {
    let area = target.bounding_box();
    // Wide lines may start just outside and still reach in.
    let pad = i64::from(w / 2);
    let lo = [
        i64::from(area.top_left.x) - pad,
        i64::from(area.top_left.y) - pad,
    ];
    // Inclusive: the last pixel is at `top_left + size − 1`.
    let hi = [
        lo[0] + i64::from(area.size.width) - 1 + 2 * pad,
        lo[1] + i64::from(area.size.height) - 1 + 2 * pad,
    ];
    let Some((a, b)) = clip(a.0, b.0, lo, hi) else {
        return Ok(());
    };
    Line::new(PixelPos(a).to_point(), PixelPos(b).to_point())
        .into_styled(PrimitiveStyle::with_stroke(colour, w))
        .draw(target)
}

/// Cohen–Sutherland clipping of segment `a`–`b` to the box `lo..=hi`, in
/// integers (intersections rounded towards zero; the box is a guard band,
/// so rounding never shows). `None` when the segment misses the box.
pub(super) fn clip(
    mut a: [i64; 2],
    mut b: [i64; 2],
    lo: [i64; 2],
    hi: [i64; 2],
) -> Option<([i64; 2], [i64; 2])> {
    let code = |p: [i64; 2]| -> u8 {
        u8::from(p[0] < lo[0])
            | u8::from(p[0] > hi[0]) << 1
            | u8::from(p[1] < lo[1]) << 2
            | u8::from(p[1] > hi[1]) << 3
    };
    // Each pass moves one endpoint onto a box edge: at most 4 per endpoint.
    for _ in 0..8 {
        let (ca, cb) = (code(a), code(b));
        if ca | cb == 0 {
            return Some((a, b));
        }
        if ca & cb != 0 {
            return None;
        }
        let (out, from, to) = if ca != 0 { (ca, a, b) } else { (cb, b, a) };
        // Intersect with the first violated edge; i128 keeps products exact.
        let (axis, edge) = match out {
            o if o & 1 != 0 => (0, lo[0]),
            o if o & 2 != 0 => (0, hi[0]),
            o if o & 4 != 0 => (1, lo[1]),
            _ => (1, hi[1]),
        };
        let other = 1 - axis;
        let t_num = i128::from(edge - from[axis]);
        let t_den = i128::from(to[axis] - from[axis]);
        if t_den == 0 {
            return None;
        }
        let moved = i128::from(from[other]) + i128::from(to[other] - from[other]) * t_num / t_den;
        let mut q = [0; 2];
        q[axis] = edge;
        q[other] = i64::try_from(moved).unwrap_or(if moved < 0 { i64::MIN } else { i64::MAX });
        if ca != 0 {
            a = q;
        } else {
            b = q;
        }
    }
    None
}
