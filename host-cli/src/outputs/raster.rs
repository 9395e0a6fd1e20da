//! Triangles for the mesh pictures (horn, bodies, bones), flat-shaded or
//! shaded smoothly between their corners' colours, without anti-aliasing:
//! pixel centres inside the triangle take its colour, and a centre
//! exactly on an edge goes to one side only (the top-left rule), so the
//! triangles of a mesh meet with neither seams nor double coverage.
//! Pictures are drawn at twice their size and halved
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
    let colour = opaque(rgb);
    let width = pixmap.width() as usize;
    let Some(cover) = Cover::new(pixmap, top, p) else {
        return;
    };
    let pixels = pixmap.pixels_mut();
    cover.spans(|y, xs| pixels[y * width + xs.start..y * width + xs.end].fill(colour));
}

/// [`triangle`] shaded smoothly (Gouraud): each pixel in the colour
/// its centre's barycentric weights make of the corners' colours `rgb`
/// (corner k that of `p[k]`), the same pixels covered.
pub fn smooth_triangle(pixmap: &mut Pixmap, p: [[f32; 2]; 3], rgb: [[u8; 3]; 3]) {
    smooth_triangle_in_band(pixmap, 0, p, rgb);
}

/// [`smooth_triangle`] band by band, as [`triangle_in_band`].
pub fn smooth_triangle_in_band(pixmap: &mut Pixmap, top: u16, p: [[f32; 2]; 3], rgb: [[u8; 3]; 3]) {
    let width = pixmap.width() as usize;
    let Some(cover) = Cover::new(pixmap, top, p) else {
        return;
    };
    // The corners as the edges name them: corner k's weight is the edge
    // facing it, edge (k + 1) mod 3, over the area (b and c swapped
    // when the triangle was turned).
    let [a, mut b, mut c] = rgb;
    if cover.turned {
        (b, c) = (c, b);
    }
    let facing = [c, a, b];
    // Per channel, in 2⁻³² units: its change a pixel across and down,
    // linear in the edges' changes, rounded (a sliver's steepest, 255
    // over a sub-pixel, is below 2⁴⁸: exact in an f64).
    let scale = 4_294_967_296.0 / cover.area as f64;
    let gradient = |part: fn(&(i64, i64, i64)) -> i64| {
        [0, 1, 2].map(|channel| {
            let sum: f64 = (cover.edges.iter().zip(&facing))
                .map(|(edge, corner)| part(edge) as f64 * f64::from(corner[channel]))
                .sum();
            (sum * scale).round()
        })
    };
    let (across, down) = (gradient(|e| e.1), gradient(|e| e.2));
    if across.iter().chain(&down).any(|g| g.abs() >= 2f64.powi(52)) {
        // A sliver far thinner than a sub-pixel, with a centre or none:
        // its corners' mean.
        let mean = std::array::from_fn(|k| {
            ((u32::from(rgb[0][k]) + u32::from(rgb[1][k]) + u32::from(rgb[2][k])) / 3) as u8
        });
        let colour = opaque(mean);
        let pixels = pixmap.pixels_mut();
        cover.spans(|y, xs| pixels[y * width + xs.start..y * width + xs.end].fill(colour));
        return;
    }
    let (across, down) = (across.map(|g| g as i64), down.map(|g| g as i64));
    // Its value at the box's first centre: a's colour, and the gradient
    // times the way there from a in sub-pixels (whole pixels in a band
    // as in the whole picture: the same value at each pixel), raised by
    // 2⁻⁸ of a level so that the rounding of the gradient (half a unit
    // a pixel: below 2⁻¹⁵ of a level over the 2¹⁷ pixels a vertex may be
    // away) keeps every value inside the corners' 0 to 255, which the
    // pixels take without a clamp.
    let one = 1i64 << SUB;
    let way = [
        cover.x0 * one + one / 2 - cover.a[0],
        cover.y0 * one + one / 2 - cover.a[1],
    ];
    // The box's corner may lie far outside the triangle, where a steep
    // gradient's values leave an i64: every value is taken modulo 2⁶⁴
    // (wrapping), which those inside, below 2⁴⁰, are not.
    let first: [i64; 3] = std::array::from_fn(|k| {
        let along =
            i128::from(across[k]) * i128::from(way[0]) + i128::from(down[k]) * i128::from(way[1]);
        (i64::from(a[k]) << 32)
            .wrapping_add((along >> SUB) as i64)
            .wrapping_add(1 << 24)
    });
    let pixels = pixmap.pixels_mut();
    cover.spans(|y, xs| {
        let (row, t) = (y as i64 - cover.y0, xs.start as i64 - cover.x0);
        let mut value: [i64; 3] = std::array::from_fn(|k| {
            first[k]
                .wrapping_add(down[k].wrapping_mul(row))
                .wrapping_add(across[k].wrapping_mul(t))
        });
        for px in &mut pixels[y * width + xs.start..y * width + xs.end] {
            *px = opaque(value.map(|v| (v >> 32) as u8));
            for k in 0..3 {
                value[k] = value[k].wrapping_add(across[k]);
            }
        }
    });
}

#[inline(always)]
fn opaque([r, g, b]: [u8; 3]) -> PremultipliedColorU8 {
    PremultipliedColorU8::from_rgba(r, g, b, 255).unwrap_or(PremultipliedColorU8::TRANSPARENT)
}

/// The pixel centres a triangle covers in a band of a picture.
struct Cover {
    /// The box of the centres inside, pixels of the band.
    x0: i64,
    y0: i64,
    x1: i64,
    y1: i64,
    /// Per edge a → b, b → c, c → a: its function at the box's first
    /// centre and its change a pixel across and down.
    edges: [(i64, i64, i64); 3],
    /// The first corner, sub-pixels of the band.
    a: [i64; 2],
    /// Twice the area, sub-pixels squared (> 0).
    area: i64,
    /// Whether b and c were swapped to wind the triangle one way.
    turned: bool,
}

