//! Flat-shaded triangles for the mesh pictures (horn, bodies, bones),
//! without anti-aliasing: pixel centres inside the triangle take its
//! colour, and a centre exactly on an edge goes to one side only (the
//! top-left rule), so the triangles of a mesh meet with neither seams nor
//! double coverage. Pictures are drawn at twice their size and halved
//! ([`super::picture::half`]) for smooth edges — far cheaper than a
//! general path filler with coverage per triangle.

use std::ops::RangeInclusive;

use tiny_skia::{Pixmap, PremultipliedColorU8};

/// Sub-pixel bits of the vertex coordinates.
const SUB: u32 = 8;
/// The largest coordinate kept, pixels: beyond any picture, and small
/// enough that edge products (< 2 · (2¹⁷⁺⁸)², a band's shift of at most
/// 2¹⁶ rows included) fit an `i64`.
const REACH: f32 = 65_536.0;

/// Fills the triangle `p` (pixel coordinates, any winding) with the opaque
/// colour `rgb`.
pub fn triangle(pixmap: &mut Pixmap, p: [[f32; 2]; 3], rgb: [u8; 3]) {
    triangle_in_band(pixmap, 0, p, rgb);
}

/// The rows of a picture the triangle `p` can fill (a row or so more
/// than it does: enough to pick the bands of a picture drawn band by
/// band that it reaches).
pub fn rows(p: [[f32; 2]; 3]) -> RangeInclusive<u32> {
    // As `triangle` reads a coordinate (not a number: 0), to whole pixels
    // outwards and one more, since rounding to sub-pixels may move it.
    let ys = p.map(|q| if q[1].is_nan() { 0.0 } else { q[1] });
    let lo = ys.into_iter().fold(f32::INFINITY, f32::min);
    let hi = ys.into_iter().fold(f32::NEG_INFINITY, f32::max);
    // Saturating casts: negative to 0, past u32 to u32::MAX.
    (lo.floor() - 1.0) as u32..=(hi.ceil() + 1.0) as u32
}

/// [`triangle`] for a picture drawn band by band: `pixmap` holds the
/// picture's rows from `top` on, and gets the same pixels of them as the
/// whole picture would (the vertices are moved by whole pixels after
/// their rounding to sub-pixels, where every edge test is exact).
pub fn triangle_in_band(pixmap: &mut Pixmap, top: u16, p: [[f32; 2]; 3], rgb: [u8; 3]) {
    let colour = PremultipliedColorU8::from_rgba(rgb[0], rgb[1], rgb[2], 255)
        .unwrap_or(PremultipliedColorU8::TRANSPARENT);
    let one = 1i64 << SUB;
    let fixed = |v: f32| (v.clamp(-REACH, REACH) * one as f32).round() as i64;
    let top = i64::from(top) * one;
    let [a, mut b, mut c] = p.map(|q| [fixed(q[0]), fixed(q[1]) - top]);
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if area == 0 {
        return;
    }
    if area < 0 {
        (b, c) = (c, b);
    }
    let (width, height) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    // Pixel x's centre is x·one + one/2; the box of centres inside.
    let first = |lo: i64| (lo - one / 2 + one - 1).div_euclid(one).max(0);
    let last = |hi: i64, n: i64| (hi - one / 2).div_euclid(one).min(n - 1);
    let x0 = first(a[0].min(b[0]).min(c[0]));
    let x1 = last(a[0].max(b[0]).max(c[0]), width);
    let y0 = first(a[1].min(b[1]).min(c[1]));
    let y1 = last(a[1].max(b[1]).max(c[1]), height);
    if x0 > x1 || y0 > y1 {
        return;
    }
    // Edge u → v: e(q) = (v − u) × (q − u), ≥ 0 inside. A centre on the
    // edge belongs to it when the edge is a top or left one, which the
    // shared edge of the neighbouring triangle (run the other way) is not.
    let edge = |u: [i64; 2], v: [i64; 2]| {
        let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
        let owns = dy < 0 || (dy == 0 && dx > 0);
        let centre = [x0 * one + one / 2, y0 * one + one / 2];
        let start = dx * (centre[1] - u[1]) - dy * (centre[0] - u[0]) - i64::from(!owns);
        (start, -dy * one, dx * one)
    };
    let edges = [edge(a, b), edge(b, c), edge(c, a)];
    let pixels = pixmap.pixels_mut();
    for row in 0..=(y1 - y0) {
        // The centres t = x − x0 of this row inside all three edges: each
        // edge e + across·t ≥ 0 bounds t from one side, exactly.
        let (mut lo, mut hi) = (0, x1 - x0);
        for &(start, across, down) in &edges {
            let e = start + down * row;
            match across.signum() {
                1 => lo = lo.max(-e.div_euclid(across)),
                -1 => hi = hi.min(e.div_euclid(-across)),
                _ if e < 0 => hi = -1,
                _ => {}
            }
        }
        if lo <= hi {
            let line = (y0 + row) * width + x0;
            pixels[(line + lo) as usize..=(line + hi) as usize].fill(colour);
        }
    }
}

#[cfg(test)]
mod tests {
    use tiny_skia::Color;

    use super::*;

