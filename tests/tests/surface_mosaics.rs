//! Mosaics grown on a mesh. For every preset with a `[mosaic.surface]`,
//! from what `morphogen run` writes (`surface.obj`, `cells_dayNN.csv`):
//! - every cell of every streamed day lies on the mesh: its distance to the
//!   nearest triangle is below 10⁻³ of the mesh's size (its bounding box's
//!   diagonal);
//! - after the initial relaxation the cells are spread regularly: the
//!   Clark–Evans index (mean nearest-neighbour distance by 3D distance over
//!   0.5/√density, 1 for random points) is at least 1.4.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use morphogen_tests::release_binary;

const SURFACE_PRESETS: &[&str] = &[
    "watermelon-fruit",
    "watermelon-sphere",
    "watermelon-square",
    "cactus-stem",
    "amanita-mushroom",
    "mushroom",
    "philodendron-leaf",
    "sansevieria-leaf",
];

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The distance from `p` to the triangle `t` (Ericson, Real-Time
/// Collision Detection, 5.1.5: the closest point by Voronoi regions).
fn to_triangle(p: P, [a, b, c]: [P; 3]) -> f64 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = sub(p, b);
        let (d3, d4) = (dot(ab, bp), dot(ac, bp));
        let cp = sub(p, c);
        let (d5, d6) = (dot(ab, cp), dot(ac, cp));
        let (vc, vb, va) = (d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4);
        let along = |o: P, e: P, t: f64| [o[0] + t * e[0], o[1] + t * e[1], o[2] + t * e[2]];
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            along(a, ab, d1 / (d1 - d3))
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            along(a, ac, d2 / (d2 - d6))
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))
        } else {
            let denom = 1.0 / (va + vb + vc);
            let (v, w) = (vb * denom, vc * denom);
            [0, 1, 2].map(|k| a[k] + ab[k] * v + ac[k] * w)
        }
    };
    dot(sub(p, closest), sub(p, closest)).sqrt()
}

/// Items binned by a uniform grid of cubes of side `side`.
struct Bins {
    lo: P,
    side: f64,
    cubes: std::collections::HashMap<[i64; 3], Vec<usize>>,
}

impl Bins {
    fn key(&self, p: P) -> [i64; 3] {
        [0, 1, 2].map(|k| ((p[k] - self.lo[k]) / self.side).floor() as i64)
    }

    /// Items whose boxes `[lo, hi]` are binned into every cube they touch.
    fn new(lo: P, side: f64, boxes: impl Iterator<Item = (P, P)>) -> Bins {
        let mut bins = Bins {
            lo,
            side,
            cubes: Default::default(),
        };
        for (i, (a, b)) in boxes.enumerate() {
            let (ka, kb) = (bins.key(a), bins.key(b));
            for x in ka[0]..=kb[0] {
                for y in ka[1]..=kb[1] {
                    for z in ka[2]..=kb[2] {
                        bins.cubes.entry([x, y, z]).or_default().push(i);
                    }
                }
            }
        }
        bins
    }

    /// The items of the cubes within `reach` cubes of `p`'s.
    fn near(&self, p: P, reach: i64) -> impl Iterator<Item = usize> + '_ {
        let k = self.key(p);
        (-reach..=reach).flat_map(move |x| {
            (-reach..=reach).flat_map(move |y| {
                (-reach..=reach).flat_map(move |z| {
                    self.cubes
                        .get(&[k[0] + x, k[1] + y, k[2] + z])
                        .into_iter()
                        .flatten()
                        .copied()
                })
            })
        })
    }
}

fn read_obj(path: &Path) -> (Vec<P>, Vec<[usize; 3]>) {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let x: Vec<f64> = w.take(3).map(|s| s.parse().unwrap()).collect();
                v.push([x[0], x[1], x[2]]);
            }
            Some("f") => {
                let i: Vec<usize> = w
                    .map(|s| s.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect();
                f.push([i[0], i[1], i[2]]);
            }
            _ => {}
        }
    }
    (v, f)
}

