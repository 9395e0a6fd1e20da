//! Tests of the mesh: validation, walks across edges and along boundaries.

#![allow(clippy::float_arithmetic)] // f64 measures the fixed-point results

use super::*;
use crate::fx::Fx;
use crate::mosaic::shapes::{Shape, Tessellation};

struct Built {
    v: Vec<[i32; 3]>,
    f: Vec<[u32; 3]>,
    nb: Vec<[u32; 3]>,
    normals: Vec<[i32; 3]>,
    inward: Vec<[[i32; 3]; 3]>,
    edges: Vec<u64>,
}

fn built(t: Tessellation) -> Built {
    let (nv, nf) = t.counts();
    let mut b = Built {
        v: vec![[0; 3]; nv],
        f: vec![[0; 3]; nf],
        nb: vec![[0; 3]; nf],
        normals: vec![[0; 3]; nf],
        inward: vec![[[0; 3]; 3]; nf],
        edges: vec![0; 3 * nf],
    };
    t.build(&mut b.v, &mut b.f);
    b
}

impl Built {
    fn mesh(&mut self) -> Result<Mesh<'_>, MeshError> {
        let parts = MeshParts {
            neighbours: &mut self.nb,
            normals: &mut self.normals,
            inward: &mut self.inward,
            edges: &mut self.edges,
        };
        Mesh::new_checked(&self.v, &self.f, parts)
    }
}

fn sphere() -> Built {
    built(Tessellation {
        shape: Shape::Ellipsoid {
            radii: [Fx::from_int(10); 3],
            square: Fx::ZERO,
        },
        rings: 16,
        segments: 24,
    })
}

/// Distance (units) from `p` to the plane of face `f`, and whether `p` is
/// inside the face's edges (within `slack` Q16 bits).
fn off_face(mesh: &Mesh<'_>, f: u32, p: [i32; 3]) -> f64 {
    let [a, _, _] = mesh.corners(f);
    let n = mesh.normal(f);
    let d: f64 = (0..3)
        .map(|c| f64::from(p[c] - a[c]) * f64::from(n[c]) / 65536.0)
        .sum();
    (d / 65536.0).abs()
}

#[test]
fn a_sphere_is_closed_and_its_area_is_close_to_4_pi_r2() {
    let mut b = sphere();
    let mesh = b.mesh().unwrap();
    let area = mesh.area_q16() as f64 / 65536.0;
    // The inscribed polyhedron of 16 × 24 faces: 1.05 % below the sphere.
    let exact = 4.0 * core::f64::consts::PI * 100.0;
    assert!((area / exact - 0.9895).abs() < 0.001, "{area} vs {exact}");
    assert!(b.nb.iter().flatten().all(|&g| g != NO_FACE));
}

#[test]
fn walks_stay_on_the_surface_and_go_around_it() {
    let mut b = sphere();
    let mesh = b.mesh().unwrap();
    let start = Place {
        face: 100,
        p: mesh.centroid(100),
    };
    // Steps of 0.5 units, each on in the direction of the last: a great
    // circle of circumference ~62.8 crosses many faces.
    let mut dir = mesh.frame(100)[0];
    let mut at = start;
    let mut faces = std::collections::BTreeSet::new();
    for _ in 0..60 {
        let n = mesh.normal(at.face).map(i64::from);
        let d = along_plane(dir, n);
        let len = d.iter().map(|x| (x * x) as f64).sum::<f64>().sqrt();
        let from = at.p;
        at = mesh.walk(at, d.map(|x| (x as f64 * 32768.0 / len) as i64));
        dir = [0, 1, 2].map(|c| i64::from(at.p[c] - from[c]));
        faces.insert(at.face);
        assert!(off_face(&mesh, at.face, at.p) < 1e-3, "{at:?}");
        let r: f64 =
            at.p.iter()
                .map(|&c| (f64::from(c) / 65536.0).powi(2))
                .sum::<f64>()
                .sqrt();
        assert!((9.5..=10.01).contains(&r), "{r}");
    }
    assert!(faces.len() > 20, "{}", faces.len());
}

#[test]
fn a_boundary_holds_the_walk() {
    let mut b = built(Tessellation {
        shape: Shape::Leaf {
            length: Fx::from_int(20),
            width: Fx::from_int(10),
            heart: false,
            cup: Fx::ZERO,
        },
        rings: 10,
        segments: 8,
    });
    let mesh = b.mesh().unwrap();
    let start = Place {
        face: 5,
        p: mesh.centroid(5),
    };
    // Far across the leaf (−x): ends on its edge, within the half width.
    let to = mesh.walk(start, [-(40 << 16), 0, 0]);
    assert!(to.p[0] >= -(5 << 16) - 2, "{to:?}");
    assert!(off_face(&mesh, to.face, to.p) < 1e-3);
}

