//! Normals for smooth shading of the mesh pictures (mosaics on a mesh,
//! horns, bones): the normal at each corner of each triangle, so that a
//! picture shades between its corners (Gouraud) and a smooth surface
//! shows no facets, while an edge sharper than [`CREASE`] stays an edge.

/// The cosine of the largest angle between two faces at a vertex that is
/// shaded smoothly across (45°): a sharper edge stays an edge.
pub const CREASE: f64 = std::f64::consts::FRAC_1_SQRT_2;

use nalgebra::Vector3;

/// The unit normal at each corner of each of `triangles` (indices into
/// `vertices`): the mean of the normals of the triangles at that point
/// that meet this one at less than [`CREASE`], weighted by their areas,
/// each turned to this triangle's side (so a mesh wound either way gets
/// the same normals, up to their sign). Vertices at the same coordinates
/// are one point (a mesh whose pieces repeat the vertices they share
/// shades smoothly across them). A triangle without area, or one whose
/// index is out of range, has zero normals.
#[must_use]
pub fn corner_normals<P>(vertices: &[P], triangles: &[[u32; 3]]) -> Vec<[[f64; 3]; 3]>
where
    P: Copy + Into<Vector3<f64>>,
{
    let vertices: Vec<Vector3<f64>> = vertices.iter().map(|&v| v.into()).collect();
    let point = points(&vertices);
    // Each triangle's points; none for one whose index is out of range.
    let points: Vec<Option<[usize; 3]>> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| point.get(v as usize).copied());
            Some([a?, b?, c?])
        })
        .collect();
    // Twice each triangle's area times its unit normal, and that unit.
    let mut normals = vec![Vector3::zeros(); triangles.len()];
    let mut units = vec![Vector3::zeros(); triangles.len()];
    for ((n, u), t) in normals.iter_mut().zip(&mut units).zip(&points) {
        if let Some([a, b, c]) = *t {
            let [a, b, c] = [a, b, c].map(|p| vertices[p]);
            *n = (b - a).cross(&(c - a));
            *u = unit(*n);
        }
    }
    let around = Around::new(&points, vertices.len());
    let shared = shared_means(&around, &normals, &units);
    let mut corners = vec![[[0.0; 3]; 3]; triangles.len()];
    for (i, (out, t)) in corners.iter_mut().zip(&points).enumerate() {
        let Some(t) = t else {
            continue;
        };
        let own = units[i];
        for (n, &p) in out.iter_mut().zip(t) {
            if let Some((first, mean)) = shared[p] {
                let turn = sign(own.dot(&units[first]));
                *n = (mean * turn).into();
                continue;
            }
            // This triangle among them (its own cosine is 1).
            let mut sum = Vector3::zeros();
            for &g in around.at(p) {
                let cos = units[g].dot(&own);
                if cos.abs() >= CREASE {
                    sum += normals[g] * sign(cos);
                }
            }
            *n = unit(sum).into();
        }
    }
    corners
}

/// Each vertex's point: the first vertex at its coordinates, found among
/// the vertices sorted by a mix of the coordinates' bits.
fn points(vertices: &[Vector3<f64>]) -> Vec<usize> {
    let bits = |v: &Vector3<f64>| [v.x, v.y, v.z].map(f64::to_bits);
    let mix = |[x, y, z]: [u64; 3]| {
        (x ^ y.rotate_left(21) ^ z.rotate_left(42)).wrapping_mul(0x9e37_79b9_7f4a_7c15)
    };
    let mut by_mix: Vec<(u64, usize)> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (mix(bits(v)), i))
        .collect();
    by_mix.sort_unstable();
    let mut point: Vec<usize> = (0..vertices.len()).collect();
    for run in by_mix.chunk_by(|a, b| a.0 == b.0) {
        // In index order: each takes the first of its coordinates.
        for (k, &(_, i)) in run.iter().enumerate() {
            if let Some(&(_, first)) = run[..k]
                .iter()
                .find(|&&(_, j)| bits(&vertices[j]) == bits(&vertices[i]))
            {
                point[i] = point[first];
            }
        }
    }
    point
}

/// The triangles at each point: `around[starts[p]..starts[p + 1]]`.
struct Around {
    starts: Vec<usize>,
    around: Vec<usize>,
}

impl Around {
    /// The triangles at each of `count` points, of the triangles' `points`.
    fn new(points: &[Option<[usize; 3]>], count: usize) -> Around {
        let mut starts = vec![0usize; count + 1];
        for &p in points.iter().flatten().flatten() {
            starts[p + 1] += 1;
        }
        for p in 1..starts.len() {
            starts[p] += starts[p - 1];
        }
        let mut fill = starts.clone();
        let mut around = vec![0usize; starts[count]];
        for (i, t) in points.iter().enumerate() {
            for &p in t.iter().flatten() {
                around[fill[p]] = i;
                fill[p] += 1;
            }
        }
        Around { starts, around }
    }

    /// The triangles at point `p`.
    fn at(&self, p: usize) -> &[usize] {
        &self.around[self.starts[p]..self.starts[p + 1]]
    }

    /// How many points.
    fn points(&self) -> usize {
        self.starts.len() - 1
    }
}

