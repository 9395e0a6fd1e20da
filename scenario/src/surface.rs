//! `[mosaic.surface]`: a built-in shape of the thesis's objects or a
//! user's OBJ mesh (read with `tobj`, polygons fanned into triangles),
//! checked into what the core's [`Surface`] borrows.

use morphogen::fx::Fx;
use morphogen::mosaic::{
    ControlMap, MeshError, MeshStore, MosaicError, Shape, Surface, SurfaceMesh, Tessellation,
    build_mesh,
};

use crate::run::MeshVecs;
use crate::schema::{self, Include};
use crate::value::{Invalid, Result, fx, int, invalid};

/// A checked surface, owning its triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceSpec {
    /// A built-in shape, or `None` for `vertices` and `faces`.
    pub shape: Option<Tessellation>,
    /// A user mesh's vertices.
    pub vertices: Vec<[Fx; 3]>,
    /// A user mesh's triangles.
    pub faces: Vec<[u32; 3]>,
    /// How (u, v) is read on it.
    pub control: ControlMap,
}

impl SurfaceSpec {
    /// The core's view of it.
    #[must_use]
    pub fn surface(&self) -> Surface<'_> {
        Surface {
            mesh: match self.shape {
                Some(t) => SurfaceMesh::Shape(t),
                None => SurfaceMesh::Triangles {
                    vertices: &self.vertices,
                    faces: &self.faces,
                },
            },
            control: self.control,
        }
    }
}

fn need<T: Copy>(key: &str, v: Option<T>, shape: &str) -> Result<T> {
    v.ok_or_else(|| Invalid {
        key: format!("mosaic.surface.{key}"),
        message: format!("is needed for shape = {shape:?}"),
    })
}

fn size(key: &str, v: Option<f64>, shape: &str) -> Result<Fx> {
    fx(
        &format!("mosaic.surface.{key}"),
        need(key, v, shape)?,
        0.01,
        256.0,
    )
}

/// Checks `[mosaic.surface]`.
///
/// # Errors
/// A missing or out-of-range key, an unknown shape, or an OBJ file that
/// cannot be read.
/// `read` gives the bytes of the OBJ file a scenario names.
pub fn check(
    s: &schema::Surface,
    read: &dyn Fn(&Include) -> Result<Vec<u8>>,
) -> Result<SurfaceSpec> {
    let name = s.shape.as_str();
    let rings = int("mosaic.surface.rings", s.rings.unwrap_or(24), 2, 1024)?;
    let segments = int("mosaic.surface.segments", s.segments.unwrap_or(48), 3, 1024)?;
    let tess = |shape| {
        Some(Tessellation {
            shape,
            rings,
            segments,
        })
    };
    let shape = match name {
        "ellipsoid" => {
            let r = need("radii", s.radii, name)?;
            let radii =
                [0, 1, 2].map(|i| fx(&format!("mosaic.surface.radii[{i}]"), r[i], 0.01, 256.0));
            let [a, b, c] = radii;
            tess(Shape::Ellipsoid {
                radii: [a?, b?, c?],
                square: fx("mosaic.surface.square", s.square.unwrap_or(0.0), 0.0, 0.9)?,
            })
        }
        "stem" => tess(Shape::Stem {
            radius: size("radius", s.radius, name)?,
            length: size("length", s.length, name)?,
            ribs: int(
                "mosaic.surface.ribs",
                s.ribs.unwrap_or(0),
                0,
                i64::from(segments / 4),
            )
            .map_err(|e| Invalid {
                message: format!(
                    "{}: a rib takes 4 of mosaic.surface.segments = {segments}",
                    e.message
                ),
                ..e
            })?,
            depth: fx("mosaic.surface.depth", s.depth.unwrap_or(0.0), 0.0, 0.5)?,
        }),
        "cap" => tess(Shape::Cap {
            radius: size("radius", s.radius, name)?,
            height: size("height", s.height, name)?,
            rim: int("mosaic.surface.rim", s.rim.unwrap_or(100), 10, 170)?,
        }),
        "heart-leaf" | "strap-leaf" => tess(Shape::Leaf {
            length: size("length", s.length, name)?,
            width: size("width", s.width, name)?,
            heart: name == "heart-leaf",
            cup: fx("mosaic.surface.cup", s.cup.unwrap_or(0.0), 0.0, 1.0)?,
        }),
        "obj" => None,
        other => {
            return invalid(
                "mosaic.surface.shape",
                format!(
                    "{other:?} (allowed: \"ellipsoid\", \"stem\", \"cap\", \"heart-leaf\", \"strap-leaf\", \"obj\")"
                ),
            );
        }
    };
    let leaf = matches!(name, "heart-leaf" | "strap-leaf");
    let control = match s.control.as_deref() {
        None if leaf => ControlMap::Plane,
        None | Some("cylinder") => ControlMap::Cylinder,
        Some("plane") => ControlMap::Plane,
        Some(other) => {
            return invalid(
                "mosaic.surface.control",
                format!("{other:?} (allowed: \"cylinder\", \"plane\")"),
            );
        }
    };
    let (vertices, faces) = match shape {
        Some(_) => (Vec::new(), Vec::new()),
        None => {
            let bytes = read(need_file(s)?)?;
            obj(&bytes)?
        }
    };
    let spec = SurfaceSpec {
        shape,
        vertices,
        faces,
        control,
    };
    carries_cells(&spec, name)?;
    Ok(spec)
}

