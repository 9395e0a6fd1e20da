//! A day's type borders on a mesh for `plot.svg`, seen as the pictures see
//! the object ([`super::view::axes`]): each face turned towards the viewer
//! is split into small triangles, about a third of the cells' spacing
//! across; where their corners' nearest cells differ in type, the border
//! runs between the midpoints of their sides (marching triangles). With
//! the object's outline. Borders on faces hidden behind others are drawn
//! too (a convex object hides none).

use std::collections::BTreeMap;

use nalgebra::Vector3;

use super::Shell;
use super::nearest::{Along, Nearest};
use crate::outputs::plot::{self, Drawing, Pen};

/// The most parts a face's side is split into.
const MOST_PARTS: usize = 32;

/// The type borders of the cells `near` finds on `shell` (`cells` of
/// them), seen along `axes` (right, up, towards the viewer), and its
/// outline.
pub(super) fn drawing(
    shell: &Shell,
    near: &Nearest,
    cells: usize,
    axes: [Vector3<f64>; 3],
) -> Drawing {
    let screen: Vec<[f64; 3]> = shell
        .vertices
        .iter()
        .map(|&p| axes.map(|a| a.dot(&Vector3::from(p))))
        .collect();
    let outline = plot::silhouette(&screen, &shell.faces);
    // Faces wound inwards turn towards the viewer when they seem turned away.
    let volume: f64 = shell
        .faces
        .iter()
        .map(|f| {
            let [a, b, c] = shell.corners(f).map(Vector3::from);
            a.dot(&b.cross(&c))
        })
        .sum();
    let outward = if volume < 0.0 { -1.0 } else { 1.0 };
    let area: f64 = shell
        .faces
        .iter()
        .map(|f| face_area(&shell.corners(f)))
        .sum();
    let spacing = (area / cells.max(1) as f64).sqrt();
    let mut borders = Borders::default();
    let mut along = Along::new(near);
    for f in &shell.faces {
        let corners = shell.corners(f);
        let [a, b, c] = corners.map(Vector3::from);
        if outward * (b - a).cross(&(c - a)).dot(&axes[2]) <= 0.0 {
            continue;
        }
        let longest = [(b - a).norm(), (c - b).norm(), (a - c).norm()]
            .into_iter()
            .fold(0.0, f64::max);
        let parts = ((3.0 * longest / spacing.max(1e-12)).ceil() as usize).clamp(1, MOST_PARTS);
        borders.face(&corners, parts, &mut along);
    }
    let project = |p: [f64; 3]| {
        let p = Vector3::from(p);
        [axes[0].dot(&p), axes[1].dot(&p)]
    };
    let points: Vec<[f64; 2]> = borders.points.iter().map(|&p| project(p)).collect();
    Drawing {
        pens: vec![
            Pen {
                name: "type borders".into(),
                colour: [30, 30, 30],
                strokes: plot::chains(&points, borders.edges),
            },
            Pen {
                name: "outline".into(),
                colour: [120, 120, 120],
                strokes: outline,
            },
        ],
    }
}

fn face_area(corners: &[[f64; 3]; 3]) -> f64 {
    let [a, b, c] = corners.map(Vector3::from);
    (b - a).cross(&(c - a)).norm() / 2.0
}

/// The border's pieces: points (each once, to a millionth of a unit, so
/// that neighbouring faces' pieces meet) and the edges between them.
#[derive(Debug, Default)]
struct Borders {
    points: Vec<[f64; 3]>,
    index: BTreeMap<[i64; 3], u32>,
    edges: Vec<[u32; 2]>,
}

impl Borders {
    /// The index of point `p`, added when new.
    fn point(&mut self, p: [f64; 3]) -> u32 {
        let next = self.points.len() as u32;
        let key = p.map(|v| (v * 1e6).round() as i64);
        let k = *self.index.entry(key).or_insert(next);
        if k == next {
            self.points.push(p);
        }
        k
    }

