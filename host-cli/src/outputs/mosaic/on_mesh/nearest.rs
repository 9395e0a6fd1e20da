//! The nearest cell of any point of a surface mosaic's object: a uniform
//! grid of cubes, searched shell by shell, and the cells that may be
//! nearest to the points of a box.

use super::Shell;
use nalgebra::Vector3;

/// The most cubes [`Nearest::near_box`] gathers cells from.
const BOX_CUBES: i64 = 4_096;
/// The most cubes of the nearest-cell search per cell ([`Nearest`]).
const CUBES_PER_CELL: i64 = 8;

/// The nearest cell of any point, through a uniform grid of cubes.
pub(super) struct Nearest {
    lo: [f64; 3],
    side: f64,
    dims: [i64; 3],
    /// `(index in the day's list, type, point)` of the cells, cube by cube
    /// (x fastest), and each cube's start in it.
    sorted: Vec<(u32, u8, [f64; 3])>,
    starts: Vec<u32>,
}

impl Nearest {
    pub(super) fn new(cells: &[(u32, u8, [f64; 3])], shell: &Shell) -> Nearest {
        let mut lo = [f64::MAX; 3];
        let mut hi = [f64::MIN; 3];
        for p in shell.vertices.iter().chain(cells.iter().map(|c| &c.2)) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let extent: f64 = (0..3).map(|k| (hi[k] - lo[k]).max(1e-9)).product::<f64>();
        // About one cell per cube the surface crosses: cubes of the cells'
        // spacing, the surface's area guessed from the extent; but no more
        // than [`CUBES_PER_CELL`] cubes a cell (a surface crosses few of
        // them, and many cells make many empty ones).
        let area_guess = extent.powf(2.0 / 3.0) * 3.0;
        let mut side = (area_guess / cells.len().max(1) as f64).sqrt().max(1e-6);
        let most = CUBES_PER_CELL * cells.len() as i64 + 4_096;
        let dims = loop {
            let dims =
                [0, 1, 2].map(|k| (((hi[k] - lo[k]) / side).floor() as i64 + 1).clamp(1, 1 << 10));
            let count = dims[0] * dims[1] * dims[2];
            if count <= most {
                break dims;
            }
            side *= (count as f64 / most as f64).cbrt().max(1.01);
        };
        let count = (dims[0] * dims[1] * dims[2]) as usize;
        let mut starts = vec![0u32; count + 1];
        let cube = |p: &[f64; 3]| Self::cube_of(lo, side, dims, p);
        for c in cells {
            starts[cube(&c.2) + 1] += 1;
        }
        for k in 1..=count {
            starts[k] += starts[k - 1];
        }
        let mut fill = starts.clone();
        let mut sorted = vec![(0, 0, [0.0; 3]); cells.len()];
        for (i, c) in cells.iter().enumerate() {
            let k = cube(&c.2);
            sorted[fill[k] as usize] = (i as u32, c.1, c.2);
            fill[k] += 1;
        }
        Nearest {
            lo,
            side,
            dims,
            sorted,
            starts,
        }
    }

    fn index(lo: [f64; 3], side: f64, dims: [i64; 3], p: &[f64; 3]) -> [i64; 3] {
        // `as` rounds towards 0: the floor, for all that is not clamped to 0.
        [0, 1, 2].map(|k| (((p[k] - lo[k]) / side) as i64).clamp(0, dims[k] - 1))
    }

    fn cube_of(lo: [f64; 3], side: f64, dims: [i64; 3], p: &[f64; 3]) -> usize {
        let [x, y, z] = Self::index(lo, side, dims, p);
        ((z * dims[1] + y) * dims[0] + x) as usize
    }

    /// The type of the cell nearest `p`, the lowest-numbered of equally
    /// near ones (so the answer does not depend on the cubes): the cubes
    /// next to `p`'s first, then one shell of cubes further out at a time,
    /// until the nearest cell found is nearer than any cube not yet
    /// searched.
    pub(super) fn kind_at(&self, p: &[f64; 3]) -> Option<u8> {
        self.kind_near(p).map(|n| n.kind)
    }

