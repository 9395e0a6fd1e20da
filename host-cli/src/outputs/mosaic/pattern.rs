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
        let (w, h) = (self.width, self.height());
        let mask: Vec<bool> = self.pixels.iter().map(|&p| p == index).collect();
        let spans = Spans::of(&mask, w);
        let (runs, count) = self.runs(&spans);
        let rows = Lines::rows(&mask, w, h);
        Figures {
            patches: self.patches(&spans),
            runs_per_row: runs as f64 / h.max(1) as f64,
            width: if runs == 0 {
                0.0
            } else {
                count as f64 * self.unit[0] / runs as f64
            },
            correlation: [
                self.correlation(&rows.columns(w, h), count, 0),
                self.correlation(&rows, count, 1),
            ],
        }
    }

    /// The runs along the rows (one across the seam of a wrapping row
    /// counted once), and the pixels.
    fn runs(&self, spans: &Spans) -> (usize, usize) {
        let count = spans.spans.iter().map(|&(start, end)| end - start).sum();
        let mut runs = 0;
        for y in 0..spans.rows() {
            let row = spans.row(y);
            let whole = row.len() == 1 && row[0] == (0, self.width);
            let joined = self.periodic[0]
                && !whole
                && row.first().is_some_and(|r| r.0 == 0)
                && row.last().is_some_and(|r| r.1 == self.width);
            runs += row.len() - usize::from(joined);
        }
        (runs, count)
    }

    /// The separate patches of `mask`: 4-connected, joined across the
    /// seams where the domain wraps. Row by row: each run of a row is
    /// joined to the runs it touches in the row below (the last row's to
    /// the first's where v wraps) and, where u wraps, a row's last run to
    /// its first; a patch is a set of runs so joined.
    fn patches(&self, spans: &Spans) -> u32 {
        let (w, runs) = (self.width, &spans.spans);
        let mut sets = Sets::new(runs.len());
        let h = spans.rows();
        for y in 0..h {
            let here = spans.range(y);
            if self.periodic[0] && here.len() > 1 {
                let (head, tail) = (here.start, here.end - 1);
                if runs[head].0 == 0 && runs[tail].1 == w {
                    sets.join(head, tail);
                }
            }
            let below = if y + 1 < h {
                spans.range(y + 1)
            } else if self.periodic[1] {
                spans.range(0)
            } else {
                continue;
            };
            // Runs that share a column, in one pass over both rows.
            let (mut i, mut j) = (here.start, below.start);
            while i < here.end && j < below.end {
                let (a, b) = (runs[i], runs[j]);
                if a.0 < b.1 && b.0 < a.1 {
                    sets.join(i, j);
                }
                if a.1 <= b.1 {
                    i += 1;
                } else {
                    j += 1;
                }
            }
        }
        sets.count
    }

    /// The correlation length along `axis` (0: u, 1: v) of a mask of
    /// `count` pixels given as its `lines` along that axis (its columns
    /// for u, its rows for v): the pixels a lag apart that are both in
    /// it, counted a word of a line at a time.
    fn correlation(&self, lines: &Lines, count: usize, axis: usize) -> f64 {
        let (w, h) = (self.width, self.height());
        let n = self.pixels.len().max(1) as f64;
        let mean = count as f64 / n;
        let variance = mean * (1.0 - mean);
        let (side, across) = if axis == 0 { (w, h) } else { (h, w) };
        if variance <= 0.0 {
            return 0.0;
        }
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

/// Transposes a 64 × 64 bit matrix, word i its row i and bit j its column
/// j: afterwards word j holds column j, bit i its row i (halves, quarters
/// and so on swapped across the diagonal: six rounds of 32 swaps).
fn transpose(block: &mut [u64; 64]) {
    let (mut width, mut mask) = (32, 0x0000_0000_ffff_ffffu64);
    while width != 0 {
        let mut k = 0;
        while k < 64 {
            // Row k's high part and row k + width's low part trade places.
            let t = ((block[k] >> width) ^ block[k + width]) & mask;
            block[k] ^= t << width;
            block[k + width] ^= t;
            k = (k + width + 1) & !width;
        }
        width >>= 1;
        mask ^= mask << width;
    }
}

/// A mask's runs along its rows, [start, end) each, row after row.
struct Spans {
    spans: Vec<(usize, usize)>,
    /// Where each row's runs begin, and one past the last row's.
    first: Vec<usize>,
}

impl Spans {
    /// The runs of a mask `w` pixels wide.
    fn of(mask: &[bool], w: usize) -> Spans {
        let mut spans = Vec::new();
        let mut first = vec![0];
        if w > 0 {
            for row in mask.chunks_exact(w) {
                let mut x = 0;
                while let Some(start) = row[x..].iter().position(|&m| m).map(|k| x + k) {
                    let end = row[start..]
                        .iter()
                        .position(|&m| !m)
                        .map_or(w, |k| start + k);
                    spans.push((start, end));
                    x = end;
                }
                first.push(spans.len());
            }
        }
        Spans { spans, first }
    }

    fn rows(&self) -> usize {
        self.first.len() - 1
    }

    /// The indices of row `y`'s runs.
    fn range(&self, y: usize) -> std::ops::Range<usize> {
        self.first[y]..self.first[y + 1]
    }

    fn row(&self, y: usize) -> &[(usize, usize)] {
        &self.spans[self.range(y)]
    }
}

/// Disjoint sets of runs (union–find with path halving), and how many.
struct Sets {
    parent: Vec<usize>,
    count: u32,
}

impl Sets {
    fn new(n: usize) -> Sets {
        Sets {
            parent: (0..n).collect(),
            count: n as u32,
        }
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    fn join(&mut self, a: usize, b: usize) {
        let (a, b) = (self.root(a), self.root(b));
        if a != b {
            self.parent[a.max(b)] = a.min(b);
            self.count -= 1;
        }
    }
}

/// A mask's lines along one axis as bits, 64 pixels a word: its columns
/// (axis 0: each column's pixels down the rows) or its rows (axis 1).
struct Lines {
    words_per_line: usize,
    words: Vec<u64>,
}

impl Lines {
    /// The rows of a `w` × `h` mask, 64 pixels a word, the first pixel in
    /// the lowest bit.
    fn rows(mask: &[bool], w: usize, h: usize) -> Lines {
        let per_row = w.div_ceil(64);
        let mut words = vec![0u64; h * per_row];
        if w > 0 {
            for (row, line) in mask.chunks_exact(w).zip(words.chunks_exact_mut(per_row)) {
                for (pixels, word) in row.chunks(64).zip(line) {
                    *word = pixels
                        .iter()
                        .rev()
                        .fold(0, |bits, &m| bits << 1 | u64::from(m));
                }
            }
        }
        Lines {
            words_per_line: per_row,
            words,
        }
    }

    /// The columns of the mask whose rows (`w` × `h`) these are: each
    /// 64 × 64 block of bits transposed.
    fn columns(&self, w: usize, h: usize) -> Lines {
        let (per_row, per_column) = (self.words_per_line, h.div_ceil(64));
        let mut words = vec![0u64; w * per_column];
        for row_block in 0..per_column {
            for column_block in 0..per_row {
                let mut block = [0u64; 64];
                for (i, bits) in block.iter_mut().enumerate() {
                    let y = row_block * 64 + i;
                    if y < h {
                        *bits = self.words[y * per_row + column_block];
                    }
                }
                transpose(&mut block);
                for (j, &bits) in block.iter().enumerate() {
                    let x = column_block * 64 + j;
                    if x < w {
                        words[x * per_column + row_block] = bits;
                    }
                }
            }
        }
        Lines {
            words_per_line: per_column,
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

    /// A xorshift generator from `state` (not zero).
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

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

    /// [`Raster::correlation`] of a mask.
    fn correlation_of(raster: &Raster<'_>, mask: &[bool], axis: usize) -> f64 {
        let (w, h) = (raster.width, raster.height());
        let rows = Lines::rows(mask, w, h);
        let lines = if axis == 0 { rows.columns(w, h) } else { rows };
        let count = mask.iter().filter(|&&m| m).count();
        raster.correlation(&lines, count, axis)
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
        let mut next = xorshift(0x2545_f491_4f6c_dd1du64);
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
                        correlation_of(&raster, &mask, axis),
                        correlation_by_pixels(&raster, &mask, axis),
                        "{w} x {h}, {periodic:?}, axis {axis}"
                    );
                }
            }
        }
    }

    /// The patches of `mask` pixel by pixel, by flood fill.
    fn patches_by_flood(raster: &Raster<'_>, mask: &[bool]) -> u32 {
        let (w, h) = (raster.width, raster.height());
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
                } else if raster.periodic[0] {
                    visit(i + 1 - w);
                }
                if x > 0 {
                    visit(i - 1);
                } else if raster.periodic[0] {
                    visit(i + w - 1);
                }
                if y + 1 < h {
                    visit(i + w);
                } else if raster.periodic[1] {
                    visit(x);
                }
                if y > 0 {
                    visit(i - w);
                } else if raster.periodic[1] {
                    visit((h - 1) * w + x);
                }
            }
        }
        patches
    }

    /// The runs along the rows and the pixels, pixel by pixel.
    fn runs_by_pixels(raster: &Raster<'_>, mask: &[bool]) -> (usize, usize) {
        let (mut runs, mut count) = (0, 0);
        for row in mask.chunks(raster.width.max(1)) {
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
            let joined = raster.periodic[0] && row[0] && row[row.len() - 1];
            runs += starts - usize::from(joined);
        }
        (runs, count)
    }

    #[test]
    fn runs_and_patches_by_spans_are_the_pixel_by_pixel_ones() {
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15u64);
        for (w, h) in [
            (1, 1),
            (1, 7),
            (7, 1),
            (2, 2),
            (37, 23),
            (64, 64),
            (130, 70),
            (200, 9),
        ] {
            for density in [1, 3, 5, 7] {
                let pixels: Vec<u8> = (0..w * h).map(|_| u8::from(next() % 8 < density)).collect();
                for periodic in [[false, false], [true, false], [false, true], [true, true]] {
                    let raster = Raster {
                        pixels: &pixels,
                        width: w,
                        unit: [1.0, 1.0],
                        periodic,
                    };
                    for index in [0, 1] {
                        let mask: Vec<bool> = pixels.iter().map(|&p| p == index).collect();
                        assert_eq!(
                            raster.runs(&Spans::of(&mask, w)),
                            runs_by_pixels(&raster, &mask)
                        );
                        assert_eq!(
                            raster.patches(&Spans::of(&mask, w)),
                            patches_by_flood(&raster, &mask),
                            "{w} x {h}, density {density}/8, {periodic:?}, index {index}"
                        );
                    }
                }
            }
        }
    }

    /// A mask's lines as bits, pixel by pixel.
    fn lines_by_pixels(mask: &[bool], w: usize, h: usize, axis: usize) -> Lines {
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

    #[test]
    fn lines_by_words_are_the_pixel_by_pixel_ones() {
        let mut next = xorshift(0x2545_f491_4f6c_dd1du64);
        for (w, h) in [
            (1, 1),
            (1, 70),
            (70, 1),
            (37, 23),
            (64, 64),
            (130, 70),
            (200, 129),
        ] {
            let mask: Vec<bool> = (0..w * h).map(|_| next().is_multiple_of(3)).collect();
            for axis in [0, 1] {
                let rows = Lines::rows(&mask, w, h);
                let fast = if axis == 0 { rows.columns(w, h) } else { rows };
                let slow = lines_by_pixels(&mask, w, h, axis);
                assert_eq!(fast.words_per_line, slow.words_per_line);
                assert_eq!(fast.words, slow.words, "{w} x {h}, axis {axis}");
            }
        }
    }
}
