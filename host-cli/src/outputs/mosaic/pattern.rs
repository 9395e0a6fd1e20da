//! The figures of a mosaic's pattern, measured on its Voronoi picture the
//! way one reads the thesis's figures (MClone thesis Sec. 4.1): how many
//! separate patches a type makes (a clone that grows as one spot is one
//! patch, Figs. 4.6–4.8), how many times a row across the surface enters
//! it and how wide it is there (the watermelon's stripes, Fig. 4.16), and
//! how far it stays correlated along each axis (a stripe along v is far
//! longer along v than across it).

/// The figures of one type in one picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Figures {
    /// Its separate patches (pixels joined across edges, and across the
    /// seam where the surface wraps).
    pub patches: u32,
    /// How many times a row (constant v) enters it, on average.
    pub runs_per_row: f64,
    /// Its mean width along a row, in domain units.
    pub width: f64,
    /// The lag, in domain units, at which its indicator's autocorrelation
    /// first falls below 1/e, along u and along v (at most half the
    /// picture's side).
    pub correlation: [f64; 2],
}

/// A picture of palette indices, row by row, with the domain's units per
/// pixel and whether it wraps along u and v.
#[derive(Debug, Clone, Copy)]
pub struct Raster<'a> {
    /// The palette index of every pixel, row by row.
    pub pixels: &'a [u8],
    /// Pixels per row.
    pub width: usize,
    /// Domain units per pixel along u and v.
    pub unit: [f64; 2],
    /// Whether the domain wraps along u and v.
    pub periodic: [bool; 2],
}

impl Raster<'_> {
    fn height(&self) -> usize {
        self.pixels.len() / self.width.max(1)
    }

    /// The figures of the pixels of palette index `index`.
    #[must_use]
    pub fn figures(&self, index: u8) -> Figures {
        let mask: Vec<bool> = self.pixels.iter().map(|&p| p == index).collect();
        let (runs, count) = self.runs(&mask);
        let rows = self.height().max(1) as f64;
        Figures {
            patches: self.patches(&mask),
            runs_per_row: runs as f64 / rows,
            width: if runs == 0 {
                0.0
            } else {
                count as f64 * self.unit[0] / runs as f64
            },
            correlation: [0, 1].map(|axis| self.correlation(&mask, axis)),
        }
    }

    /// The runs of `mask` along the rows, and its pixels.
    fn runs(&self, mask: &[bool]) -> (usize, usize) {
        let (mut runs, mut count) = (0, 0);
        for row in mask.chunks(self.width.max(1)) {
            let inside = row.iter().filter(|&&m| m).count();
            count += inside;
            if inside == row.len() {
                runs += usize::from(inside > 0);
                continue;
            }
            let starts = row
                .iter()
                .enumerate()
                .filter(|&(x, &m)| m && (x == 0 || !row[x - 1]))
                .count();
            // A run across the seam of a wrapping row is one run.
            let joined = self.periodic[0] && row[0] && row[row.len() - 1];
            runs += starts - usize::from(joined);
        }
        (runs, count)
    }

    /// The separate patches of `mask`: 4-connected, joined across the
    /// seams where the domain wraps.
    fn patches(&self, mask: &[bool]) -> u32 {
        let (w, h) = (self.width, self.height());
        let mut seen = vec![false; mask.len()];
        let mut stack = Vec::new();
        let mut patches = 0;
        for start in 0..mask.len() {
            if !mask[start] || seen[start] {
                continue;
            }
            patches += 1;
            seen[start] = true;
            stack.push(start);
            while let Some(i) = stack.pop() {
                let (x, y) = (i % w, i / w);
                let mut visit = |j: usize| {
                    if mask[j] && !seen[j] {
                        seen[j] = true;
                        stack.push(j);
                    }
                };
                if x + 1 < w {
                    visit(i + 1);
                } else if self.periodic[0] {
                    visit(i + 1 - w);
                }
                if x > 0 {
                    visit(i - 1);
                } else if self.periodic[0] {
                    visit(i + w - 1);
                }
                if y + 1 < h {
                    visit(i + w);
                } else if self.periodic[1] {
                    visit(x);
                }
                if y > 0 {
                    visit(i - w);
                } else if self.periodic[1] {
                    visit((h - 1) * w + x);
                }
            }
        }
        patches
    }

    /// The correlation length of `mask` along `axis` (0: u, 1: v): the
    /// pixels a lag apart that are both in it, counted a word of lines at
    /// a time (the columns for u, the rows for v).
    fn correlation(&self, mask: &[bool], axis: usize) -> f64 {
        let (w, h) = (self.width, self.height());
        let n = mask.len().max(1) as f64;
        let mean = mask.iter().filter(|&&m| m).count() as f64 / n;
        let variance = mean * (1.0 - mean);
        let (side, across) = if axis == 0 { (w, h) } else { (h, w) };
        if variance <= 0.0 {
            return 0.0;
        }
        let lines = Lines::new(mask, w, h, axis);
        for lag in 1..=side / 2 {
            let (mut pairs, mut both) = (0u64, 0u64);
            for a in 0..side {
                let mut b = a + lag;
                if b >= side {
                    if !self.periodic[axis] {
                        continue;
                    }
                    b -= side;
                }
                pairs += across as u64;
                both += lines.both(a, b);
            }
            let covariance = both as f64 / pairs.max(1) as f64 - mean * mean;
            if covariance / variance < (-1.0f64).exp() {
                return lag as f64 * self.unit[axis];
            }
        }
        (side / 2) as f64 * self.unit[axis]
    }
}

