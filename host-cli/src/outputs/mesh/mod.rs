//! One mesh writer for every model: a model-independent [`Mesh`] (positions,
//! polygon faces in named groups, optional per-vertex colours and normals,
//! named materials) written as Wavefront OBJ with an `.mtl` ([`write_obj`])
//! or as binary glTF 2.0 ([`write_glb`], [`GlbWriter`]) with `POSITION`,
//! `NORMAL`, `COLOR_0` and indices, one mesh per frame and, for several
//! frames, an animation that shows one frame at a time.
//!
//! Every model's geometry fits: horn rings (a group `module_<i>` per
//! module, triangles), body and bone surfaces (one unnamed group of
//! triangles under an object name), plant segments as square prisms
//! ([`Mesh::push_square_prism`], four quads each) and leaves as polygons,
//! grouped or coloured by colour index, and a mosaic on a surface
//! (per-vertex colours).
//!
//! Numbers: positions are `f64`, which hold a fixed-point (`Fx`) value
//! exactly; OBJ prints them through [`morphogen_stream_text::text`] (5 decimals read off
//! the fixed-point bits, or the exact text), glTF stores them as `f32`.

mod glb;
mod obj;

pub use glb::{GlbWriter, Scene, write_glb};
pub use obj::{Library, Numbers, ObjStyle, mtl, obj, obj_part, write_frame_obj, write_obj};

use std::fmt;

use nalgebra::Vector3;

/// An sRGB colour, 8 bits a channel (as the pictures use them).
pub type Rgb = [u8; 3];

/// What makes a [`Mesh`] or a scene impossible to write.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshError {
    /// A face names a vertex the mesh does not have.
    VertexOutOfRange {
        /// The index named (0-based).
        index: u32,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A face has fewer than 3 corners.
    FaceTooSmall(usize),
    /// More vertices than `u32` indices reach.
    TooManyVertices,
    /// Some vertices were given a colour and others not.
    MixedColours,
    /// Normals given for a different number of vertices.
    NormalCount {
        /// Normals given.
        normals: usize,
        /// Vertices in the mesh.
        vertices: usize,
    },
    /// A group, material or object name that is empty or has white space
    /// (OBJ and MTL lines are split at white space).
    InvalidName(String),
    /// A group id that no [`Mesh::group`] call returned.
    UnknownGroup(usize),
    /// A material id that no [`Mesh::material`] call returned.
    UnknownMaterial(usize),
    /// Frame times must be finite and rise strictly from frame to frame.
    TimeNotIncreasing {
        /// The frame whose time is wrong.
        frame: usize,
    },
    /// The binary data passes glTF's 4 GiB limit.
    TooLarge,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::VertexOutOfRange { index, vertices } => write!(
                f,
                "a face names vertex {index}, but the mesh has {vertices} vertices"
            ),
            MeshError::FaceTooSmall(n) => write!(f, "a face has {n} corners; it needs 3"),
            MeshError::TooManyVertices => write!(f, "more than 2^32 - 1 vertices in one mesh"),
            MeshError::MixedColours => write!(f, "some vertices have a colour and others not"),
            MeshError::NormalCount { normals, vertices } => {
                write!(f, "{normals} normals for {vertices} vertices")
            }
            MeshError::InvalidName(name) => {
                write!(f, "the name {name:?} is empty or has white space")
            }
            MeshError::UnknownGroup(g) => write!(f, "no group {g} in the mesh"),
            MeshError::UnknownMaterial(m) => write!(f, "no material {m} in the mesh"),
            MeshError::TimeNotIncreasing { frame } => {
                write!(f, "frame {frame}'s time is not after the previous frame's")
            }
            MeshError::TooLarge => write!(f, "the glTF binary data passes 4 GiB"),
        }
    }
}

impl std::error::Error for MeshError {}

/// A named material: an OBJ `usemtl` / MTL `newmtl` with its diffuse
/// colour, a glTF material of that name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Material {
    name: String,
    colour: Rgb,
}

impl Material {
    /// Its name (no white space).
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its colour (sRGB).
    #[must_use]
    pub fn colour(&self) -> Rgb {
        self.colour
    }
}

/// The id of a material in its [`Mesh`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaterialId(usize);

/// The id of a group in its [`Mesh`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GroupId(usize);

/// Faces under one OBJ `g` name and material; a glTF primitive.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Group {
    name: Option<String>,
    material: Option<usize>,
    /// Every face's corners, one face after another.
    corners: Vec<u32>,
    /// Where each face ends in `corners`.
    ends: Vec<usize>,
}