/// For each point where every triangle is within half the crease of the
/// first (turned to its side), so that any two are within the crease:
/// that first triangle and the one mean every corner there takes (turned
/// to its triangle's side).
fn shared_means(
    around: &Around,
    normals: &[Vector3<f64>],
    units: &[Vector3<f64>],
) -> Vec<Option<(usize, Vector3<f64>)>> {
    (0..around.points())
        .map(|p| {
            let faces = around.at(p);
            let &first = faces.first()?;
            let mut sum = Vector3::zeros();
            let mut alike = true;
            for &g in faces {
                let cos = units[g].dot(&units[first]);
                alike &= cos.abs() >= HALF_CREASE;
                sum += normals[g] * sign(cos);
            }
            alike.then(|| (first, unit(sum)))
        })
        .collect()
}

/// The side a cosine puts a normal on: −1 behind, 1 in front.
fn sign(cos: f64) -> f64 {
    if cos < 0.0 { -1.0 } else { 1.0 }
}

/// `v` scaled to length 1; the zero vector stays 0.
#[must_use]
pub fn unit(v: Vector3<f64>) -> Vector3<f64> {
    let length = v.norm();
    if length > 0.0 {
        v / length
    } else {
        Vector3::zeros()
    }
}

/// The cosine of half [`CREASE`] (22.5°).
const HALF_CREASE: f64 = 0.923_879_532_511_286_7;

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A globe of radius `r` from `rings` bands of `segments` facets (a fan
    /// round each pole), as vertices and triangles wound outwards.
    pub(crate) fn globe(r: f64, rings: u32, segments: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut vertices = vec![[0.0, 0.0, r]];
        for i in 1..rings {
            let polar = std::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..segments {
                let a = std::f64::consts::TAU * f64::from(j) / f64::from(segments);
                let p = [polar.sin() * a.cos(), polar.sin() * a.sin(), polar.cos()];
                vertices.push(p.map(|x| r * x));
            }
        }
        vertices.push([0.0, 0.0, -r]);
        let south = (rings - 1) * segments + 1;
        let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let mut triangles = Vec::new();
        for j in 0..segments {
            triangles.push([0, at(1, j), at(1, j + 1)]);
            triangles.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
            for i in 1..rings - 1 {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
                triangles.extend([[a, c, b], [b, c, d]]);
            }
        }
        (vertices, triangles)
    }

    fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
        Vector3::from(a)
            .dot(&Vector3::from(b))
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees()
    }

    #[test]
    fn a_globe_gets_the_normals_of_the_sphere() {
        let (vertices, triangles) = globe(1.0, 12, 24);
        let normals = corner_normals(&vertices, &triangles);
        for (t, corners) in triangles.iter().zip(&normals) {
            for (&v, &n) in t.iter().zip(corners) {
                // The mean of the faces' normals, within 3° of the
                // sphere's own at the vertex, where a facet's own normal
                // is up to 10° off (facets 15° apart; the fans round the
                // poles pull their rings' vertices most).
                let off = angle(n, vertices[v as usize]);
                assert!(off < 3.0, "{off}° off at vertex {v}");
            }
        }
    }

    #[test]
    fn either_winding_and_repeated_vertices_give_the_same_normals() {
        let (vertices, triangles) = globe(1.0, 8, 12);
        let normals = corner_normals(&vertices, &triangles);
        // Every other triangle wound the other way.
        let mut mixed = triangles.clone();
        for t in mixed.iter_mut().step_by(2) {
            t.swap(1, 2);
        }
        let turned = corner_normals(&vertices, &mixed);
        for (k, (a, b)) in normals.iter().zip(&turned).enumerate() {
            // A swapped triangle's corners 1 and 2 swap too.
            let b = if k % 2 == 0 { [b[0], b[2], b[1]] } else { *b };
            for (a, b) in a.iter().zip(&b) {
                let apart = |b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
                let off = apart(*b).min(apart(b.map(|x| -x)));
                assert!(off < 1e-12, "triangle {k}: {a:?} {b:?}");
            }
        }
        // Each triangle with vertices of its own, at the same places.
        let apart: Vec<[f64; 3]> = triangles
            .iter()
            .flat_map(|t| t.map(|v| vertices[v as usize]))
            .collect();
        let own: Vec<[u32; 3]> = (0..triangles.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        assert_eq!(corner_normals(&apart, &own), normals);
    }

    /// A cube of half side `r` round the origin, two triangles a face.
    pub(crate) fn cube(r: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let vertices = (0..8)
            .map(|k| [1, 2, 4].map(|bit| if k & bit == 0 { -r } else { r }))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        (vertices, triangles)
    }

    #[test]
    fn a_cube_keeps_its_edges() {
        let (vertices, triangles) = cube(1.0);
        let normals = corner_normals(&vertices, &triangles);
        for (t, corners) in triangles.iter().zip(&normals) {
            let [a, b, c] = t.map(|v| vertices[v as usize]);
            let [a, b, c] = [a, b, c].map(Vector3::from);
            let face: [f64; 3] = unit((b - a).cross(&(c - a))).into();
            for n in corners {
                assert!(angle(*n, face) < 1e-9, "{n:?} {face:?}");
            }
        }
    }

    #[test]
    fn flat_or_broken_triangles_have_zero_normals() {
        let vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let normals = corner_normals(&vertices, &[[0, 1, 2], [0, 1, 7]]);
        assert_eq!(normals, vec![[[0.0; 3]; 3]; 2]);
    }
}