    /// [`Nearest::kind_at`], and how far from `p` the nearest cell stays
    /// of that type: half the difference between the nearest distance d₁
    /// and a bound d₂ below the distance of every cell of another type,
    /// since a point q with 2·|q − p| < d₂ − d₁ is nearer to this cell
    /// (d₁ + |q − p|) than to any of those (d₂ − |q − p|). Across a patch
    /// of one type that is far more than the distance the cell itself
    /// stays the nearest. 0 when cells of two types are equally near.
    fn kind_near(&self, p: &[f64; 3]) -> Option<Nearby> {
        let at = Self::index(self.lo, self.side, self.dims, p);
        let mut found = Found {
            best: (f64::INFINITY, u32::MAX, 0),
            at: [0.0; 3],
            other: f64::INFINITY,
        };
        let mut gap = f64::MAX;
        for reach in 1..=self.dims.iter().copied().max().unwrap_or(1) {
            let [x0, y0, z0] = [0, 1, 2].map(|k| (at[k] - reach).max(0));
            let [x1, y1, z1] = [0, 1, 2].map(|k| (at[k] + reach).min(self.dims[k] - 1));
            for z in z0..=z1 {
                for y in y0..=y1 {
                    if reach == 1 || (z - at[2]).abs() == reach || (y - at[1]).abs() == reach {
                        // The whole first box, or a face of a shell.
                        found.scan(self.run(x0, x1, y, z), p);
                    } else {
                        // Inside the shell's faces: its two ends, the cubes
                        // between them searched before.
                        if at[0] - reach >= 0 {
                            found.scan(self.run(x0, x0, y, z), p);
                        }
                        if at[0] + reach < self.dims[0] {
                            found.scan(self.run(x1, x1, y, z), p);
                        }
                    }
                }
            }
            // Every cell not yet seen lies in a cube beyond the box searched,
            // at least `gap` from p (less a margin for rounding): done when
            // the nearest found is nearer.
            gap = f64::MAX;
            for k in 0..3 {
                if at[k] - reach > 0 {
                    gap = gap.min(p[k] - (self.lo[k] + (at[k] - reach) as f64 * self.side));
                }
                if at[k] + reach + 1 < self.dims[k] {
                    gap = gap.min(self.lo[k] + (at[k] + reach + 1) as f64 * self.side - p[k]);
                }
            }
            if gap == f64::MAX {
                break; // every cube searched
            }
            gap = (gap - 1e-9 * self.side).max(0.0);
            if found.best.0 < gap * gap {
                break;
            }
        }
        let (d, i, kind) = found.best;
        (i != u32::MAX).then(|| {
            let others = found.other.sqrt().min(gap);
            Nearby {
                kind,
                stays: ((others - d.sqrt()) / 2.0 - 1e-9 * self.side).max(0.0),
                distance: d.sqrt(),
                cell: found.at,
                others: others - 2e-9 * self.side,
            }
        })
    }

    /// Which cells may be the nearest of the points in the box `lo`–`hi`
    /// (into `out`, by index), or the one type they all have. Every
    /// point q of the box is within r = d + h of the cell nearest its
    /// centre g (at d; h half the box's diagonal), so q's nearest cell is
    /// within r of the box: those cells, gathered from the cubes the box
    /// widened by r touches. A widened box of more than [`BOX_CUBES`]
    /// cubes is not searched.
    pub(super) fn near_box(&self, lo: [f64; 3], hi: [f64; 3], out: &mut Vec<Cell>) -> Reach {
        out.clear();
        let g = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        let Some(near) = self.kind_near(&g) else {
            return Reach::One(None);
        };
        let half = (Vector3::from(hi) - Vector3::from(lo)).norm() / 2.0;
        if near.stays > half * (1.0 + 1e-9) + self.margin() {
            return Reach::One(Some(near.kind)); // the whole box is within `stays`
        }
        let reach = (near.distance + half) * (1.0 + 1e-9) + self.margin();
        let [x0, y0, z0] = Self::index(
            self.lo,
            self.side,
            self.dims,
            &[0, 1, 2].map(|k| lo[k] - reach),
        );
        let [x1, y1, z1] = Self::index(
            self.lo,
            self.side,
            self.dims,
            &[0, 1, 2].map(|k| hi[k] + reach),
        );
        if (x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1) > BOX_CUBES {
            return Reach::Far;
        }
        for z in z0..=z1 {
            for y in y0..=y1 {
                out.extend(
                    self.run(x0, x1, y, z)
                        .iter()
                        .filter(|c| within(&c.2, lo, hi, reach)),
                );
            }
        }
        Reach::among(out)
    }