impl Group {
    /// The `g` name, if any.
    #[must_use]
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The material's index in [`Mesh::materials`], if any.
    #[must_use]
    pub fn material(&self) -> Option<usize> {
        self.material
    }

    /// The faces, each as its corners (0-based vertex indices).
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts.zip(&self.ends).map(|(s, &e)| &self.corners[s..e])
    }

    /// The faces as triangles: each polygon a fan from its first corner
    /// (polygons are taken to be convex).
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> {
        self.faces()
            .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]]))
    }
}

/// A model-independent polygon mesh; see the module docs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    comments: Vec<String>,
    object: Option<String>,
    positions: Vec<[f64; 3]>,
    colours: Option<Vec<Rgb>>,
    normals: Option<Vec<[f32; 3]>>,
    materials: Vec<Material>,
    groups: Vec<Group>,
}

fn checked_name(name: &str) -> Result<String, MeshError> {
    if name.is_empty() || name.chars().any(char::is_whitespace) {
        return Err(MeshError::InvalidName(name.to_owned()));
    }
    Ok(name.to_owned())
}

impl Mesh {
    /// An empty mesh.
    #[must_use]
    pub fn new() -> Mesh {
        Mesh::default()
    }

    /// A mesh of one unnamed group of triangles (a body or a bone frame).
    ///
    /// # Errors
    /// When a triangle names a vertex beyond `positions`.
    pub fn from_triangles(
        positions: Vec<[f64; 3]>,
        triangles: &[[u32; 3]],
    ) -> Result<Mesh, MeshError> {
        if u32::try_from(positions.len()).is_err() {
            return Err(MeshError::TooManyVertices);
        }
        let mut mesh = Mesh {
            positions,
            ..Mesh::default()
        };
        let group = mesh.group(None, None)?;
        for t in triangles {
            mesh.push_face(group, t)?;
        }
        Ok(mesh)
    }

    /// Gives `material` to every group that has none yet.
    ///
    /// # Errors
    /// When `material` is not one of the mesh's.
    pub fn paint(&mut self, material: MaterialId) -> Result<(), MeshError> {
        if material.0 >= self.materials.len() {
            return Err(MeshError::UnknownMaterial(material.0));
        }
        for g in self.groups.iter_mut().filter(|g| g.material.is_none()) {
            g.material = Some(material.0);
        }
        Ok(())
    }

    /// Adds an OBJ comment line (`# line`) to the header, in order.
    pub fn comment(&mut self, line: &str) {
        self.comments.extend(line.lines().map(str::to_owned));
    }

    /// Names the OBJ object (`o name`).
    ///
    /// # Errors
    /// When `name` is empty or has white space.
    pub fn set_object(&mut self, name: &str) -> Result<(), MeshError> {
        self.object = Some(checked_name(name)?);
        Ok(())
    }

    /// Adds a vertex; returns its index. Vertices of a mesh have colours
    /// all or none ([`Mesh::push_coloured_vertex`]).
    ///
    /// # Errors
    /// When the mesh has 2³² − 1 vertices already, or coloured ones.
    pub fn push_vertex(&mut self, p: [f64; 3]) -> Result<u32, MeshError> {
        if self.colours.is_some() {
            return Err(MeshError::MixedColours);
        }
        self.push_position(p)
    }

    /// Adds a vertex of colour `rgb` (sRGB); returns its index.
    ///
    /// # Errors
    /// When the mesh has 2³² − 1 vertices already, or uncoloured ones.
    pub fn push_coloured_vertex(&mut self, p: [f64; 3], rgb: Rgb) -> Result<u32, MeshError> {
        let colours = match &mut self.colours {
            Some(c) => c,
            None if self.positions.is_empty() => self.colours.insert(Vec::new()),
            None => return Err(MeshError::MixedColours),
        };
        colours.push(rgb);
        let index = self.push_position(p);
        if index.is_err()
            && let Some(c) = &mut self.colours
        {
            c.pop();
        }
        index
    }

    fn push_position(&mut self, p: [f64; 3]) -> Result<u32, MeshError> {
        let index = u32::try_from(self.positions.len())
            .ok()
            .filter(|&i| i < u32::MAX)
            .ok_or(MeshError::TooManyVertices)?;
        self.positions.push(p);
        Ok(index)
    }