fn read_cells(path: &Path) -> Vec<P> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("id,type,x,y,z"));
    lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').skip(2).map(|s| s.parse().unwrap()).collect();
            [f[0], f[1], f[2]]
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "runs the release binary: run it in a debug build"
)]
fn cells_lie_on_their_mesh_and_start_regularly_spread() {
    let binary = release_binary();
    let tmp = tempfile::tempdir().unwrap();
    // The presets shared among as many threads as there are cores, each
    // taking the next one left.
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut report: Vec<String> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut found = Vec::new();
                    while let Some(name) = SURFACE_PRESETS.get(next.fetch_add(1, Ordering::Relaxed))
                    {
                        found.extend(check(&binary, tmp.path(), name));
                    }
                    found
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    report.sort();
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// What is wrong with surface preset `name`, run by `binary` into a folder
/// of `tmp`: cells off the mesh, or a day 0 less regular than Clark–Evans
/// 1.4.
fn check(binary: &Path, tmp: &Path, name: &str) -> Vec<String> {
    let mut report = Vec::new();
    let out = tmp.join(name);
    let o = Command::new(binary)
        .args(["run", name, "--only", "csv,obj", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (vertices, faces) = read_obj(&out.join("surface.obj"));
    let tri = |f: &[usize; 3]| f.map(|i| vertices[i]);
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for v in &vertices {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    let size = dot(sub(hi, lo), sub(hi, lo)).sqrt();
    let area: f64 = faces
        .iter()
        .map(|f| {
            let [a, b, c] = tri(f);
            dot(cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(c, a))).sqrt() / 2.0
        })
        .sum();
    // Triangles binned by their boxes; a cell within 10⁻³·size of one
    // lies in a cube next to one its box touches.
    let side = (area / faces.len() as f64).sqrt() * 2.0;
    let boxes = faces.iter().map(|f| {
        let t = tri(f);
        let lo = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::MAX, f64::min));
        let hi = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::MIN, f64::max));
        (lo, hi)
    });
    let triangles = Bins::new(lo, side, boxes);
    let mut days: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(|e| {
            let n = e.unwrap().file_name().into_string().unwrap();
            n.starts_with("cells_day").then_some(n)
        })
        .collect();
    days.sort();
    assert!(!days.is_empty(), "{name}: no cells_dayNN.csv");
    for day in &days {
        let cells = read_cells(&out.join(day));
        let worst = cells
            .iter()
            .map(|&p| {
                triangles
                    .near(p, 1)
                    .map(|i| to_triangle(p, tri(&faces[i])))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        if worst >= 1e-3 * size {
            report.push(format!(
                "{name} {day}: a cell {worst:.2e} off the mesh (size {size:.1})"
            ));
        }
    }
    // Clark–Evans on day 0 (after the initial relaxation).
    let index = clark_evans(&read_cells(&out.join(&days[0])), area, lo);
    eprintln!("{name}: Clark–Evans {index:.3} on day 0, mesh size {size:.1}");
    if index < 1.4 {
        report.push(format!("{name}: Clark–Evans index {index:.3} on day 0"));
    }
    report
}

/// The Clark–Evans index of `cells` spread over `area`: their mean distance
/// to the nearest other cell over 0.5/√density, that of random points
/// (cubes of the cells' spacing from `lo` find the nearest).
fn clark_evans(cells: &[P], area: f64, lo: P) -> f64 {
    let spacing = (area / cells.len() as f64).sqrt();
    let points = Bins::new(lo, spacing, cells.iter().map(|&p| (p, p)));
    let mean = cells
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let mut reach = 1;
            loop {
                let d = points
                    .near(p, reach)
                    .filter(|&j| j != i)
                    .map(|j| dot(sub(cells[j], p), sub(cells[j], p)).sqrt())
                    .fold(f64::INFINITY, f64::min);
                if d <= reach as f64 * spacing {
                    break d;
                }
                reach += 1;
            }
        })
        .sum::<f64>()
        / cells.len() as f64;
    mean / (0.5 * spacing)
}