    /// [`Nearest::near_box`] for a box inside one whose cells `wider`
    /// may be the nearest of its points: those of them that may be the
    /// nearest of this box's points, the nearest of its centre found
    /// among them.
    pub(super) fn narrow(
        &self,
        wider: &[Cell],
        lo: [f64; 3],
        hi: [f64; 3],
        out: &mut Vec<Cell>,
    ) -> Reach {
        out.clear();
        let g = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        let Some(d2) = nearest_among(wider, &g).map(|(d2, _)| d2) else {
            return Reach::One(None);
        };
        let half = (Vector3::from(hi) - Vector3::from(lo)).norm() / 2.0;
        let reach = (d2.sqrt() + half) * (1.0 + 1e-9) + self.margin();
        out.extend(wider.iter().filter(|c| within(&c.2, lo, hi, reach)));
        Reach::among(out)
    }

    /// A margin for rounding in distances.
    fn margin(&self) -> f64 {
        1e-6 * self.side
    }

    /// The cells of cubes `x0..=x1` of row (y, z): one run of `sorted`.
    fn run(&self, x0: i64, x1: i64, y: i64, z: i64) -> &[(u32, u8, [f64; 3])] {
        let row = (z * self.dims[1] + y) * self.dims[0];
        let from = self.starts[(row + x0) as usize] as usize;
        &self.sorted[from..self.starts[(row + x1) as usize + 1] as usize]
    }
}

/// A cell of a day: its index in the day's list, type and point.
pub(super) type Cell = (u32, u8, [f64; 3]);

/// What [`Nearest::near_box`] found for a box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Reach {
    /// Every point of the box has this nearest type (`None`: there are no
    /// cells).
    One(Option<u8>),
    /// The nearest cell of every point is among those gathered.
    Among,
    /// Too many cubes to gather the cells from.
    Far,
}

impl Reach {
    /// `Among` the cells `near`, or the `One` type they all have.
    fn among(near: &[Cell]) -> Reach {
        match near.split_first() {
            Some((first, rest)) if rest.iter().any(|c| c.1 != first.1) => Reach::Among,
            Some((first, _)) => Reach::One(Some(first.1)),
            // Never (the centre's nearest is within reach); if rounding
            // ever left it out, a search per pixel.
            None => Reach::Far,
        }
    }
}

/// Whether `p` is within `reach` of the box `lo`–`hi`.
fn within(p: &[f64; 3], lo: [f64; 3], hi: [f64; 3], reach: f64) -> bool {
    let d = Vector3::from([0, 1, 2].map(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0)));
    d.norm_squared() <= reach * reach
}

/// The squared distance and type of the cell of `cells` nearest `p`, the
/// lowest-numbered of equally near ones.
/// Without branches on which is nearer: as for the plane's pictures, a
/// branch mispredicted for many cells cost more than the comparisons.
pub(super) fn nearest_among(cells: &[Cell], p: &[f64; 3]) -> Option<(f64, u8)> {
    let d2 = |c: &[f64; 3]| (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2);
    let (&(mut at, mut kind, c), rest) = cells.split_first()?;
    let mut best = d2(&c);
    for &(i, k, c) in rest {
        let d = d2(&c);
        // All ones where this cell wins.
        let nearer = u32::from((d < best) | ((d == best) & (i < at))).wrapping_neg();
        at = (at & !nearer) | (i & nearer);
        kind = (kind & !nearer as u8) | (k & nearer as u8);
        best = best.min(d);
    }
    Some((best, kind))
}