    /// Gives every vertex a colour (replacing any), e.g. a mosaic's cell
    /// colours on a surface.
    ///
    /// # Errors
    /// When `colours` is not one per vertex.
    pub fn set_colours(&mut self, colours: Vec<Rgb>) -> Result<(), MeshError> {
        if colours.len() != self.positions.len() {
            return Err(MeshError::MixedColours);
        }
        self.colours = Some(colours);
        Ok(())
    }

    /// Gives every vertex a normal (replacing the computed ones).
    ///
    /// # Errors
    /// When `normals` is not one per vertex.
    pub fn set_normals(&mut self, normals: Vec<[f32; 3]>) -> Result<(), MeshError> {
        if normals.len() != self.positions.len() {
            return Err(MeshError::NormalCount {
                normals: normals.len(),
                vertices: self.positions.len(),
            });
        }
        self.normals = Some(normals);
        Ok(())
    }

    /// The material named `name`, added with `colour` unless the mesh has
    /// it already (then its first colour stays).
    ///
    /// # Errors
    /// When `name` is empty or has white space.
    pub fn material(&mut self, name: &str, colour: Rgb) -> Result<MaterialId, MeshError> {
        if let Some(k) = self.materials.iter().position(|m| m.name == name) {
            return Ok(MaterialId(k));
        }
        self.materials.push(Material {
            name: checked_name(name)?,
            colour,
        });
        Ok(MaterialId(self.materials.len() - 1))
    }

    /// Starts a group (OBJ `g name` when named, `usemtl` when it has a
    /// material); groups are written in the order they are started.
    ///
    /// # Errors
    /// When `name` is empty or has white space, or `material` is unknown.
    pub fn group(
        &mut self,
        name: Option<&str>,
        material: Option<MaterialId>,
    ) -> Result<GroupId, MeshError> {
        let name = name.map(checked_name).transpose()?;
        if let Some(MaterialId(m)) = material
            && m >= self.materials.len()
        {
            return Err(MeshError::UnknownMaterial(m));
        }
        self.groups.push(Group {
            name,
            material: material.map(|m| m.0),
            ..Group::default()
        });
        Ok(GroupId(self.groups.len() - 1))
    }

    /// Adds a face (a triangle or a polygon, counter-clockwise seen from
    /// outside; corners are 0-based vertex indices) to `group`.
    ///
    /// # Errors
    /// When the face has fewer than 3 corners, names a missing vertex, or
    /// the group is unknown.
    pub fn push_face(&mut self, group: GroupId, corners: &[u32]) -> Result<(), MeshError> {
        if corners.len() < 3 {
            return Err(MeshError::FaceTooSmall(corners.len()));
        }
        let vertices = self.positions.len();
        if let Some(&index) = corners.iter().find(|&&c| c as usize >= vertices) {
            return Err(MeshError::VertexOutOfRange { index, vertices });
        }
        let g = self
            .groups
            .get_mut(group.0)
            .ok_or(MeshError::UnknownGroup(group.0))?;
        g.corners.extend_from_slice(corners);
        g.ends.push(g.corners.len());
        Ok(())
    }

