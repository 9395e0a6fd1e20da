//! A frame's rings as a closed triangle mesh, a group per module (horn
//! paper, Sec. 7, Fig. 8).

use anyhow::Result;

use super::frames::{Frame, P3};
use crate::outputs::mesh;

/// The horn's colour, sRGB.
pub(super) const HORN: [f64; 3] = [222.0, 204.0, 168.0];

/// A triangle by vertex indices, with its month (for the stripes); caps
/// have `None`.
pub type Triangle = ([usize; 3], Option<u32>);

/// A frame as a triangle mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions, cm.
    pub vertices: Vec<P3>,
    /// Per module: the module and its triangles.
    pub groups: Vec<(u16, Vec<Triangle>)>,
}

pub(super) fn centroid(points: &[P3]) -> P3 {
    let n = points.len().max(1) as f64;
    points.iter().fold(P3::zeros(), |s, p| s + p) / n
}

/// The mesh of `frame`; `rings_per_year` (J) maps ring indices to months.
#[must_use]
pub fn mesh(frame: &Frame, rings_per_year: u32) -> Mesh {
    let mut m = Mesh::default();
    let mut starts = Vec::with_capacity(frame.rings.len());
    for r in &frame.rings {
        starts.push(m.vertices.len());
        m.vertices.extend_from_slice(&r.points);
    }
    // Orientation: is (A₀, A₁, B₀) outward on the first pair of rings?
    let outward = frame
        .rings
        .windows(2)
        .find(|w| w[0].module == w[1].module && w[0].points.len() >= 2)
        .is_none_or(|w| {
            let (a, b) = (&w[0].points, &w[1].points);
            let n = (a[1] - a[0]).cross(&(b[0] - a[0]));
            n.dot(&(a[0] - centroid(a))) > 0.0
        });
    for (k, w) in frame.rings.windows(2).enumerate() {
        if w[0].module != w[1].module || w[0].points.len() != w[1].points.len() {
            continue;
        }
        let month = u32::from(w[0].ring) * 12 / rings_per_year.max(1);
        let (a, b, n) = (starts[k], starts[k + 1], w[0].points.len());
        if m.groups.last().is_none_or(|g| g.0 != w[0].module) {
            m.groups.push((w[0].module, Vec::new()));
        }
        let Some((_, group)) = m.groups.last_mut() else {
            continue;
        };
        for i in 0..n {
            let j = (i + 1) % n;
            let (t1, t2) = if outward {
                ([a + i, a + j, b + i], [a + j, b + j, b + i])
            } else {
                ([a + i, b + i, a + j], [a + j, b + i, b + j])
            };
            group.push((t1, Some(month)));
            group.push((t2, Some(month)));
        }
    }
    // Caps: the tip and the skull end, each a fan from its centroid.
    let last = frame.rings.len();
    let caps = [
        (0usize, 1usize),
        (last.saturating_sub(1), last.saturating_sub(2)),
    ];
    for (cap, neighbour) in caps {
        if last < 2 {
            break;
        }
        let ring = &frame.rings[cap];
        let c = centroid(&ring.points);
        let away = c - centroid(&frame.rings[neighbour].points);
        let centre = m.vertices.len();
        m.vertices.push(c);
        let (s, n) = (starts[cap], ring.points.len());
        let Some(group) = m.groups.iter_mut().find(|g| g.0 == ring.module) else {
            continue;
        };
        for i in 0..n {
            let j = (i + 1) % n;
            let normal = (ring.points[i] - c).cross(&(ring.points[j] - c));
            let tri = if normal.dot(&away) > 0.0 {
                [centre, s + i, s + j]
            } else {
                [centre, s + j, s + i]
            };
            group.1.push((tri, None));
        }
    }
    m
}

/// The OBJ and glTF mesh of a frame (its geometry `m`): one group
/// `module_<i>` per module, vertex colours the horn's with the picture's
/// monthly bands (so the annual rings show), in the material `horn`,
/// headed by `title`.
///
/// # Errors
/// Never for a mesh of [`mesh()`].
pub fn solid(frame: &Frame, m: &Mesh, title: &str, rings_per_year: u32) -> Result<mesh::Mesh> {
    let mut out = mesh::Mesh::new();
    out.comment(title);
    out.comment("units: cm; skull frame (module k grows along +x)");
    let shade = |k: f64| HORN.map(|v| (v * k).round().clamp(0.0, 255.0) as u8);
    let mut vertices = m.vertices.iter();
    for r in &frame.rings {
        let month = u32::from(r.ring) * 12 / rings_per_year.max(1);
        let rgb = shade(if month % 2 == 1 { 0.86 } else { 1.0 });
        for v in vertices.by_ref().take(r.points.len()) {
            out.push_coloured_vertex((*v).into(), rgb)?;
        }
    }
    for v in vertices {
        out.push_coloured_vertex((*v).into(), shade(0.8))?;
    }
    let horn = out.material("horn", shade(1.0))?;
    for (module, tris) in &m.groups {
        let g = out.group(Some(&format!("module_{module}")), Some(horn))?;
        for (t, _) in tris {
            out.push_face(g, &t.map(|k| k as u32))?;
        }
    }
    Ok(out)
}