/// [`Nearest::kind_at`] for points one after another, each near the one
/// before, with a search only where the last search's answer may not
/// hold ([`Known::kind_at`]).
pub(super) struct Along<'n> {
    near: &'n Nearest,
    known: Option<Known>,
}

impl<'n> Along<'n> {
    pub(super) fn new(near: &'n Nearest) -> Along<'n> {
        Along { near, known: None }
    }

    pub(super) fn kind_at(&mut self, p: &[f64; 3]) -> Option<u8> {
        if let Some(kind) = self.known.as_ref().and_then(|k| k.kind_at(p)) {
            return Some(kind);
        }
        let found = self.near.kind_near(p)?;
        self.known = Some(Known { at: *p, found });
        Some(found.kind)
    }
}

/// A search's answer at a point, and where it holds.
struct Known {
    /// The point searched, q.
    at: [f64; 3],
    found: Nearby,
}

impl Known {
    /// The type of the cell nearest `p`, if it is the one found at q:
    /// when `p` is within the distance that type stays the nearest's, or
    /// nearer to the cell found than any cell of another type can be
    /// (those were at least `others` from q, so at least `others` −
    /// |p − q| from p).
    fn kind_at(&self, p: &[f64; 3]) -> Option<u8> {
        let found = &self.found;
        let moved = (Vector3::from(*p) - Vector3::from(self.at)).norm_squared();
        if moved < found.stays * found.stays {
            return Some(found.kind);
        }
        let to_cell = (Vector3::from(*p) - Vector3::from(found.cell)).norm();
        (to_cell + moved.sqrt() < found.others).then_some(found.kind)
    }
}

/// What [`Nearest::kind_near`] found for a point.
#[derive(Debug, Clone, Copy)]
struct Nearby {
    /// The nearest cell's type.
    kind: u8,
    /// How far from the point the nearest cell stays of that type.
    stays: f64,
    /// The nearest cell's distance.
    distance: f64,
    /// The nearest cell's point.
    cell: [f64; 3],
    /// A bound below the distance of every cell of another type, less a
    /// margin for rounding.
    others: f64,
}

/// What a search of [`Nearest::kind_near`] has found so far.
struct Found {
    /// (squared distance, index, type) of the nearest cell; no index: none.
    best: (f64, u32, u8),
    /// The nearest cell's point.
    at: [f64; 3],
    /// The squared distance of the nearest cell of another type than
    /// `best`'s.
    other: f64,
}

impl Found {
    /// Takes in the cells `run` (from `sorted`) for the point `p`.
    fn scan(&mut self, run: &[(u32, u8, [f64; 3])], p: &[f64; 3]) {
        for &(i, kind, c) in run {
            let d = (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2);
            if d < self.best.0 || (d == self.best.0 && i < self.best.1) {
                // The old nearest was nearer than every other cell seen.
                if kind != self.best.2 {
                    self.other = self.best.0;
                }
                self.best = (d, i, kind);
                self.at = c;
            } else if d < self.other && kind != self.best.2 {
                self.other = d;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` cells on a sphere of `radius` (a Fibonacci lattice), cell i of
    /// type `kind(i, point)`.
    fn sphere(n: u32, radius: f64, kind: impl Fn(u32, [f64; 3]) -> u8) -> Vec<Cell> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / f64::from(n);
                let r = (1.0 - z * z).sqrt();
                let a = f64::from(i) * 2.399_963;
                let p = [r * a.cos(), r * a.sin(), z].map(|x| radius * x);
                (i, kind(i, p), p)
            })
            .collect()
    }

    /// The `t`-th of a set of points spread through the box of ±`radius`
    /// in x and y and ±`height` in z around the origin.
    fn probe(t: f64, radius: f64, height: f64) -> [f64; 3] {
        [
            radius * (t * 0.731).sin(),
            radius * (t * 1.113).cos(),
            height * (t * 0.377).sin(),
        ]
    }

    /// Three patches of one type each, by longitude.
    fn patch(p: [f64; 3]) -> u8 {
        ((p[1].atan2(p[0]) + 3.2) / 2.2) as u8
    }

    /// The nearest cell by looking at every one, the lowest-numbered of
    /// equally near ones.
    fn nearest_of_all(cells: &[(u32, u8, [f64; 3])], p: &[f64; 3]) -> Option<u8> {
        // A plain loop, quick in a debug build: the tests ask it about
        // hundreds of thousands of points.
        let mut best: Option<(f64, u8)> = None;
        for &(_, kind, c) in cells {
            let e = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
            let d = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, kind));
            }
        }
        best.map(|(_, kind)| kind)
    }

    #[test]
    fn the_grid_finds_the_nearest_cell_of_every_point() {
        // Cells on a sphere of radius 10 (a Fibonacci lattice), each type
        // its index mod 7, and pairs of cells at one place (ties); points
        // on, inside and far outside it.
        let n = 600;
        let mut cells = sphere(n, 10.0, |i, _| (i % 7) as u8);
        for i in 0..50 {
            let twin = cells[i * 11].2;
            cells.push((n + i as u32, 6 - (i % 7) as u8, twin));
        }
        let shell = Shell::default();
        let near = Nearest::new(&cells, &shell);
        for i in 0..4_000u32 {
            let t = f64::from(i);
            let scale = [1.0, 0.3, 1.7, 6.0][i as usize % 4];
            let p = probe(t, 10.0 * scale, 10.0 * scale);
            assert_eq!(near.kind_at(&p), nearest_of_all(&cells, &p), "at {p:?}");
        }
        // Within the distance it reports, the nearest cell's type stays
        // the same (points at 0.999 of it, in 8 directions, checked cell
        // by cell).
        let mut stayed = 0;
        for i in 0..2_000u32 {
            let t = f64::from(i);
            let p = probe(t, 10.0, 9.0);
            let Nearby { kind, stays, .. } = near.kind_near(&p).expect("cells");
            for step in [
                [1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.6, 0.8, 0.0],
            ] {
                for sign in [-1.0, 1.0] {
                    let q = [0, 1, 2].map(|k| p[k] + sign * 0.999 * stays * step[k]);
                    assert_eq!(nearest_of_all(&cells, &q), Some(kind), "{q:?} near {p:?}");
                }
            }
            stayed += usize::from(stays > 0.0);
        }
        // All but those nearest to a twin (equally near to both: 0).
        assert!(stayed > 1_700, "{stayed}");
        // Along a path of small steps the answers are the searches'.
        let mut along = Along::new(&near);
        for i in 0..20_000u32 {
            let t = f64::from(i) * 0.0005;
            let p = [
                10.5 * (t * 3.1).sin(),
                10.5 * (t * 2.3).cos(),
                10.0 * (t * 0.7).sin(),
            ];
            assert_eq!(along.kind_at(&p), nearest_of_all(&cells, &p), "at {p:?}");
        }
        // Exactly on the twins: the lower-numbered one.
        for i in 0..50 {
            let at = cells[i * 11];
            assert_eq!(near.kind_at(&at.2), Some(at.1));
        }
        assert_eq!(Nearest::new(&[], &shell).kind_at(&[0.0; 3]), None);
    }

    #[test]
    fn across_a_patch_of_one_type_the_type_stays_further_than_the_cell() {
        // 2,000 cells on a sphere in three patches of one type each (by
        // longitude), with cells of a fourth type sprinkled in.
        let n = 2_000;
        let cells = sphere(n, 5.0, |i, p| if i % 37 == 0 { 3 } else { patch(p) });
        let near = Nearest::new(&cells, &Shell::default());
        let (mut beyond, mut searched) = (0, 0);
        for i in 0..1_500u32 {
            let t = f64::from(i);
            let p = probe(t, 5.0, 4.5);
            let Nearby { kind, stays, .. } = near.kind_near(&p).expect("cells");
            assert_eq!(Some(kind), nearest_of_all(&cells, &p), "at {p:?}");
            // The gap between the nearest cell and the next of any type.
            let mut d: Vec<f64> = cells
                .iter()
                .map(|c| (0..3).map(|k| (c.2[k] - p[k]).powi(2)).sum::<f64>().sqrt())
                .collect();
            d.sort_by(f64::total_cmp);
            searched += 1;
            beyond += usize::from(stays > (d[1] - d[0]) / 2.0 + 1e-6);
            for j in 0..16 {
                let a = f64::from(j) * std::f64::consts::FRAC_PI_8;
                let step = [a.cos(), a.sin() * 0.6, a.sin() * 0.8];
                let q = [0, 1, 2].map(|k| p[k] + 0.999 * stays * step[k]);
                assert_eq!(nearest_of_all(&cells, &q), Some(kind), "{q:?} near {p:?}");
            }
        }
        // Inside the patches, most points' type stays further than the
        // point's nearest cell does.
        assert!(beyond * 2 > searched, "{beyond} of {searched}");
    }

    #[test]
    fn the_cells_gathered_for_a_box_hold_the_nearest_of_its_every_point() {
        // Three patches on a sphere as above; boxes of three sizes around
        // points near it, some flat, and each box's quarters.
        let n = 3_000;
        let cells = sphere(n, 5.0, |_, p| patch(p));
        let near = Nearest::new(&cells, &Shell::default());
        // Every point of a grid in the box, corners included.
        let grid = |lo: [f64; 3], hi: [f64; 3]| {
            (0..7 * 7 * 7).map(move |i| {
                let f = [i % 7, i / 7 % 7, i / 49].map(|x| f64::from(x) / 6.0);
                [0, 1, 2].map(|k| lo[k] + f[k] * (hi[k] - lo[k]))
            })
        };
        let check = |reach: Reach, among: &[Cell], lo, hi| {
            for q in grid(lo, hi) {
                let kind = match reach {
                    Reach::One(kind) => kind,
                    Reach::Among => nearest_among(among, &q).map(|(_, k)| k),
                    Reach::Far => return,
                };
                assert_eq!(nearest_of_all(&cells, &q), kind, "{q:?} in {lo:?}-{hi:?}");
            }
        };
        let (mut one, mut among, mut narrowed) = (0, 0, 0);
        let (mut gathered, mut quarter) = (Vec::new(), Vec::new());
        for i in 0..600u32 {
            let t = f64::from(i);
            let size = [0.05, 0.2, 0.6][i as usize % 3];
            let g = probe(t, 5.0, 4.5);
            let half = [size, size * 0.7, if i % 2 == 0 { 0.0 } else { size * 0.4 }];
            let lo = [0, 1, 2].map(|k| g[k] - half[k]);
            let hi = [0, 1, 2].map(|k| g[k] + half[k]);
            let reach = near.near_box(lo, hi, &mut gathered);
            check(reach, &gathered, lo, hi);
            match reach {
                Reach::One(_) => one += 1,
                Reach::Among => among += 1,
                Reach::Far => {}
            }
            if reach != Reach::Among {
                continue;
            }
            // A quarter of the box (its lower x and y half).
            let qhi = [g[0], g[1], hi[2]];
            let narrow = near.narrow(&gathered, lo, qhi, &mut quarter);
            check(narrow, &quarter, lo, qhi);
            narrowed += usize::from(narrow == Reach::Among && quarter.len() < gathered.len());
        }
        // Most boxes lie inside a patch; the others' quarters need fewer
        // cells.
        assert!(one > 300, "{one} of 600");
        assert!(among > 50 && narrowed * 2 > among, "{among}, {narrowed}");
    }

    #[test]
    fn the_cubes_are_bounded_by_the_cells() {
        // 200,000 cells on a sphere: cubes of the cells' spacing would be
        // 259³, 87 a cell.
        let n = 200_000;
        let cells = sphere(n, 1.0, |_, _| 0);
        let near = Nearest::new(&cells, &Shell::default());
        let cubes = near.starts.len() - 1;
        assert!(
            cubes as i64 <= CUBES_PER_CELL * i64::from(n) + 4_096,
            "{cubes}"
        );
        assert_eq!(near.kind_at(&[0.0, 0.0, 1.5]), Some(0));
    }
}