    /// Adds the segment `a`–`b` as a square prism of side `width` (at
    /// least 10⁻⁴) without end caps, as the plant OBJ draws segments: 8
    /// vertices (the square around `a`, then around `b`) coloured `rgb`
    /// when the mesh has colours, and 4 quads to `group`. The square's
    /// sides are `d × h` and `d × (d × h)` with `h` the x axis, or the y
    /// axis when the segment `d` is mostly along x.
    ///
    /// # Errors
    /// As [`Mesh::push_vertex`] and [`Mesh::push_face`].
    pub fn push_square_prism(
        &mut self,
        group: GroupId,
        [a, b]: [[f64; 3]; 2],
        width: f64,
        rgb: Option<Rgb>,
    ) -> Result<(), MeshError> {
        let [a, b] = [a, b].map(Vector3::from);
        let d = b - a;
        let helper = if d.x.abs() < d.y.abs().max(d.z.abs()) {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let r = width.max(1e-4) / 2.0;
        let u = scaled(d.cross(&helper), r);
        let v = scaled(d.cross(&u), r);
        let corners = [u + v, v - u, -u - v, u - v];
        let mut first = None;
        for end in [a, b] {
            for c in &corners {
                let p = (end + c).into();
                let i = match rgb {
                    Some(rgb) => self.push_coloured_vertex(p, rgb)?,
                    None => self.push_vertex(p)?,
                };
                first.get_or_insert(i);
            }
        }
        let n = first.unwrap_or(0);
        for k in 0..4 {
            let k1 = (k + 1) % 4;
            self.push_face(group, &[n + k, n + k1, n + 4 + k1, n + 4 + k])?;
        }
        Ok(())
    }

    /// Adds the vertices of `piece` (with their colours, if it has them)
    /// and the faces of its groups to `group`, their materials left out:
    /// a mesh built a piece at a time.
    ///
    /// # Errors
    /// As [`Mesh::push_vertex`] and [`Mesh::push_face`].
    pub fn append(&mut self, group: GroupId, piece: &Mesh) -> Result<(), MeshError> {
        let before = u32::try_from(self.positions.len()).map_err(|_| MeshError::TooManyVertices)?;
        for (k, &p) in piece.positions.iter().enumerate() {
            match piece.colours.as_ref().and_then(|c| c.get(k)) {
                Some(&rgb) => self.push_coloured_vertex(p, rgb)?,
                None => self.push_vertex(p)?,
            };
        }
        let mut corners = Vec::new();
        for face in piece.groups.iter().flat_map(Group::faces) {
            corners.clear();
            corners.extend(face.iter().map(|&c| before + c));
            self.push_face(group, &corners)?;
        }
        Ok(())
    }

    /// The vertex positions.
    #[must_use]
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// The vertex colours, when given.
    #[must_use]
    pub fn colours(&self) -> Option<&[Rgb]> {
        self.colours.as_deref()
    }

    /// The materials, in the order added.
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The groups, in the order started.
    #[must_use]
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The number of triangles once polygons are fanned.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.groups
            .iter()
            .flat_map(Group::faces)
            .map(|f| f.len() - 2)
            .sum()
    }

