//! Normals for smooth shading of the mesh pictures (mosaics on a mesh,
//! horns, bones): the normal at each corner of each triangle, so that a
//! picture shades between its corners (Gouraud) and a smooth surface
//! shows no facets, while an edge sharper than [`CREASE`] stays an edge.

/// The cosine of the largest angle between two faces at a vertex that is
/// shaded smoothly across (45°): a sharper edge stays an edge.
pub const CREASE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The unit normal at each corner of each of `triangles` (indices into
/// `vertices`): the mean of the normals of the triangles at that point
/// that meet this one at less than [`CREASE`], weighted by their areas,
/// each turned to this triangle's side (so a mesh wound either way gets
/// the same normals, up to their sign). Vertices at the same coordinates
/// are one point (a mesh whose pieces repeat the vertices they share
/// shades smoothly across them). A triangle without area, or one whose
/// index is out of range, has zero normals.
#[must_use]
pub fn corner_normals(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[[f64; 3]; 3]> {
    // Each vertex's point: the first vertex at its coordinates (sorted by
    // them, and by index among equals).
    let mut by_place: Vec<([u64; 3], usize)> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (v.map(f64::to_bits), i))
        .collect();
    by_place.sort_unstable();
    let mut point: Vec<usize> = (0..vertices.len()).collect();
    for pair in by_place.windows(2) {
        if pair[1].0 == pair[0].0 {
            point[pair[1].1] = point[pair[0].1];
        }
    }
    let corner = |v: u32| point.get(v as usize).copied();
    // Twice each triangle's area times its unit normal, and that unit.
    let normals: Vec<[f64; 3]> = triangles
        .iter()
        .map(|t| match t.map(|v| corner(v).map(|p| vertices[p])) {
            [Some(a), Some(b), Some(c)] => cross(sub(b, a), sub(c, a)),
            _ => [0.0; 3],
        })
        .collect();
    let units: Vec<[f64; 3]> = normals.iter().map(|&n| unit(n)).collect();
    // The triangles at each point: `around[starts[p]..starts[p + 1]]`.
    let mut starts = vec![0usize; vertices.len() + 1];
    for p in triangles.iter().flatten().filter_map(|&v| corner(v)) {
        starts[p + 1] += 1;
    }
    for p in 1..starts.len() {
        starts[p] += starts[p - 1];
    }
    let mut fill = starts.clone();
    let mut around = vec![0usize; starts[vertices.len()]];
    for (i, t) in triangles.iter().enumerate() {
        for p in t.iter().filter_map(|&v| corner(v)) {
            around[fill[p]] = i;
            fill[p] += 1;
        }
    }
    // Where every triangle at a point is within half the crease of the
    // first (turned to its side), any two are within the crease: each
    // corner there takes the one mean, turned to its triangle's side.
    let sign = |cos: f64| if cos < 0.0 { -1.0 } else { 1.0 };
    let shared: Vec<Option<[f64; 3]>> = (0..vertices.len())
        .map(|p| {
            let faces = &around[starts[p]..starts[p + 1]];
            let first = units[*faces.first()?];
            let mut sum = [0.0; 3];
            for &g in faces {
                let cos = dot(units[g], first);
                if cos.abs() < HALF_CREASE {
                    return None;
                }
                sum = [0, 1, 2].map(|k| sum[k] + sign(cos) * normals[g][k]);
            }
            Some(unit(sum))
        })
        .collect();
    triangles
        .iter()
        .zip(&units)
        .map(|(t, &own)| {
            t.map(|v| {
                let Some(p) = corner(v) else {
                    return [0.0; 3];
                };
                let faces = &around[starts[p]..starts[p + 1]];
                if let Some(mean) = shared[p] {
                    let turn = sign(dot(own, units[faces[0]]));
                    return mean.map(|x| turn * x);
                }
                // This triangle among them (its own cosine is 1).
                let mut sum = [0.0; 3];
                for &g in faces {
                    let cos = dot(units[g], own);
                    if cos.abs() >= CREASE {
                        sum = [0, 1, 2].map(|k| sum[k] + sign(cos) * normals[g][k]);
                    }
                }
                unit(sum)
            })
        })
        .collect()
}

/// The cosine of half [`CREASE`] (22.5°).
const HALF_CREASE: f64 = 0.923_879_532_511_286_7;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `v` scaled to length 1; the zero vector stays 0.
fn unit(v: [f64; 3]) -> [f64; 3] {
    let length = dot(v, v).sqrt();
    if length > 0.0 {
        v.map(|x| x / length)
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A globe of radius 1 from `rings` bands of `segments` facets (a fan
    /// round each pole), as vertices and triangles wound outwards.
    fn globe(rings: u32, segments: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut vertices = vec![[0.0, 0.0, 1.0]];
        for i in 1..rings {
            let polar = std::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..segments {
                let a = std::f64::consts::TAU * f64::from(j) / f64::from(segments);
                vertices.push([polar.sin() * a.cos(), polar.sin() * a.sin(), polar.cos()]);
            }
        }
        vertices.push([0.0, 0.0, -1.0]);
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
        dot(a, b).clamp(-1.0, 1.0).acos().to_degrees()
    }

    #[test]
    fn a_globe_gets_the_normals_of_the_sphere() {
        let (vertices, triangles) = globe(12, 24);
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
        let (vertices, triangles) = globe(8, 12);
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

    #[test]
    fn a_cube_keeps_its_edges() {
        let vertices: Vec<[f64; 3]> = (0..8)
            .map(|k| [1, 2, 4].map(|bit| if k & bit == 0 { -1.0 } else { 1.0 }))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        let normals = corner_normals(&vertices, &triangles);
        for (t, corners) in triangles.iter().zip(&normals) {
            let [a, b, c] = t.map(|v| vertices[v as usize]);
            let face = unit(cross(sub(b, a), sub(c, a)));
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