/// Builds the mesh as a run does and checks it with the core's
/// [`build_mesh`], so that a shape too small for its grid, or an OBJ the
/// core cannot use, is refused here, naming its key, not at the run's
/// start. The run builds it again in its own store (the core checks what
/// it is given): 6.4 M instructions more for watermelon-fruit's 3,000
/// triangles, 0.08 % of its `verify`.
fn carries_cells(spec: &SurfaceSpec, name: &str) -> Result<()> {
    let surface = spec.surface();
    let (vertices, faces) = surface.counts();
    let built = MeshVecs::default()
        .buffers(vertices, faces)
        .and_then(|(buffers, _)| build_mesh(&surface, buffers).map(drop));
    let Err(e) = built else { return Ok(()) };
    let (problem, remedy) = match e {
        morphogen::Error::Mosaic(MosaicError::Mesh(e @ MeshError::Degenerate { .. })) => (
            e.to_string(),
            "make it larger, or use fewer rings or segments",
        ),
        morphogen::Error::Mosaic(MosaicError::Mesh(e)) => {
            (e.to_string(), "use fewer rings or segments")
        }
        other => return invalid("mosaic.surface", other.to_string()),
    };
    match spec.shape {
        Some(t) => invalid(
            "mosaic.surface",
            format!(
                "shape {name:?} in {} rings × {} segments cannot carry cells: {problem}; {remedy}",
                t.rings, t.segments
            ),
        ),
        None => invalid("mosaic.surface.file", problem),
    }
}

fn need_file(s: &schema::Surface) -> Result<&Include> {
    s.file.as_ref().ok_or_else(|| Invalid {
        key: "mosaic.surface.file".into(),
        message: "is needed for shape = \"obj\" (a path to an OBJ file)".into(),
    })
}

/// A user mesh: vertices and triangles by vertex index.
type Triangles = (Vec<[Fx; 3]>, Vec<[u32; 3]>);