    /// The vertex normals: those given, or smooth ones, each the sum of
    /// its triangles' face normals weighted by their areas, made unit
    /// length (`[0, 0, 1]` for a vertex on no triangle of any area).
    #[must_use]
    pub fn vertex_normals(&self) -> Vec<[f32; 3]> {
        if let Some(n) = &self.normals {
            return n.clone();
        }
        let mut sums = vec![Vector3::<f64>::zeros(); self.positions.len()];
        for t in self.groups.iter().flat_map(Group::triangles) {
            let [a, b, c] = t.map(|i| Vector3::from(self.positions[i as usize]));
            // |(b − a) × (c − a)| is twice the area: the weight.
            let n = (b - a).cross(&(c - a));
            for i in t {
                sums[i as usize] += n;
            }
        }
        sums.into_iter()
            .map(|s| {
                let len = s.norm();
                if len > 0.0 && len.is_finite() {
                    [s.x, s.y, s.z].map(|c| (c / len) as f32)
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect()
    }

    /// The colour of every vertex: the given colours, or else that of the
    /// material of the first group using the vertex (white for a vertex in
    /// no group with a material); `None` when the mesh has neither.
    #[must_use]
    pub fn resolved_colours(&self) -> Option<Vec<Rgb>> {
        if let Some(c) = &self.colours {
            return Some(c.clone());
        }
        if self.groups.iter().all(|g| g.material.is_none()) {
            return None;
        }
        let mut colours: Vec<Option<Rgb>> = vec![None; self.positions.len()];
        for g in &self.groups {
            let Some(m) = g.material else { continue };
            for &i in &g.corners {
                colours[i as usize].get_or_insert(self.materials[m].colour);
            }
        }
        Some(colours.into_iter().map(|c| c.unwrap_or([255; 3])).collect())
    }
}

/// `a` at length `s` (the zero vector stays 0).
fn scaled(a: Vector3<f64>, s: f64) -> Vector3<f64> {
    let n = a.norm();
    if n == 0.0 {
        return Vector3::zeros();
    }
    a * s / n
}
#[cfg(test)]
mod tests {
    use super::*;

    /// A plant: two prisms in two colour groups and a leaf polygon.
    pub(super) fn plant() -> Mesh {
        let mut m = Mesh::new();
        m.comment("morphogen L-system plant");
        let bark = m.material("colour_0", [101, 67, 33]).unwrap();
        let leaf = m.material("colour_8", [50, 130, 45]).unwrap();
        assert_eq!(m.material("colour_0", [0, 0, 0]).unwrap(), bark);
        let stem = m.group(Some("colour_0"), Some(bark)).unwrap();
        m.push_square_prism(stem, [[0.0; 3], [0.0, 1.0, 0.0]], 2.0, None)
            .unwrap();
        let green = m.group(Some("colour_8"), Some(leaf)).unwrap();
        m.push_square_prism(green, [[0.0, 1.0, 0.0], [1.0, 2.0, 0.0]], 0.5, None)
            .unwrap();
        let first = m.positions().len() as u32;
        for p in [
            [1.0, 2.0, 0.0],
            [2.0, 2.0, 0.0],
            [2.5, 3.0, 0.0],
            [1.5, 3.5, 0.0],
        ] {
            m.push_vertex(p).unwrap();
        }
        m.push_face(green, &[first, first + 1, first + 2, first + 3])
            .unwrap();
        m
    }

    #[test]
    fn prisms_are_the_plant_writers_and_face_outwards() {
        let m = plant();
        // Along +y with width 2: h = x, u = d × h = −z, v = d × u = −x.
        assert_eq!(
            &m.positions()[..8],
            &[
                [-1.0, 0.0, -1.0],
                [-1.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 0.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, 1.0, 1.0],
                [1.0, 1.0, 1.0],
                [1.0, 1.0, -1.0],
            ]
        );
        let g = &m.groups()[0];
        assert_eq!(
            g.faces().collect::<Vec<_>>(),
            [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
        );
        // Each side's normal points away from the axis.
        for f in g.faces() {
            let [a, b, c] = [f[0], f[1], f[2]].map(|i| Vector3::from(m.positions()[i as usize]));
            let n = (b - a).cross(&(c - a));
            let centre = Vector3::new((a.x + c.x) / 2.0, 0.0, (a.z + c.z) / 2.0);
            assert!(n.dot(&centre) > 0.0, "face {f:?}");
        }
        assert_eq!(m.triangle_count(), 8 + 8 + 2);
    }

    #[test]
    fn normals_are_area_weighted_and_unit() {
        // Vertex 0 is on a triangle of area 2 in the x–y plane (normal +z)
        // and one of area 1 in the x–z plane (normal −y): the weighted sum
        // is (0, −1, 2), the unweighted one would be (0, −1, 1).
        let m = Mesh::from_triangles(
            vec![
                [0.0; 3],
                [2.0, 0.0, 0.0],
                [0.0, 2.0, 0.0],
                [0.0, 0.0, 1.0],
                [9.0; 3],
            ],
            &[[0, 1, 2], [0, 1, 3]],
        )
        .unwrap();
        let n = m.vertex_normals();
        let k = 5f64.sqrt();
        let expected = [0.0, -1.0 / k, 2.0 / k].map(|c| c as f32);
        assert_eq!(n[0], expected);
        assert_eq!(n[2], [0.0, 0.0, 1.0]);
        assert_eq!(n[3], [0.0, -1.0, 0.0]);
        // Vertex 4 is on no triangle.
        assert_eq!(n[4], [0.0, 0.0, 1.0]);
        // Given normals win.
        let mut m = m;
        assert!(m.set_normals(vec![[1.0, 0.0, 0.0]]).is_err());
        m.set_normals(vec![[1.0, 0.0, 0.0]; 5]).unwrap();
        assert_eq!(m.vertex_normals()[0], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn bad_meshes_are_refused_with_the_reason() {
        let mut m = Mesh::from_triangles(vec![[0.0; 3]; 3], &[[0, 1, 2]]).unwrap();
        let g = GroupId(0);
        assert_eq!(
            m.push_face(g, &[0, 1, 3]),
            Err(MeshError::VertexOutOfRange {
                index: 3,
                vertices: 3
            })
        );
        assert_eq!(m.push_face(g, &[0, 1]), Err(MeshError::FaceTooSmall(2)));
        assert_eq!(
            m.push_face(GroupId(4), &[0, 1, 2]),
            Err(MeshError::UnknownGroup(4))
        );
        assert_eq!(
            m.group(Some("module 1"), None),
            Err(MeshError::InvalidName("module 1".into()))
        );
        assert_eq!(
            m.group(None, Some(MaterialId(0))),
            Err(MeshError::UnknownMaterial(0))
        );
        assert!(m.material("", [0; 3]).is_err());
        assert!(Mesh::from_triangles(vec![[0.0; 3]; 2], &[[0, 1, 2]]).is_err());
        let mut glb = GlbWriter::new("x", 1.0);
        glb.push_frame(&m, 1.0).unwrap();
        assert_eq!(
            glb.push_frame(&m, 1.0),
            Err(MeshError::TimeNotIncreasing { frame: 1 })
        );
        assert_eq!(
            glb.push_frame(&m, f32::NAN),
            Err(MeshError::TimeNotIncreasing { frame: 1 })
        );
    }
}