/// A mask's lines along one axis as bits, 64 pixels a word: its columns
/// (axis 0: each column's pixels down the rows) or its rows (axis 1).
struct Lines {
    words_per_line: usize,
    words: Vec<u64>,
}

impl Lines {
    fn new(mask: &[bool], w: usize, h: usize, axis: usize) -> Lines {
        let (count, length) = if axis == 0 { (w, h) } else { (h, w) };
        let words_per_line = length.div_ceil(64);
        let mut words = vec![0u64; count * words_per_line];
        for y in 0..h {
            for x in 0..w {
                if mask[y * w + x] {
                    let (line, at) = if axis == 0 { (x, y) } else { (y, x) };
                    words[line * words_per_line + at / 64] |= 1 << (at % 64);
                }
            }
        }
        Lines {
            words_per_line,
            words,
        }
    }

    fn line(&self, k: usize) -> &[u64] {
        &self.words[k * self.words_per_line..(k + 1) * self.words_per_line]
    }

    /// The pixels in both line `a` and line `b`.
    fn both(&self, a: usize, b: usize) -> u64 {
        let (a, b) = (self.line(a), self.line(b));
        a.iter()
            .zip(b)
            .map(|(x, y)| u64::from((x & y).count_ones()))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A picture `w` × `h` of index 1 where `inside(x, y)`, else 0.
    fn picture(w: usize, h: usize, inside: impl Fn(usize, usize) -> bool) -> Vec<u8> {
        (0..w * h).map(|i| u8::from(inside(i % w, i / w))).collect()
    }

    #[test]
    fn stripes_along_v_are_long_along_v_and_counted_across() {
        // 8 stripes 3 px wide every 10 px, on a 80 × 60 cylinder.
        let pixels = picture(80, 60, |x, _| x % 10 < 3);
        let raster = Raster {
            pixels: &pixels,
            width: 80,
            unit: [0.5, 0.5],
            periodic: [true, false],
        };
        let f = raster.figures(1);
        assert_eq!(f.patches, 8);
        assert_eq!(f.runs_per_row, 8.0);
        assert_eq!(f.width, 1.5);
        assert!(f.correlation[0] <= 1.5, "{f:?}");
        assert_eq!(f.correlation[1], 15.0, "{f:?}"); // never falls: half the side
    }

    #[test]
    fn a_patch_across_the_seam_is_one_patch() {
        let pixels = picture(40, 20, |x, y| !(3..=36).contains(&x) && (5..9).contains(&y));
        let wrapped = Raster {
            pixels: &pixels,
            width: 40,
            unit: [1.0, 1.0],
            periodic: [true, false],
        };
        assert_eq!(wrapped.figures(1).patches, 1);
        assert_eq!(wrapped.figures(1).runs_per_row, 4.0 / 20.0);
        let flat = Raster {
            periodic: [false, false],
            ..wrapped
        };
        assert_eq!(flat.figures(1).patches, 2);
    }

    #[test]
    fn scattered_dots_are_short_both_ways() {
        let pixels = picture(60, 60, |x, y| x % 6 < 2 && y % 6 < 2);
        let raster = Raster {
            pixels: &pixels,
            width: 60,
            unit: [1.0, 1.0],
            periodic: [true, true],
        };
        let f = raster.figures(1);
        assert_eq!(f.patches, 100);
        assert!(f.correlation[0] <= 2.0 && f.correlation[1] <= 2.0, "{f:?}");
    }

    /// The correlation length pixel pair by pixel pair, as defined.
    fn correlation_by_pixels(raster: &Raster<'_>, mask: &[bool], axis: usize) -> f64 {
        let (w, h) = (raster.width, raster.height());
        let mean = mask.iter().filter(|&&m| m).count() as f64 / mask.len() as f64;
        let variance = mean * (1.0 - mean);
        let side = if axis == 0 { w } else { h };
        if variance <= 0.0 {
            return 0.0;
        }
        for lag in 1..=side / 2 {
            let (mut pairs, mut both) = (0u64, 0u64);
            for y in 0..h {
                for x in 0..w {
                    let (mut x2, mut y2) = if axis == 0 {
                        (x + lag, y)
                    } else {
                        (x, y + lag)
                    };
                    if x2 >= w {
                        if !raster.periodic[0] {
                            continue;
                        }
                        x2 -= w;
                    }
                    if y2 >= h {
                        if !raster.periodic[1] {
                            continue;
                        }
                        y2 -= h;
                    }
                    pairs += 1;
                    both += u64::from(mask[y * w + x] && mask[y2 * w + x2]);
                }
            }
            let covariance = both as f64 / pairs as f64 - mean * mean;
            if covariance / variance < (-1.0f64).exp() {
                return lag as f64 * raster.unit[axis];
            }
        }
        (side / 2) as f64 * raster.unit[axis]
    }

    #[test]
    fn correlation_by_words_is_the_pixel_by_pixel_one() {
        // Blobs of a random walk's size on sides that are and are not
        // multiples of 64, flat and wrapping.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h) in [(37, 23), (64, 64), (130, 70), (200, 9)] {
            let (cx, cy, r) = (
                next() as usize % w,
                next() as usize % h,
                2 + next() as usize % 20,
            );
            let pixels = picture(w, h, |x, y| {
                let (dx, dy) = (x.abs_diff(cx), y.abs_diff(cy));
                dx * dx + 4 * dy * dy < r * r || (x * 7 + y * 3) % 11 == 0
            });
            let mask: Vec<bool> = pixels.iter().map(|&p| p == 1).collect();
            for periodic in [[false, false], [true, false], [false, true], [true, true]] {
                let raster = Raster {
                    pixels: &pixels,
                    width: w,
                    unit: [0.25, 0.5],
                    periodic,
                };
                for axis in [0, 1] {
                    assert_eq!(
                        raster.correlation(&mask, axis),
                        correlation_by_pixels(&raster, &mask, axis),
                        "{w} x {h}, {periodic:?}, axis {axis}"
                    );
                }
            }
        }
    }
}