/// The vertices and triangles of an OBJ file (every object in it, as one
/// mesh; polygons fanned into triangles).
fn obj(bytes: &[u8]) -> Result<Triangles> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..tobj::LoadOptions::default()
    };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::MaterialParseError)
    })
    .or_else(|e| invalid("mosaic.surface.file", format!("not a usable OBJ file: {e}")))?;
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for m in &models {
        let base = vertices.len() as u32;
        for (i, p) in m.mesh.positions.chunks_exact(3).enumerate() {
            let key = |c: usize| {
                format!(
                    "mosaic.surface.file: vertex {} coordinate {c}",
                    base as usize + i + 1
                )
            };
            vertices.push([
                fx(&key(0), f64::from(p[0]), -512.0, 512.0)?,
                fx(&key(1), f64::from(p[1]), -512.0, 512.0)?,
                fx(&key(2), f64::from(p[2]), -512.0, 512.0)?,
            ]);
        }
        for t in m.mesh.indices.chunks_exact(3) {
            faces.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if faces.is_empty() {
        return invalid("mosaic.surface.file", "the OBJ file has no face (f lines)");
    }
    Ok((vertices, faces))
}

#[cfg(test)]
mod tests {
    use crate::Scenario;

    /// A mosaic scenario on the OBJ text `obj`.
    fn on(obj: &str) -> String {
        format!(
            r#"name = "t"
summary = "t"
seed = 1
[mosaic]
domain = {{ size = [10, 10], periodic = [true, false] }}
initial_cells = 20
days = 1
radius_weight = 1
push_weight = 0.1
initial_relaxations = 1
daily_relaxations = 1
frames = [1]
adhesion = [[0.5]]
[mosaic.surface]
shape = "obj"
file = {{ text = """{obj}""" }}
[[mosaic.types]]
colour = [1, 2, 3]
division_days = 2
initial_probability = 1
"#
        )
    }

    /// The error of running the scenario on `obj`, as the CLI prints it.
    fn refusal(obj: &str) -> String {
        let scenario = match Scenario::from_text("t.toml", &on(obj)) {
            Ok(s) => s,
            Err(e) => return e.to_string(),
        };
        let mut sink = Vec::new();
        let mut encoder = morphogen::stream::Encoder::new(&mut sink);
        scenario
            .with_preset(|p| crate::run::run(p, 1, &mut encoder, &mut |_| {}))
            .map_or_else(|e| e.to_string(), |()| "ran".into())
    }

    #[test]
    fn unusable_meshes_are_refused_naming_the_problem() {
        let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        assert_eq!(
            refusal(square),
            "ran",
            "a quad is fanned into two triangles"
        );
        assert!(refusal("v 0 0 0\nv 1 0 0\n").contains("no face"));
        assert!(refusal("v 0 0 0\nv 900 0 0\nv 0 1 0\nf 1 2 3\n").contains("vertex 2"));
        let flat = "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
        assert!(
            refusal(flat).starts_with("t.toml:16: mosaic.surface.file: triangle 0 has no area"),
            "refused at the door, naming the key: {}",
            refusal(flat)
        );
        let fin = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
        assert!(
            refusal(fin).contains("shared by more than two"),
            "{}",
            refusal(fin)
        );
    }

    #[test]
    fn a_shape_too_small_for_its_grid_is_refused_at_the_door() {
        let stem = |radius: &str, rings: u32| {
            on("").replace(
                "shape = \"obj\"\nfile = { text = \"\"\"\"\"\" }",
                &format!("shape = \"stem\"\nradius = {radius}\nlength = 20\nrings = {rings}"),
            )
        };
        let refused = |text: String| match Scenario::from_text("t.toml", &text) {
            Ok(_) => "accepted".to_string(),
            Err(e) => e.to_string(),
        };
        assert_eq!(refused(stem("2", 24)), "accepted");
        assert_eq!(
            refused(stem("0.01", 24)),
            "t.toml:14: mosaic.surface: shape \"stem\" in 24 rings × 48 segments cannot carry \
             cells: triangle 1728 has no area; make it larger, or use fewer rings or segments"
        );
        assert!(
            refused(stem("2", 1024).replace("length = 20", "length = 20\nsegments = 1024"))
                .contains("more than 1048576 vertices"),
        );
    }
}