#[test]
fn bad_meshes_name_their_problem() {
    let v = [[0, 0, 0], [1 << 16, 0, 0], [0, 1 << 16, 0], [0, 0, 1 << 16]];
    let mut nb = [[0; 3]; 3];
    let mut normals = [[0; 3]; 3];
    let mut inward = [[[0; 3]; 3]; 3];
    let mut edges = [0; 9];
    let mut check = |f: &[[u32; 3]], v: &[[i32; 3]]| {
        let parts = MeshParts {
            neighbours: &mut nb,
            normals: &mut normals,
            inward: &mut inward,
            edges: &mut edges,
        };
        Mesh::new_checked(v, f, parts).map(|_| ())
    };
    assert_eq!(check(&[], &v), Err(MeshError::Empty));
    assert_eq!(check(&[[0, 1, 7]], &v), Err(MeshError::Index { face: 0 }));
    assert_eq!(check(&[[0, 1, 1]], &v), Err(MeshError::Index { face: 0 }));
    let flat = [[0, 0, 0], [1 << 16, 0, 0], [2 << 16, 0, 0]];
    assert_eq!(
        check(&[[0, 1, 2]], &flat),
        Err(MeshError::Degenerate { face: 0 })
    );
    let far = [[0, 0, 0], [1 << 16, 0, 0], [0, 600 << 16, 0]];
    assert_eq!(
        check(&[[0, 1, 2]], &far),
        Err(MeshError::Coordinate { vertex: 2 })
    );
    // Three triangles on the edge 0–1.
    assert_eq!(
        check(&[[0, 1, 2], [1, 0, 3], [0, 1, 3]], &v),
        Err(MeshError::NonManifold { face: 0 })
    );
    assert_eq!(check(&[[0, 1, 2], [1, 0, 3]], &v), Ok(()));
}

#[test]
fn without_scratch_the_search_finds_the_neighbours_the_sort_does() {
    let shapes = [
        Shape::Ellipsoid {
            radii: [Fx::from_int(10); 3],
            square: Fx::ZERO,
        },
        Shape::Stem {
            radius: Fx::from_int(3),
            length: Fx::from_int(12),
            ribs: 8,
            depth: Fx::from_ratio(1, 5),
        },
        Shape::Leaf {
            length: Fx::from_int(20),
            width: Fx::from_int(10),
            heart: true,
            cup: Fx::from_ratio(1, 10),
        },
    ];
    for shape in shapes {
        let t = Tessellation {
            shape,
            rings: 9,
            segments: 14,
        };
        let mut sorted = built(t);
        let info = sorted.mesh().unwrap().info();
        let mut searched = built(t);
        let parts = MeshParts {
            neighbours: &mut searched.nb,
            normals: &mut searched.normals,
            inward: &mut [],
            edges: &mut [],
        };
        let mesh = Mesh::new_checked(&searched.v, &searched.f, parts).unwrap();
        assert_eq!(mesh.info(), info, "{shape:?}");
        assert!(mesh.inward.is_empty());
        // Every stored inward normal is what a walk works out without them.
        let full = Mesh::view(
            &info,
            MeshArrays {
                vertices: &sorted.v,
                faces: &sorted.f,
                neighbours: &sorted.nb,
                normals: &sorted.normals,
                inward: &sorted.inward,
            },
        );
        for f in 0..sorted.f.len() as u32 {
            let computed = inward_normals(mesh.normal(f).map(i64::from), mesh.corners(f));
            assert_eq!(full.inward[f as usize], computed);
        }
        assert_eq!(searched.nb, sorted.nb, "{shape:?}");
    }
    // An edge of three faces is refused as by the sort.
    let v = [[0, 0, 0], [1 << 16, 0, 0], [0, 1 << 16, 0], [0, 0, 1 << 16]];
    let mut nb = [[0; 3]; 3];
    let mut normals = [[0; 3]; 3];
    let parts = MeshParts {
        neighbours: &mut nb,
        normals: &mut normals,
        inward: &mut [],
        edges: &mut [],
    };
    assert_eq!(
        Mesh::new_checked(&v, &[[0, 1, 2], [1, 0, 3], [0, 1, 3]], parts).map(|_| ()),
        Err(MeshError::NonManifold { face: 0 })
    );
}
