//! A day's cell edges for `plot.svg`: the edges of the Voronoi diagram of
//! its cells, the boundaries [`super::voronoi`]'s picture colours between
//! (u to the right, v down). Each cell is placed again beyond every side
//! of the domain — shifted by the domain's size where it wraps, mirrored
//! in the wall where it does not — so that the diagram of them all,
//! clipped to the domain, has the edges of the periodic diagram and the
//! walls themselves.

use anyhow::{Context, Result};
use morphogen::fx::Fx;
use morphogen::fx::Real as _;
use morphogen::mosaic::Domain;
use spade::handles::VoronoiVertex::Inner;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

use crate::outputs::plot::{Drawing, Pen, Stroke};

/// A cell or one of its images, as a site of the diagram.
#[derive(Debug, Clone, Copy)]
struct Site {
    at: Point2<f64>,
    /// The cell's position in the day's list, and its type.
    cell: usize,
    kind: u8,
}

impl HasPosition for Site {
    type Scalar = f64;

    fn position(&self) -> Point2<f64> {
        self.at
    }
}

/// The cell edges of a day's `cells` (`id, type, u, v`) on `domain`: pen 1
/// the borders of the picture's colours (between cells of two types, and
/// the walls), pen 2 the edges between cells of one type.
///
/// # Errors
/// When a cell's place cannot be triangulated (not a number).
pub(super) fn drawing(domain: &Domain, cells: &[(u32, u8, Fx, Fx)]) -> Result<Drawing> {
    let size = domain.size.map(f64::from_fx);
    let image = |x: f64, axis: usize, side: i8| match (side, domain.periodic[axis]) {
        (0, _) => x,
        (s, true) => x + f64::from(s) * size[axis],
        (-1, false) => -x,
        (_, false) => 2.0 * size[axis] - x,
    };
    let mut sites = Vec::with_capacity(9 * cells.len());
    for (cell, &(_, kind, u, v)) in cells.iter().enumerate() {
        let (u, v) = (f64::from_fx(u), f64::from_fx(v));
        for (su, sv) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
            let at = Point2::new(image(u, 0, su), image(v, 1, sv));
            sites.push(Site { at, cell, kind });
        }
    }
    // Loaded at once (sorted round their centre): inserted one by one,
    // each image's search would start a domain away from the last.
    let diagram = DelaunayTriangulation::<Site>::bulk_load(sites)
        .context("the cells' places cannot be triangulated")?;
    // A hair beyond the domain, so that the walls' own edges are kept.
    let tolerance = 1e-9 * size[0].max(size[1]);
    let (mut borders, mut inside) = (Vec::new(), Vec::new());
    for edge in diagram.undirected_voronoi_edges() {
        let [Inner(a), Inner(b)] = edge.vertices() else {
            continue;
        };
        let (a, b) = (a.circumcenter(), b.circumcenter());
        let Some([a, b]) = clip([[a.x, a.y], [b.x, b.y]], size, tolerance) else {
            continue;
        };
        let [p, q] = edge.as_delaunay_edge().vertices().map(|v| *v.data());
        let stroke = Stroke::open(vec![[a[0], -a[1]], [b[0], -b[1]]]);
        if p.kind != q.kind || p.cell == q.cell {
            borders.push(stroke);
        } else {
            inside.push(stroke);
        }
    }
    Ok(Drawing {
        pens: vec![
            Pen {
                name: "type borders".into(),
                colour: [30, 30, 30],
                strokes: borders,
            },
            Pen {
                name: "cell edges".into(),
                colour: [150, 150, 150],
                strokes: inside,
            },
        ],
    })
}

/// The part of the segment `ends` inside the box from the origin to
/// `size`, widened by `tolerance` (Liang–Barsky); `None` when nothing or
/// no more than a few `tolerance`s of it are inside.
fn clip(ends: [[f64; 2]; 2], size: [f64; 2], tolerance: f64) -> Option<[[f64; 2]; 2]> {
    let [a, b] = ends;
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for axis in 0..2 {
        let (lo, hi) = (-tolerance, size[axis] + tolerance);
        if d[axis] == 0.0 {
            if a[axis] < lo || a[axis] > hi {
                return None;
            }
            continue;
        }
        let (mut enter, mut leave) = ((lo - a[axis]) / d[axis], (hi - a[axis]) / d[axis]);
        if enter > leave {
            (enter, leave) = (leave, enter);
        }
        t0 = t0.max(enter);
        t1 = t1.min(leave);
    }
    let at = |t: f64| [a[0] + t * d[0], a[1] + t * d[1]];
    let length = (t1 - t0) * d[0].hypot(d[1]);
    (length > 4.0 * tolerance).then(|| [at(t0), at(t1)])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fx(v: f64) -> Fx {
        Fx::from_bits((v * 65536.0) as i32)
    }

    #[test]
    fn a_grid_of_cells_on_a_torus_has_its_squares_for_edges() {
        // 4 × 4 cells at the centres of unit squares, all of one type but
        // one: every edge a side of a square, the outer ones split where
        // the torus wraps (on the domain's sides) into two halves.
        let cells: Vec<(u32, u8, Fx, Fx)> = (0..16)
            .map(|i| {
                (
                    i,
                    u8::from(i == 5),
                    fx(f64::from(i % 4) + 0.5),
                    fx(f64::from(i / 4) + 0.5),
                )
            })
            .collect();
        let domain = Domain::periodic(fx(4.0), fx(4.0));
        let d = drawing(&domain, &cells).unwrap();
        let strokes: Vec<&Stroke> = d.pens.iter().flat_map(|p| &p.strokes).collect();
        let length: f64 = strokes
            .iter()
            .map(|s| {
                let [a, b] = [s.points[0], s.points[1]];
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .sum();
        // The lines u = 0, 1, …, 4 and v = 0, 1, …, 4, each 4 units long:
        // the torus's seams are drawn on both sides of the picture.
        assert!((length - 40.0).abs() < 1e-6, "{length}");
        // Cell 5's four sides border another type.
        assert_eq!(d.pens[0].strokes.len(), 4);
    }

    #[test]
    fn walls_are_edges_and_clipping_keeps_what_is_inside() {
        let cells = [(0, 0, fx(1.0), fx(1.0)), (1, 0, fx(3.0), fx(1.0))];
        let d = drawing(&Domain::walled(fx(4.0), fx(2.0)), &cells).unwrap();
        // The box's four sides (walls, two of them split between the two
        // cells) and the one edge between them at u = 2.
        assert_eq!(d.pens[0].strokes.len(), 6);
        assert_eq!(d.pens[1].strokes.len(), 1);
        let e = &d.pens[1].strokes[0].points;
        assert!(e.iter().all(|p| (p[0] - 2.0).abs() < 1e-9), "{e:?}");
        assert_eq!(
            clip([[-1.0, 1.0], [5.0, 1.0]], [4.0, 2.0], 0.0),
            Some([[0.0, 1.0], [4.0, 1.0]])
        );
        assert_eq!(clip([[-1.0, 3.0], [5.0, 3.0]], [4.0, 2.0], 0.0), None);
    }
}