    fn ascii(p: &Pixmap) -> Vec<String> {
        (0..p.height())
            .map(|y| {
                (0..p.width())
                    .map(|x| match p.pixel(x, y).unwrap().red() {
                        255 => '.',
                        10 => 'a',
                        20 => 'b',
                        _ => '?',
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn two_halves_of_a_square_cover_it_once_without_seams() {
        let mut p = Pixmap::new(6, 4).unwrap();
        p.fill(Color::WHITE);
        let square = [[1.0, 0.0], [5.0, 0.0], [5.0, 4.0], [1.0, 4.0]];
        triangle(&mut p, [square[0], square[1], square[2]], [10, 0, 0]);
        triangle(&mut p, [square[0], square[3], square[2]], [20, 0, 0]);
        assert_eq!(ascii(&p), [".aaaa.", ".baaa.", ".bbaa.", ".bbba."]);
    }

    /// Coordinates in [−range/4, 3·range/4) from an xorshift sequence
    /// seeded by `seed`: vertices on a picture `range` wide and around it.
    fn coordinates(mut seed: u64) -> impl FnMut(f64) -> f64 {
        move |range| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * range - range / 4.0
        }
    }

    #[test]
    fn random_triangles_cover_the_centres_inside_them() {
        // Against each pixel centre's three edge functions (sub-pixel
        // vertices, the top-left rule): tall, thin, tiny and off-picture
        // triangles, both windings.
        let one = f64::from(1u32 << SUB);
        let mut random = coordinates(0x2545_f491_4f6c_dd1d);
        for round in 0..800 {
            let scale = [3.0, 12.0, 40.0][round / 2 % 3];
            // Half the rounds on a half-pixel grid: centres exactly on
            // edges, where the top-left rule decides.
            let snap = |v: f64| {
                if round % 2 == 0 {
                    (v * 2.0).round() / 2.0
                } else {
                    v
                }
            };
            let p: [[f32; 2]; 3] =
                std::array::from_fn(|_| [snap(random(scale)) as f32, snap(random(scale)) as f32]);
            let mut pixmap = Pixmap::new(24, 24).unwrap();
            pixmap.fill(Color::WHITE);
            triangle(&mut pixmap, p, [10, 0, 0]);
            let q = p.map(|v| v.map(|c| (f64::from(c) * one).round()));
            let area = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1])
                - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
            let [a, mut b, mut c] = q;
            if area < 0.0 {
                (b, c) = (c, b);
            }
            for y in 0..24 {
                for x in 0..24 {
                    let centre = [(f64::from(x) + 0.5) * one, (f64::from(y) + 0.5) * one];
                    let inside = area != 0.0
                        && [(a, b), (b, c), (c, a)].iter().all(|&(u, v)| {
                            let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
                            let e = dx * (centre[1] - u[1]) - dy * (centre[0] - u[0]);
                            e > 0.0 || (e == 0.0 && (dy < 0.0 || (dy == 0.0 && dx > 0.0)))
                        });
                    let drawn = pixmap.pixel(x, y).unwrap().red() == 10;
                    assert_eq!(drawn, inside, "round {round} {p:?} at ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn triangles_off_the_picture_or_flat_draw_nothing() {
        let mut p = Pixmap::new(3, 3).unwrap();
        p.fill(Color::WHITE);
        triangle(
            &mut p,
            [[-9.0, -9.0], [-5.0, -9.0], [-5.0, -5.0]],
            [10, 0, 0],
        );
        triangle(&mut p, [[0.0, 0.0], [3.0, 3.0], [1.5, 1.5]], [10, 0, 0]);
        triangle(&mut p, [[-1e9, -1e9], [1e9, -1e9], [0.0, 1e9]], [20, 0, 0]);
        assert_eq!(ascii(&p), ["bbb", "bbb", "bbb"]);
    }

    #[test]
    fn a_triangle_drawn_band_by_band_is_the_triangle_drawn_whole() {
        // Triangles large and small, some far off the picture or with a
        // coordinate not a number, each drawn whole and in bands of 5 rows
        // (each band drawing it when its rows reach the band): the same
        // pixels.
        let mut random = coordinates(0x9e37_79b9_7f4a_7c15);
        let mut tris: Vec<[[f32; 2]; 3]> = (0..600)
            .map(|k| {
                let scale = [4.0, 12.0, 40.0, 90.0][k % 4];
                std::array::from_fn(|_| [random(scale) as f32, random(scale) as f32])
            })
            .collect();
        tris.push([[10.0, f32::NAN], [30.0, 25.0], [5.0, 30.0]]);
        tris.push([[-1e9, -1e9], [1e9, 10.5], [5.0, 1e9]]);
        tris.push([[3.0, 2.0], [30.0, 9.0], [12.0, 1e30]]);
        let (w, h, band) = (40u32, 33u32, 5u32);
        let rows_of = |p: &Pixmap, from: u32, n: u32| {
            p.pixels()[(from * w) as usize..][..(n * w) as usize].to_vec()
        };
        for p in tris {
            let mut whole = Pixmap::new(w, h).unwrap();
            triangle(&mut whole, p, [10, 0, 0]);
            for top in (0..h).step_by(band as usize) {
                let mut part = Pixmap::new(w, band.min(h - top)).unwrap();
                let reach = rows(p);
                if *reach.start() < top + part.height() && *reach.end() >= top {
                    triangle_in_band(&mut part, top as u16, p, [10, 0, 0]);
                }
                let n = part.height();
                assert_eq!(
                    rows_of(&part, 0, n),
                    rows_of(&whole, top, n),
                    "{p:?} from row {top}"
                );
            }
        }
    }
}
