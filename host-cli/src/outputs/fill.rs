//! Anti-aliased fills of polygons and round-capped strokes blended over an
//! opaque picture. A small shape's pixels are each covered by the exact
//! area of it inside the shape (`ab_glyph_rasterizer`, the coverage
//! rasteriser of the text renderer): a plant is thousands of shapes a few
//! pixels across, where a general path filler (tiny-skia: edge lists, a
//! supersampled scan and a raster pipeline per span) spends ~70 K
//! instructions on each. A large one goes to tiny-skia, whose span fills
//! beat a pass over every pixel of its box (`LARGE`).

use ab_glyph_rasterizer::{Rasterizer, point};
use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, PremultipliedColorU8, Transform};

use super::animation::mix;

/// How far above or below the picture a point is kept, pixels (rows
/// outside the picture are not drawn): a point beyond is moved to it,
/// which bounds the f32 arithmetic on a stray point and moves an edge
/// within the picture by a negligible part of a pixel (a plant's points
/// are inside).
const REACH: f32 = 1.0e6;

/// The most pixels in a shape's box filled by coverage; a larger shape
/// is filled by tiny-skia. A coverage pass costs ~10 instructions a
/// pixel of the box, tiny-skia ~70 K a shape and little a pixel inside:
/// strokes as wide as the picture took 19.3 s by coverage and 1.8 s by
/// tiny-skia (15 625 of them).
const LARGE: usize = 8_192;

/// Coverage below this (of 1) leaves a pixel as it is.
const NONE: f32 = 0.5 / 255.0;

/// A filler, keeping its coverage grid and outlines between shapes.
pub struct Filler {
    grid: Rasterizer,
    /// The outline being filled, and its part within the picture's columns.
    outline: Vec<[f32; 2]>,
    clipped: Vec<[f32; 2]>,
}

impl std::fmt::Debug for Filler {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Filler").finish_non_exhaustive()
    }
}

impl Default for Filler {
    fn default() -> Self {
        Filler {
            grid: Rasterizer::new(0, 0),
            outline: Vec::new(),
            clipped: Vec::new(),
        }
    }
}

impl Filler {
    /// Fills the closed polygon through `points` (pixel coordinates, any
    /// winding, not crossing itself) with the opaque colour `rgb`.
    pub fn polygon(&mut self, pixmap: &mut Pixmap, points: &[[f32; 2]], rgb: [u8; 3]) {
        self.outline.clear();
        self.outline.extend_from_slice(points);
        self.fill(pixmap, rgb);
    }

    /// Strokes the segment `a`–`b` (pixel coordinates) `width` pixels
    /// wide with round caps in the opaque colour `rgb`: the outline of
    /// its capsule, each cap a half circle of `width / 2` in chords at
    /// most an eighth of a pixel off the arc.
    pub fn segment(
        &mut self,
        pixmap: &mut Pixmap,
        a: [f32; 2],
        b: [f32; 2],
        width: f32,
        rgb: [u8; 3],
    ) {
        let r = width / 2.0;
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let length = dx.hypot(dy);
        // Along the segment, and to its left; a dot points anywhere.
        let along = if length > 1e-6 {
            [dx / length, dy / length]
        } else {
            [1.0, 0.0]
        };
        let left = [-along[1], along[0]];
        // A chord of angle θ is off its arc by r·(1 − cos(θ/2)) ≈ r·θ²/8:
        // an eighth of a pixel at θ = 1/√r.
        let steps = (std::f32::consts::PI * r.max(1e-3).sqrt())
            .ceil()
            .clamp(2.0, 64.0) as usize;
        let cap = move |centre: [f32; 2], from: [f32; 2]| {
            (0..=steps).map(move |k| {
                // From `from` turning through half a circle, clockwise on
                // screen (y down) from left to right around the end.
                let t = std::f32::consts::PI * k as f32 / steps as f32;
                let (s, c) = t.sin_cos();
                let to = [-from[1], from[0]];
                [
                    centre[0] + r * (from[0] * c - to[0] * s),
                    centre[1] + r * (from[1] * c - to[1] * s),
                ]
            })
        };
        self.outline.clear();
        self.outline
            .extend(cap(b, left).chain(cap(a, [-left[0], -left[1]])));
        self.fill(pixmap, rgb);
    }