impl Cover {
    /// The triangle `p` in the band of `pixmap` from row `top` on; none
    /// when it covers no centre there or has no area.
    #[inline]
    fn new(pixmap: &Pixmap, top: u16, p: [[f32; 2]; 3]) -> Option<Cover> {
        let one = 1i64 << SUB;
        let fixed = |v: f32| (v.clamp(-REACH, REACH) * one as f32).round() as i64;
        let top = i64::from(top) * one;
        let [a, mut b, mut c] = p.map(|q| [fixed(q[0]), fixed(q[1]) - top]);
        let mut area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area == 0 {
            return None;
        }
        let turned = area < 0;
        if turned {
            (b, c) = (c, b);
            area = -area;
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
            return None;
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
        Some(Cover {
            x0,
            y0,
            x1,
            y1,
            edges: [edge(a, b), edge(b, c), edge(c, a)],
            a,
            area,
            turned,
        })
    }

    /// Calls `fill(y, xs)` for each row y of the band with the columns xs
    /// of the centres inside all three edges.
    #[inline]
    fn spans(&self, mut fill: impl FnMut(usize, std::ops::Range<usize>)) {
        for row in 0..=(self.y1 - self.y0) {
            // The centres t = x − x0 of this row inside all three edges:
            // each edge e + across·t ≥ 0 bounds t from one side, exactly.
            let (mut lo, mut hi) = (0, self.x1 - self.x0);
            for &(start, across, down) in &self.edges {
                let e = start + down * row;
                match across.signum() {
                    1 => lo = lo.max(-e.div_euclid(across)),
                    -1 => hi = hi.min(e.div_euclid(-across)),
                    _ if e < 0 => hi = -1,
                    _ => {}
                }
            }
            if lo <= hi {
                let x = self.x0 as usize;
                fill(
                    (self.y0 + row) as usize,
                    x + lo as usize..x + hi as usize + 1,
                );
            }
        }
    }
}

/// `depth` as an integer that orders as [`f64::total_cmp`] does: sorting
/// `(depth_key(depth), position)` pairs unstably is the stable sort by
/// depth, on 16-byte items however large the things sorted.
#[must_use]
pub(crate) fn depth_key(depth: f64) -> i64 {
    let bits = depth.to_bits() as i64;
    bits ^ ((((bits >> 63) as u64) >> 1) as i64)
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
    fn a_smooth_triangle_covers_the_flat_ones_pixels_in_its_corners_blend() {
        // Against each covered centre's barycentric weights in f64, from
        // the vertices rounded to sub-pixels: within a unit a channel.
        let one = f64::from(1u32 << SUB);
        let mut random = coordinates(0x5851_f42d_4c95_7f2d);
        for round in 0..300 {
            let scale = [6.0, 20.0, 60.0][round % 3];
            let p: [[f32; 2]; 3] =
                std::array::from_fn(|_| [random(scale) as f32, random(scale) as f32]);
            let corners: [[u8; 3]; 3] =
                std::array::from_fn(|k| std::array::from_fn(|c| (37 * k + 101 * c + round) as u8));
            let (mut flat, mut smooth) =
                (Pixmap::new(48, 48).unwrap(), Pixmap::new(48, 48).unwrap());
            flat.fill(Color::WHITE);
            smooth.fill(Color::WHITE);
            triangle(&mut flat, p, [1, 2, 3]);
            smooth_triangle(&mut smooth, p, corners);
            let q = p.map(|v| v.map(|c| (f64::from(c) * one).round() / one));
            let cross = |u: [f64; 2], v: [f64; 2], w: [f64; 2]| {
                (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0])
            };
            let area = cross(q[0], q[1], q[2]);
            for y in 0..48 {
                for x in 0..48 {
                    let covered = flat.pixel(x, y).unwrap().red() == 1;
                    let pixel = smooth.pixel(x, y).unwrap();
                    if !covered {
                        assert_eq!(pixel.red(), 255, "round {round} ({x}, {y}) outside");
                        continue;
                    }
                    let centre = [f64::from(x) + 0.5, f64::from(y) + 0.5];
                    let weights = [
                        cross(q[1], q[2], centre) / area,
                        cross(q[2], q[0], centre) / area,
                        cross(q[0], q[1], centre) / area,
                    ];
                    for (c, got) in [pixel.red(), pixel.green(), pixel.blue()]
                        .into_iter()
                        .enumerate()
                    {
                        let want: f64 = (0..3).map(|k| weights[k] * f64::from(corners[k][c])).sum();
                        assert!(
                            (f64::from(got) - want.floor()).abs() <= 1.0,
                            "round {round} ({x}, {y}) channel {c}: {got}, not {want}"
                        );
                    }
                }
            }
        }
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
        let corners = [[10, 200, 0], [90, 0, 40], [250, 30, 255]];
        for (p, smooth) in tris.into_iter().flat_map(|p| [(p, false), (p, true)]) {
            let mut whole = Pixmap::new(w, h).unwrap();
            if smooth {
                smooth_triangle(&mut whole, p, corners);
            } else {
                triangle(&mut whole, p, [10, 0, 0]);
            }
            for top in (0..h).step_by(band as usize) {
                let mut part = Pixmap::new(w, band.min(h - top)).unwrap();
                let reach = rows(p);
                if *reach.start() < top + part.height() && *reach.end() >= top {
                    if smooth {
                        smooth_triangle_in_band(&mut part, top as u16, p, corners);
                    } else {
                        triangle_in_band(&mut part, top as u16, p, [10, 0, 0]);
                    }
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