    /// The border across the face with `corners`, its sides split into
    /// `parts`: on each small triangle whose corners are of two types, a
    /// piece between the midpoints of its two sides that change type; of
    /// three types, a piece from each side's midpoint to its centre.
    fn face(&mut self, corners: &[[f64; 3]; 3], parts: usize, along: &mut Along<'_>) {
        let [a, b, c] = corners.map(Vector3::from);
        let n = parts as f64;
        let at = |i: usize, j: usize| -> [f64; 3] {
            let (u, v) = (i as f64 / n, j as f64 / n);
            (a + (b - a) * u + (c - a) * v).into()
        };
        // Each grid point's type, row by row (i + j ≤ parts).
        let mut kinds = BTreeMap::new();
        for i in 0..=parts {
            for j in 0..=parts - i {
                kinds.insert((i, j), along.kind_at(&at(i, j)));
            }
        }
        for i in 0..parts {
            for j in 0..parts - i {
                self.triangle([(i, j), (i + 1, j), (i, j + 1)], &kinds, &at);
                if i + j + 2 <= parts {
                    self.triangle([(i + 1, j), (i + 1, j + 1), (i, j + 1)], &kinds, &at);
                }
            }
        }
    }

    /// One small triangle's piece of the border ([`Borders::face`]).
    fn triangle(
        &mut self,
        grid: [(usize, usize); 3],
        kinds: &BTreeMap<(usize, usize), Option<u8>>,
        at: &impl Fn(usize, usize) -> [f64; 3],
    ) {
        let kind = grid.map(|g| kinds.get(&g).copied().flatten());
        let p = grid.map(|(i, j)| Vector3::from(at(i, j)));
        let mid = |x: usize, y: usize| -> [f64; 3] { ((p[x] + p[y]) / 2.0).into() };
        let changes: Vec<(usize, usize)> = [(0, 1), (1, 2), (2, 0)]
            .into_iter()
            .filter(|&(x, y)| kind[x] != kind[y])
            .collect();
        match changes.as_slice() {
            [(x0, y0), (x1, y1)] => {
                let e = [self.point(mid(*x0, *y0)), self.point(mid(*x1, *y1))];
                self.edges.push(e);
            }
            [_, _, _] => {
                let centre = self.point(((p[0] + p[1] + p[2]) / 3.0).into());
                for (x, y) in changes {
                    let e = [self.point(mid(x, y)), centre];
                    self.edges.push(e);
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outputs::mosaic::on_mesh::view;

    /// The unit octahedron, its faces wound outwards.
    fn octahedron() -> Shell {
        Shell {
            vertices: vec![
                [1.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
            ],
            faces: vec![
                [0, 2, 4],
                [2, 1, 4],
                [1, 3, 4],
                [3, 0, 4],
                [2, 0, 5],
                [1, 2, 5],
                [3, 1, 5],
                [0, 3, 5],
            ],
        }
    }

    #[test]
    fn two_caps_of_two_types_meet_on_the_equator_seen_in_front() {
        let shell = octahedron();
        let caps = [(0, 0, [0.0, 0.0, 1.0]), (1, 1, [0.0, 0.0, -1.0])];
        let near = Nearest::new(&caps, &shell);
        let d = drawing(&shell, &near, 2, view::axes(0.35));
        // The equator's front half: one stroke, level (z = 0 seen from
        // above it), from near the left of the outline to near its right
        // (the border ends on the middle of the last small triangle).
        let borders = &d.pens[0].strokes;
        assert_eq!(borders.len(), 1, "{borders:?}");
        let xs: Vec<f64> = borders[0].points.iter().map(|p| p[0]).collect();
        let (lo, hi) = xs
            .iter()
            .fold((1.0f64, -1.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        assert!(lo < -0.8 && hi > 0.8, "{lo} {hi}");
        assert_eq!(
            d.pens[1].strokes.len(),
            1,
            "the outline is one closed stroke"
        );
        // One type all over: no border.
        let one = [(0, 0, [0.0, 0.0, 1.0]), (1, 0, [0.0, 0.0, -1.0])];
        let d = drawing(&shell, &Nearest::new(&one, &shell), 2, view::axes(0.35));
        assert!(d.pens[0].strokes.is_empty());
    }
}