    /// Fills the closed outline in `self.outline` with `rgb`.
    fn fill(&mut self, pixmap: &mut Pixmap, rgb: [u8; 3]) {
        let (w, h) = (pixmap.width() as f32, pixmap.height() as f32);
        for p in &mut self.outline {
            *p = [p[0], p[1].clamp(-REACH, h + REACH)];
        }
        // Coverage runs along a row from the grid's left end, so the
        // outline is cut exactly to a pixel beyond either side of the
        // picture (not just its box) and the grid spans no more.
        clip(&self.outline, &mut self.clipped, |p| p[0] >= -1.0, -1.0);
        clip(
            &self.clipped,
            &mut self.outline,
            |p| p[0] <= w + 1.0,
            w + 1.0,
        );
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in &self.outline {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        // The grid: whole pixels around the box, one more column on the
        // right for the coverage an edge hands its right neighbour; rows
        // outside the picture left out (each row's coverage is its own).
        let (left, top, bottom) = (lo[0].floor(), lo[1].floor().max(0.0), hi[1].ceil().min(h));
        if top >= bottom || hi[0] < 0.0 || lo[0] >= w {
            return;
        }
        let (columns, rows) = ((hi[0].ceil() - left) as usize + 2, (bottom - top) as usize);
        if columns * rows > LARGE {
            self.fill_path(pixmap, rgb);
            return;
        }
        self.grid.reset(columns, rows);
        let at = |p: [f32; 2]| point(p[0] - left, p[1] - top);
        let ends = self.outline.iter().zip(self.outline.iter().cycle().skip(1));
        for (&p, &q) in ends {
            self.grid.draw_line(at(p), at(q));
        }
        let stride = pixmap.width() as usize;
        let pixels = pixmap.pixels_mut();
        self.grid.for_each_pixel_2d(|gx, gy, coverage| {
            let x = left + gx as f32;
            if coverage < NONE || x < 0.0 || x >= w {
                return;
            }
            let at = (top as usize + gy as usize) * stride + x as usize;
            let weight = (coverage.min(1.0) * 255.0 + 0.5) as u16;
            if let Some(pixel) = pixels.get_mut(at) {
                *pixel = blend(*pixel, rgb, weight);
            }
        });
    }

    /// Fills the outline in `self.outline` with tiny-skia's anti-aliased
    /// path filler.
    fn fill_path(&self, pixmap: &mut Pixmap, rgb: [u8; 3]) {
        let mut path = PathBuilder::new();
        for (k, p) in self.outline.iter().enumerate() {
            if k == 0 {
                path.move_to(p[0], p[1]);
            } else {
                path.line_to(p[0], p[1]);
            }
        }
        path.close();
        let Some(path) = path.finish() else { return };
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgb[0], rgb[1], rgb[2], 255);
        paint.anti_alias = true;
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

/// The closed outline `from` cut to the side of the vertical line
/// `x = at` where `keep` holds, into `to` (Sutherland–Hodgman: each edge
/// keeps its end inside and adds where it crosses the line).
fn clip(from: &[[f32; 2]], to: &mut Vec<[f32; 2]>, keep: impl Fn([f32; 2]) -> bool, at: f32) {
    to.clear();
    let cross = |p: [f32; 2], q: [f32; 2]| {
        let t = (at - p[0]) / (q[0] - p[0]);
        [at, p[1] + t * (q[1] - p[1])]
    };
    let Some(&last) = from.last() else { return };
    let mut p = last;
    for &q in from {
        match (keep(p), keep(q)) {
            (true, true) => to.push(q),
            (true, false) => to.push(cross(p, q)),
            (false, true) => to.extend([cross(p, q), q]),
            (false, false) => {}
        }
        p = q;
    }
}

/// `pixel` (opaque) moved towards `rgb` by `weight` of 255, rounded
/// ([`mix`]).
fn blend(pixel: PremultipliedColorU8, rgb: [u8; 3], weight: u16) -> PremultipliedColorU8 {
    let [r, g, b] = [
        mix(pixel.red(), rgb[0], weight),
        mix(pixel.green(), rgb[1], weight),
        mix(pixel.blue(), rgb[2], weight),
    ];
    PremultipliedColorU8::from_rgba(r, g, b, 255).unwrap_or(pixel)
}

#[cfg(test)]
mod tests {
    use tiny_skia::Color;

    use super::*;

    /// A white `w × h` picture.
    fn white(w: u32, h: u32) -> Pixmap {
        let mut p = Pixmap::new(w, h).unwrap();
        p.fill(Color::WHITE);
        p
    }

    /// How much of pixel (x, y) is black, 0 to 1.
    fn ink(p: &Pixmap, x: u32, y: u32) -> f32 {
        1.0 - f32::from(p.pixel(x, y).unwrap().red()) / 255.0
    }

    /// The area painted black, pixels.
    fn area(p: &Pixmap) -> f32 {
        (0..p.height())
            .flat_map(|y| (0..p.width()).map(move |x| (x, y)))
            .map(|(x, y)| ink(p, x, y))
            .sum()
    }

    #[test]
    fn a_polygon_covers_each_pixel_by_its_area_inside() {
        let mut p = white(12, 10);
        let square = [[2.25, 3.0], [5.75, 3.0], [5.75, 6.5], [2.25, 6.5]];
        Filler::default().polygon(&mut p, &square, [0, 0, 0]);
        assert_eq!(p.pixel(2, 3).unwrap().red(), 64); // 3/4 covered
        assert_eq!(p.pixel(3, 4).unwrap().red(), 0);
        assert_eq!(p.pixel(5, 6).unwrap().red(), 159); // 3/4 · 1/2
        assert_eq!(p.pixel(6, 4).unwrap().red(), 255);
        assert_eq!(p.pixel(3, 2).unwrap().red(), 255);
        assert!((area(&p) - 3.5 * 3.5).abs() < 0.02, "{}", area(&p));
        // Either winding, and a shape cut by the picture's left edge.
        let mut q = white(12, 10);
        let across = [[3.25, 1.0], [-5.5, 1.0], [-5.5, 2.0], [3.25, 2.0]];
        Filler::default().polygon(&mut q, &across, [0, 0, 0]);
        let row: Vec<u8> = (0..5).map(|x| q.pixel(x, 1).unwrap().red()).collect();
        assert_eq!(row, [0, 0, 0, 191, 255]);
        assert!((area(&q) - 3.25).abs() < 0.02);
        // Slanted edges cut at either side: inside a 10 × 20 picture, the
        // area under y = 17.5 + x/4 (0 ≤ x ≤ 10) is 187.5; mirrored, the
        // same; and a shape far larger than the picture fills all of it.
        for mirror in [false, true] {
            let mut r = white(10, 20);
            let x = |x: f32| if mirror { 10.0 - x } else { x };
            let slanted = [
                [x(-50.0), 0.0],
                [x(10.0), 0.0],
                [x(10.0), 20.0],
                [x(-50.0), 5.0],
            ];
            Filler::default().polygon(&mut r, &slanted, [0, 0, 0]);
            assert!((area(&r) - 187.5).abs() < 0.05, "{}", area(&r));
        }
        let mut r = white(10, 20);
        let huge = [[-1e5, -3e5], [2e5, 1e5], [-1e5, 1e5]];
        Filler::default().polygon(&mut r, &huge, [0, 0, 0]);
        assert!((area(&r) - 200.0).abs() < 0.05, "{}", area(&r));
    }

    #[test]
    fn a_segment_is_a_capsule_of_its_width() {
        let mut p = white(40, 20);
        Filler::default().segment(&mut p, [10.0, 10.5], [30.0, 10.5], 3.0, [0, 0, 0]);
        for y in 9..12 {
            assert_eq!(p.pixel(20, y).unwrap().red(), 0);
        }
        assert_eq!(p.pixel(20, 8).unwrap().red(), 255);
        assert_eq!(p.pixel(20, 12).unwrap().red(), 255);
        // The caps reach 1.5 beyond both ends: of pixel 8 (x 8 to 9, y 10
        // to 11) the disc about (10, 10.5) covers √(2.25 − t²) − 1 at
        // t = y − 10.5, 0.472 on average; the chords, up to 1/8 px inside
        // the arc, may take up to 1/8 of it.
        for x in [8, 31] {
            let ink = ink(&p, x, 10);
            assert!((ink - 0.472).abs() < 0.125, "{x}: {ink}");
        }
        assert_eq!(p.pixel(7, 10).unwrap().red(), 255);
        assert_eq!(p.pixel(32, 10).unwrap().red(), 255);
        // A rectangle and two half discs, of which the chords (at least
        // four a half circle) keep at least 90 % (less a little for ink
        // rounded to 1/255 a pixel).
        within_capsule(&p, 20.0, 1.5);
        // Slanted, and a dot (both ends at one place) is a disc.
        let mut q = white(40, 40);
        Filler::default().segment(&mut q, [5.0, 5.0], [25.0, 30.0], 2.0, [0, 0, 0]);
        within_capsule(&q, 41f32.sqrt() * 5.0, 1.0);
        let mut d = white(20, 20);
        Filler::default().segment(&mut d, [9.3, 9.7], [9.3, 9.7], 8.0, [0, 0, 0]);
        within_capsule(&d, 0.0, 4.0);
    }

    /// Checks that `p`'s ink is a capsule's of `length` and radius `r`.
    fn within_capsule(p: &Pixmap, length: f32, r: f32) {
        let (rectangle, disc) = (2.0 * r * length, std::f32::consts::PI * r * r);
        let ink = area(p);
        assert!(
            ink > rectangle + 0.88 * disc && ink < (rectangle + disc) * 1.005,
            "{ink}"
        );
    }

    #[test]
    fn a_large_shape_is_filled_by_its_area_too() {
        // 150 × 120.5 pixels at fractional places, a box past LARGE.
        let mut p = white(200, 160);
        let square = [
            [20.5, 10.25],
            [170.5, 10.25],
            [170.5, 130.75],
            [20.5, 130.75],
        ];
        Filler::default().polygon(&mut p, &square, [0, 0, 0]);
        let want = 150.0 * 120.5;
        assert!((area(&p) - want).abs() < 0.002 * want, "{}", area(&p));
        assert_eq!(p.pixel(100, 70).unwrap().red(), 0);
        assert_eq!(p.pixel(19, 70).unwrap().red(), 255);
        let mut q = white(200, 160);
        Filler::default().segment(&mut q, [30.0, 80.0], [170.0, 80.0], 60.0, [0, 0, 0]);
        within_capsule(&q, 140.0, 30.0);
    }

    #[test]
    fn thin_strokes_are_faint_and_colours_blend() {
        // 0.6 px wide on a row's middle: 60 % of each pixel it crosses.
        let mut p = white(20, 5);
        Filler::default().segment(&mut p, [3.0, 2.5], [15.0, 2.5], 0.6, [0, 0, 0]);
        assert!((ink(&p, 9, 2) - 0.6).abs() < 0.01, "{}", ink(&p, 9, 2));
        let mut q = white(6, 6);
        let all = [[0.0, 0.0], [6.0, 0.0], [6.0, 6.0], [0.0, 6.0]];
        Filler::default().polygon(&mut q, &all, [200, 100, 0]);
        let half = [[0.0, 0.0], [3.5, 0.0], [3.5, 6.0], [0.0, 6.0]];
        Filler::default().polygon(&mut q, &half, [0, 100, 200]);
        let c = q.pixel(3, 1).unwrap();
        assert_eq!(
            [c.red(), c.green(), c.blue(), c.alpha()],
            [100, 100, 100, 255]
        );
        // Nothing at all outside the picture.
        Filler::default().polygon(&mut q, &[[-9.0, 0.0], [-1.0, 0.0], [-1.0, 4.0]], [0; 3]);
        Filler::default().segment(&mut q, [3.0, 30.0], [3.0, 40.0], 4.0, [0; 3]);
        assert_eq!(q.pixel(0, 0).unwrap().blue(), 200);
    }
}
