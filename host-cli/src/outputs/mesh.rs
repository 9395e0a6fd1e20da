//! One mesh writer for every model (issue 19, point 3): a model-independent
//! [`Mesh`] (positions, polygon faces in named groups, optional per-vertex
//! colours and normals, named materials) written as Wavefront OBJ with an
//! `.mtl` ([`write_obj`]) or as binary glTF 2.0 ([`write_glb`],
//! [`GlbWriter`]) with `POSITION`, `NORMAL`, `COLOR_0` and indices, one mesh
//! per frame and, for several frames, an animation that shows one frame at
//! a time.
//!
//! Every model's geometry fits: horn rings (a group `module_<i>` per
//! module, triangles), body and bone surfaces (one unnamed group of
//! triangles under an object name), plant segments as square prisms
//! ([`Mesh::push_square_prism`], four quads each) and leaves as polygons,
//! grouped or coloured by colour index, and a mosaic on a surface
//! (per-vertex colours).
//!
//! Numbers: positions are `f64`, which hold a fixed-point (`Fx`) value
//! exactly; OBJ prints them through [`super::text`] (5 decimals read off
//! the fixed-point bits, or the exact text), glTF stores them as `f32`.
//!
//! # Animation in glTF
//! Frame `k` is node `frame_k` (a child of one root node) with its own mesh;
//! a glTF animation switches the frames on the nodes' scale, 1 ↔ 0, with
//! `STEP` interpolation over one shared list of key times. This works for
//! frames of any topology (a growing horn or bone gains vertices) and in
//! every viewer (morph targets would need one topology, and many viewers
//! handle only a few of them at once). Its cost equals morph targets':
//! each frame's positions and normals are stored once (24 bytes a vertex),
//! while index and colour blocks equal to the previous frame's are shared,
//! not repeated (the trot's topology and colours are stored once). A viewer
//! that does not play the animation shows frame 0.

use std::fmt;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};

use super::text;
use super::vector::{cross, dot, sub};
use crate::atomic::{OutputFile, write_atomic};

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

    /// The number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.ends.len()
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
        let d = sub(b, a);
        let helper = if d[0].abs() < d[1].abs().max(d[2].abs()) {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let r = width.max(1e-4) / 2.0;
        let u = scaled(cross(d, helper), r);
        let v = scaled(cross(d, u), r);
        let corners = [
            [u[0] + v[0], u[1] + v[1], u[2] + v[2]],
            [v[0] - u[0], v[1] - u[1], v[2] - u[2]],
            [-u[0] - v[0], -u[1] - v[1], -u[2] - v[2]],
            [u[0] - v[0], u[1] - v[1], u[2] - v[2]],
        ];
        let mut first = None;
        for end in [a, b] {
            for c in &corners {
                let p = [end[0] + c[0], end[1] + c[1], end[2] + c[2]];
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
        let mut sums = vec![[0.0f64; 3]; self.positions.len()];
        for t in self.groups.iter().flat_map(Group::triangles) {
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            // |(b − a) × (c − a)| is twice the area: the weight.
            let n = cross(sub(b, a), sub(c, a));
            for i in t {
                let s = &mut sums[i as usize];
                *s = [s[0] + n[0], s[1] + n[1], s[2] + n[2]];
            }
        }
        sums.into_iter()
            .map(|s| {
                let len = dot(s, s).sqrt();
                if len > 0.0 && len.is_finite() {
                    s.map(|c| (c / len) as f32)
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

fn scaled(a: [f64; 3], s: f64) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    if n == 0.0 {
        return [0.0; 3];
    }
    [a[0] * s / n, a[1] * s / n, a[2] * s / n]
}

// ------------------------------------------------------------------ OBJ

/// How coordinates are printed in an OBJ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Numbers {
    /// Rounded to 5 decimals as `{:.5}` prints them
    /// ([`text::decimals_5`]; the horn, body, bone and mosaic OBJ files).
    Decimals5,
    /// In full: fixed-point values exactly, computed ones in their
    /// shortest form ([`text::float`]; the plant OBJ).
    Exact,
}

/// What an OBJ holds beyond `v` and `f` lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjStyle {
    /// How coordinates are printed.
    pub numbers: Numbers,
    /// `vn` lines (one per vertex, given or computed) and `f a//a …`.
    pub normals: bool,
    /// Vertex colours as `v x y z r g b` (r, g, b from 0 to 1; an
    /// extension read by MeshLab, Blender and others), when the mesh has
    /// them.
    pub vertex_colours: bool,
}

impl ObjStyle {
    /// The horn, body and bone OBJ files as written before this module:
    /// 5 decimals, no normals, no vertex colours. A mesh without materials
    /// gives the same bytes as those writers.
    pub const PLAIN: ObjStyle = ObjStyle {
        numbers: Numbers::Decimals5,
        normals: false,
        vertex_colours: false,
    };

    /// [`ObjStyle::PLAIN`] with normals and vertex colours.
    pub const FULL: ObjStyle = ObjStyle {
        numbers: Numbers::Decimals5,
        normals: true,
        vertex_colours: true,
    };
}

fn number(line: &mut Vec<u8>, numbers: Numbers, x: f64) {
    match numbers {
        Numbers::Decimals5 => text::decimals_5(line, x),
        Numbers::Exact => text::float(line, x),
    }
}

/// Writes `mesh` as OBJ text to `out`: its comments, `mtllib library`
/// (when given and the mesh has materials), `o` (when named), the `v`
/// lines (and `vn`), then each group's `g`, `usemtl` and `f` lines.
///
/// # Errors
/// When `out` fails.
pub fn obj(
    mesh: &Mesh,
    style: ObjStyle,
    library: Option<&str>,
    out: &mut impl Write,
) -> io::Result<()> {
    for c in &mesh.comments {
        writeln!(out, "# {c}")?;
    }
    if let Some(lib) = library.filter(|_| !mesh.materials.is_empty()) {
        writeln!(out, "mtllib {lib}")?;
    }
    if let Some(o) = &mesh.object {
        writeln!(out, "o {o}")?;
    }
    obj_part(mesh, style, 0, out)
}

/// Writes the `v` (and `vn`), `g`, `usemtl` and `f` lines of `mesh` to
/// `out` as the part of a larger OBJ whose earlier parts hold `before`
/// vertices: its faces' indices are shifted by that many. Streams a mesh
/// too large to hold as one, a piece at a time (the plant's segments).
///
/// # Errors
/// When `out` fails.
pub fn obj_part(mesh: &Mesh, style: ObjStyle, before: u64, out: &mut impl Write) -> io::Result<()> {
    let colours = mesh.colours.as_deref().filter(|_| style.vertex_colours);
    // A colour channel is one of 256 bytes: its text (` 0.41176`) once.
    let channels: Vec<Vec<u8>> = if colours.is_some() {
        (0..=255u8)
            .map(|k| {
                let mut text = vec![b' '];
                text::decimals_5(&mut text, f64::from(k) / 255.0);
                text
            })
            .collect()
    } else {
        Vec::new()
    };
    let mut line = Vec::with_capacity(96);
    for (i, p) in mesh.positions.iter().enumerate() {
        line.clear();
        line.push(b'v');
        for &c in p {
            line.push(b' ');
            number(&mut line, style.numbers, c);
        }
        if let Some(rgb) = colours.map(|c| c[i]) {
            for k in rgb {
                line.extend_from_slice(&channels[usize::from(k)]);
            }
        }
        line.push(b'\n');
        out.write_all(&line)?;
    }
    if style.normals {
        for n in mesh.vertex_normals() {
            line.clear();
            line.extend_from_slice(b"vn");
            for c in n {
                line.push(b' ');
                text::decimals_5(&mut line, f64::from(c));
            }
            line.push(b'\n');
            out.write_all(&line)?;
        }
    }
    for g in &mesh.groups {
        if let Some(name) = &g.name {
            writeln!(out, "g {name}")?;
        }
        if let Some(m) = g.material {
            writeln!(out, "usemtl {}", mesh.materials[m].name)?;
        }
        for face in g.faces() {
            line.clear();
            line.push(b'f');
            for &k in face {
                line.push(b' ');
                text::int(&mut line, before + u64::from(k) + 1);
                if style.normals {
                    line.extend_from_slice(b"//");
                    text::int(&mut line, before + u64::from(k) + 1);
                }
            }
            line.push(b'\n');
            out.write_all(&line)?;
        }
    }
    Ok(())
}

/// Writes a material library: `newmtl`, `Kd` (the sRGB colour over 255,
/// 5 decimals) and `illum 1` (diffuse only) for each material.
///
/// # Errors
/// When `out` fails.
pub fn mtl(materials: &[Material], out: &mut impl Write) -> io::Result<()> {
    out.write_all(b"# morphogen materials\n")?;
    let mut line = Vec::with_capacity(64);
    for m in materials {
        line.clear();
        line.extend_from_slice(b"newmtl ");
        line.extend_from_slice(m.name.as_bytes());
        line.extend_from_slice(b"\nKd");
        for c in m.colour {
            line.push(b' ');
            text::decimals_5(&mut line, f64::from(c) / 255.0);
        }
        line.extend_from_slice(b"\nillum 1\n");
        out.write_all(&line)?;
    }
    Ok(())
}

/// Writes `path` (an `.obj`) and, when the mesh has materials, the
/// library beside it (`path` with extension `.mtl`, named by `mtllib`);
/// returns the paths written. Each file is written whole or not at all.
///
/// # Errors
/// When a file cannot be written.
pub fn write_obj(path: &Path, mesh: &Mesh, style: ObjStyle) -> Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(2);
    let library = if mesh.materials.is_empty() {
        None
    } else {
        let lib = path.with_extension("mtl");
        OutputFile::write_with(&lib, |f| mtl(&mesh.materials, f))?;
        let name = lib
            .file_name()
            .and_then(|n| n.to_str())
            .context("the material library's name is not UTF-8")?
            .to_owned();
        written.push(lib);
        Some(name)
    };
    OutputFile::write_with(path, |f| obj(mesh, style, library.as_deref(), f))?;
    written.insert(0, path.to_path_buf());
    Ok(written)
}

/// The material library (an `.mtl`) that the OBJ files of a run's frames
/// share ([`write_frame_obj`]): written from the first frame's mesh.
#[derive(Debug)]
pub struct Library {
    path: PathBuf,
    written: bool,
}

impl Library {
    /// The library `name` in `dir`, not written yet.
    #[must_use]
    pub fn new(dir: &Path, name: &str) -> Library {
        Library {
            path: dir.join(name),
            written: false,
        }
    }

    /// Writes the materials of `mesh`, unless a frame already did.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn write_once(&mut self, mesh: &Mesh) -> Result<()> {
        if !self.written {
            OutputFile::write_with(&self.path, |f| mtl(&mesh.materials, f))?;
            self.written = true;
        }
        Ok(())
    }

    /// Its path, once written.
    #[must_use]
    pub fn written(self) -> Option<PathBuf> {
        self.written.then_some(self.path)
    }
}

/// Writes `path` (an `.obj`) of one frame of many, naming the material
/// library `library` (a file beside it, written once by a [`Library`]).
///
/// # Errors
/// When the file cannot be written.
pub fn write_frame_obj(path: &Path, mesh: &Mesh, style: ObjStyle, library: &str) -> Result<()> {
    OutputFile::write_with(path, |f| obj(mesh, style, Some(library), f))
}

// ------------------------------------------------------------------ glTF

/// Frames to write as one glTF scene ([`write_glb`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The scene's and its root node's name.
    pub name: String,
    /// Metres per model unit (0.01 for centimetres): the root node's
    /// scale, so positions stay the model's numbers.
    pub metres_per_unit: f32,
    /// The frames: their time (seconds, rising) and mesh.
    pub frames: Vec<(f32, Mesh)>,
}

/// Writes `scene` as binary glTF 2.0 to `path`, whole or not at all.
///
/// # Errors
/// When a frame's time does not rise, or the file cannot be written.
pub fn write_glb(path: &Path, scene: &Scene) -> Result<()> {
    let mut glb = GlbWriter::new(&scene.name, scene.metres_per_unit);
    for (seconds, mesh) in &scene.frames {
        glb.push_frame(mesh, *seconds)?;
    }
    glb.write(path)
}

/// Index and colour blocks of the previous frame, shared when equal.
#[derive(Debug, Default)]
struct Shared {
    indices: Vec<(Vec<u8>, json::Index<json::Accessor>)>,
    colours: Option<(Vec<u8>, json::Index<json::Accessor>)>,
}

/// A binary glTF file built one frame at a time (so a writer holds one
/// frame's mesh, plus the binary data so far).
#[derive(Debug)]
pub struct GlbWriter {
    root: json::Root,
    bin: Vec<u8>,
    name: String,
    metres_per_unit: f32,
    /// Each frame's time and node.
    frames: Vec<(f32, json::Index<json::Node>)>,
    /// Materials by name.
    materials: Vec<(String, json::Index<json::Material>)>,
    shared: Shared,
}

/// glTF's byte length limit on a buffer (GLB's header is 32-bit).
const GLB_LIMIT: usize = u32::MAX as usize - 1024;

const ARRAY_BUFFER: json::buffer::Target = json::buffer::Target::ArrayBuffer;
const ELEMENT_ARRAY_BUFFER: json::buffer::Target = json::buffer::Target::ElementArrayBuffer;

/// An sRGB channel as a linear one (the IEC 61966-2-1 curve), 0–255.
fn linear(c: u8) -> u8 {
    let c = f64::from(c) / 255.0;
    let l = if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    (l * 255.0).round() as u8
}

impl GlbWriter {
    /// An empty file whose scene and root node are called `name`, scaled
    /// by `metres_per_unit`.
    #[must_use]
    pub fn new(name: &str, metres_per_unit: f32) -> GlbWriter {
        let root = json::Root {
            asset: json::Asset {
                generator: Some("morphogen".to_owned()),
                version: "2.0".to_owned(),
                copyright: None,
                extensions: None,
                extras: Default::default(),
                min_version: None,
            },
            ..json::Root::default()
        };
        GlbWriter {
            root,
            bin: Vec::new(),
            name: name.to_owned(),
            metres_per_unit,
            frames: Vec::new(),
            materials: Vec::new(),
            shared: Shared::default(),
        }
    }

    /// Appends `bytes` as a buffer view (4-byte aligned); returns it.
    fn view(
        &mut self,
        bytes: &[u8],
        target: json::buffer::Target,
    ) -> Result<json::Index<json::buffer::View>, MeshError> {
        if self.bin.len() + bytes.len() + 3 > GLB_LIMIT {
            return Err(MeshError::TooLarge);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        Ok(self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: Default::default(),
        }))
    }

    /// Appends an accessor of `count` elements over `bytes`.
    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        normalized: bool,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> Result<json::Index<json::Accessor>, MeshError> {
        let view = match target {
            Some(t) => self.view(bytes, t)?,
            None => {
                // Animation data: a view without a target.
                let v = self.view(bytes, ARRAY_BUFFER)?;
                self.root.buffer_views[v.value()].target = None;
                v
            }
        };
        let (min, max) = match bounds {
            Some((lo, hi)) => (Some(json::Value::from(lo)), Some(json::Value::from(hi))),
            None => (None, None),
        };
        Ok(self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized,
            sparse: None,
        }))
    }

    fn material(&mut self, name: &str) -> json::Index<json::Material> {
        if let Some((_, m)) = self.materials.iter().find(|(n, _)| n == name) {
            return *m;
        }
        // Colour lives in COLOR_0: the material is white, not metallic,
        // and seen from both sides (leaves are single faces).
        let m = self.root.push(json::Material {
            name: Some(name.to_owned()),
            double_sided: true,
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                metallic_factor: json::material::StrengthFactor(0.0),
                roughness_factor: json::material::StrengthFactor(0.8),
                ..Default::default()
            },
            ..Default::default()
        });
        self.materials.push((name.to_owned(), m));
        m
    }

    /// Adds `mesh` as the next frame, shown from `seconds` until the next
    /// frame's time.
    ///
    /// # Errors
    /// When `seconds` is not finite or not after the previous frame's, or
    /// the data passes glTF's size limit.
    pub fn push_frame(&mut self, mesh: &Mesh, seconds: f32) -> Result<(), MeshError> {
        use json::accessor::{ComponentType as C, Type as T};
        let frame = self.frames.len();
        if !seconds.is_finite() || self.frames.last().is_some_and(|&(t, _)| seconds <= t) {
            return Err(MeshError::TimeNotIncreasing { frame });
        }
        let name = format!("frame_{frame}");
        let mut json_mesh = None;
        let vertices = mesh.positions.len();
        if vertices > 0 && mesh.triangle_count() > 0 {
            let mut attributes = std::collections::BTreeMap::new();
            // POSITION, with the bounds glTF requires (of the f32 values).
            let points: Vec<[f32; 3]> =
                mesh.positions.iter().map(|p| p.map(|c| c as f32)).collect();
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for p in &points {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let bytes: Vec<u8> = points
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect();
            let a = self.accessor(
                &bytes,
                Some(ARRAY_BUFFER),
                vertices,
                C::F32,
                T::Vec3,
                false,
                Some((lo.to_vec(), hi.to_vec())),
            )?;
            attributes.insert(Valid(json::mesh::Semantic::Positions), a);
            let bytes: Vec<u8> = mesh
                .vertex_normals()
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes())
                .collect();
            let a = self.accessor(
                &bytes,
                Some(ARRAY_BUFFER),
                vertices,
                C::F32,
                T::Vec3,
                false,
                None,
            )?;
            attributes.insert(Valid(json::mesh::Semantic::Normals), a);
            if let Some(colours) = mesh.resolved_colours() {
                let table: Vec<u8> = (0..=255).map(linear).collect();
                let bytes: Vec<u8> = colours
                    .iter()
                    .flat_map(|c| {
                        [
                            table[c[0] as usize],
                            table[c[1] as usize],
                            table[c[2] as usize],
                            255,
                        ]
                    })
                    .collect();
                let a = match &self.shared.colours {
                    Some((b, a)) if *b == bytes => *a,
                    _ => {
                        let a = self.accessor(
                            &bytes,
                            Some(ARRAY_BUFFER),
                            vertices,
                            C::U8,
                            T::Vec4,
                            true,
                            None,
                        )?;
                        self.shared.colours = Some((bytes, a));
                        a
                    }
                };
                attributes.insert(Valid(json::mesh::Semantic::Colors(0)), a);
            }
            // Indices: u16 while they fit (65 535 is reserved), per group.
            let short = vertices < 65_535;
            let mut shared = Vec::new();
            let mut primitives = Vec::new();
            for g in &mesh.groups {
                let triangles: Vec<u32> = g.triangles().flatten().collect();
                if triangles.is_empty() {
                    continue;
                }
                let bytes: Vec<u8> = if short {
                    triangles
                        .iter()
                        .flat_map(|&i| (i as u16).to_le_bytes())
                        .collect()
                } else {
                    triangles.iter().flat_map(|&i| i.to_le_bytes()).collect()
                };
                let previous = self.shared.indices.iter().find(|(b, _)| *b == bytes);
                let a = match previous {
                    Some((_, a)) => *a,
                    None => self.accessor(
                        &bytes,
                        Some(ELEMENT_ARRAY_BUFFER),
                        triangles.len(),
                        if short { C::U16 } else { C::U32 },
                        T::Scalar,
                        false,
                        None,
                    )?,
                };
                shared.push((bytes, a));
                let material = match g.material {
                    Some(m) => mesh.materials[m].name.clone(),
                    None => "default".to_owned(),
                };
                primitives.push(json::mesh::Primitive {
                    attributes: attributes.clone(),
                    extensions: None,
                    extras: Default::default(),
                    indices: Some(a),
                    material: Some(self.material(&material)),
                    mode: Valid(json::mesh::Mode::Triangles),
                    targets: None,
                });
            }
            self.shared.indices = shared;
            json_mesh = Some(self.root.push(json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(name.clone()),
                primitives,
                weights: None,
            }));
        }
        let node = self.root.push(json::Node {
            mesh: json_mesh,
            name: Some(name),
            // Frame 0 is what a viewer shows without playing.
            scale: (frame > 0).then_some([0.0; 3]),
            ..json::Node::default()
        });
        self.frames.push((seconds, node));
        Ok(())
    }

    /// The file's bytes: the scene, the animation (for two or more
    /// frames; the last frame lasts as long as the one before it) and the
    /// GLB container.
    ///
    /// # Errors
    /// When the data passes glTF's size limit.
    pub fn finish(mut self) -> Result<Vec<u8>, MeshError> {
        use json::accessor::{ComponentType as C, Type as T};
        let children: Vec<_> = self.frames.iter().map(|&(_, n)| n).collect();
        let root = self.root.push(json::Node {
            children: (!children.is_empty()).then_some(children),
            name: Some(self.name.clone()),
            scale: (self.metres_per_unit != 1.0).then_some([self.metres_per_unit; 3]),
            ..json::Node::default()
        });
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: Some(self.name.clone()),
            nodes: vec![root],
        });
        self.root.scene = Some(scene);
        if self.frames.len() >= 2 {
            let n = self.frames.len();
            let mut times: Vec<f32> = self.frames.iter().map(|&(t, _)| t).collect();
            let end = times[n - 1] + (times[n - 1] - times[n - 2]);
            // An end time that rounds onto the last one would not rise.
            times.push(if end > times[n - 1] { end } else { f32::MAX });
            let bytes: Vec<u8> = times.iter().flat_map(|t| t.to_le_bytes()).collect();
            let bounds = (vec![times[0]], vec![times[n]]);
            let input =
                self.accessor(&bytes, None, n + 1, C::F32, T::Scalar, false, Some(bounds))?;
            let mut channels = Vec::with_capacity(n);
            let mut samplers = Vec::with_capacity(n);
            for (k, &(_, node)) in self.frames.clone().iter().enumerate() {
                let on = |key: usize| key == k || (k == n - 1 && key == n);
                let bytes: Vec<u8> = (0..=n)
                    .flat_map(|key| [if on(key) { 1.0f32 } else { 0.0 }; 3])
                    .flat_map(f32::to_le_bytes)
                    .collect();
                let output = self.accessor(&bytes, None, n + 1, C::F32, T::Vec3, false, None)?;
                let sampler = json::Index::push(
                    &mut samplers,
                    json::animation::Sampler {
                        extensions: None,
                        extras: Default::default(),
                        input,
                        interpolation: Valid(json::animation::Interpolation::Step),
                        output,
                    },
                );
                channels.push(json::animation::Channel {
                    sampler,
                    target: json::animation::Target {
                        extensions: None,
                        extras: Default::default(),
                        node,
                        path: Valid(json::animation::Property::Scale),
                    },
                    extensions: None,
                    extras: Default::default(),
                });
            }
            self.root.push(json::Animation {
                extensions: None,
                extras: Default::default(),
                channels,
                name: Some("frames".to_owned()),
                samplers,
            });
        }
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
        }
        let mut json = self.root.to_vec().map_err(|_| MeshError::TooLarge)?;
        json.resize(json.len().next_multiple_of(4), b' ');
        glb(&json, &self.bin)
    }

    /// Writes the file to `path`, whole or not at all.
    ///
    /// # Errors
    /// When the data passes glTF's size limit or the file cannot be
    /// written.
    pub fn write(self, path: &Path) -> Result<()> {
        let bytes = self
            .finish()
            .with_context(|| format!("cannot write {}", path.display()))?;
        write_atomic(path, &bytes)
    }
}

/// The GLB container: a 12-byte header, the JSON chunk (padded with
/// spaces) and, when there is binary data, the BIN chunk (padded with
/// zeros); all lengths little-endian `u32`.
fn glb(json: &[u8], bin: &[u8]) -> Result<Vec<u8>, MeshError> {
    let bin_padded = bin.len().next_multiple_of(4);
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin_padded };
    let length = |n: usize| u32::try_from(n).map_err(|_| MeshError::TooLarge);
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&length(total)?.to_le_bytes());
    out.extend_from_slice(&length(json.len())?.to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    if !bin.is_empty() {
        out.extend_from_slice(&length(bin_padded)?.to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `bits / 65 536`, as the streams' fixed-point coordinates read.
    fn fx(bits: i32) -> f64 {
        f64::from(bits) / 65_536.0
    }

    fn obj_text(mesh: &Mesh, style: ObjStyle, library: Option<&str>) -> String {
        let mut out = Vec::new();
        obj(mesh, style, library, &mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// Two horn-like modules of one triangle each, as `horn::obj` wrote
    /// them (two comment lines, 5 decimals off the bits, `g module_<i>`).
    #[test]
    fn a_mesh_without_materials_prints_as_the_horn_and_body_writers_did() {
        let mut m = Mesh::new();
        m.comment("morphogen horn, frame 0 at t = 0.5 years\nunits: cm; skull frame (module k grows along +x)");
        // 1 137 017 / 65 536 = 17.3495025… → 17.34950; a computed value
        // (a cap's centroid) goes through `{:.5}`.
        for p in [
            [fx(1_137_017), fx(661_140), fx(-59_783)],
            [fx(0), fx(-1), fx(65_536 * 3)],
            [1.0 / 3.0, -2.5e-6, 7.0],
            [fx(32_768), fx(98_304), fx(-98_304)],
        ] {
            m.push_vertex(p).unwrap();
        }
        let g1 = m.group(Some("module_1"), None).unwrap();
        let g2 = m.group(Some("module_2"), None).unwrap();
        m.push_face(g1, &[0, 1, 2]).unwrap();
        m.push_face(g2, &[1, 3, 2]).unwrap();
        m.push_face(g1, &[2, 1, 3]).unwrap();
        let expected = "# morphogen horn, frame 0 at t = 0.5 years\n\
                        # units: cm; skull frame (module k grows along +x)\n\
                        v 17.34950 10.08820 -0.91222\n\
                        v 0.00000 -0.00002 3.00000\n\
                        v 0.33333 -0.00000 7.00000\n\
                        v 0.50000 1.50000 -1.50000\n\
                        g module_1\nf 1 2 3\nf 3 2 4\ng module_2\nf 2 4 3\n";
        assert_eq!(obj_text(&m, ObjStyle::PLAIN, Some("unused.mtl")), expected);
        // The body and bone writers: a comment, `o body`, no groups.
        let body = {
            let mut b = Mesh::from_triangles(
                vec![[0.0; 3], [fx(1), 1.0, 0.0], [0.0, 0.5, 2.0]],
                &[[0, 1, 2]],
            )
            .unwrap();
            b.comment("horse-trot frame 0, age 6.00 months");
            b.set_object("body").unwrap();
            b
        };
        assert_eq!(
            obj_text(&body, ObjStyle::PLAIN, None),
            "# horse-trot frame 0, age 6.00 months\no body\nv 0.00000 0.00000 0.00000\n\
             v 0.00002 1.00000 0.00000\nv 0.00000 0.50000 2.00000\nf 1 2 3\n"
        );
    }

    /// A plant: two prisms in two colour groups and a leaf polygon.
    fn plant() -> Mesh {
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
            let [a, b, c] = [f[0], f[1], f[2]].map(|i| m.positions()[i as usize]);
            let n = cross(sub(b, a), sub(c, a));
            let centre = [(a[0] + c[0]) / 2.0, 0.0, (a[2] + c[2]) / 2.0];
            assert!(dot(n, centre) > 0.0, "face {f:?}");
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
    fn obj_with_materials_has_a_library_normals_and_usemtl_per_group() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plant.obj");
        let m = plant();
        let written = write_obj(&path, &m, ObjStyle::FULL).unwrap();
        assert_eq!(written, [path.clone(), dir.path().join("plant.mtl")]);
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let count = |p: &str| lines.iter().filter(|l| l.starts_with(p)).count();
        assert_eq!(lines[1], "mtllib plant.mtl");
        assert_eq!(count("v "), 20);
        assert_eq!(count("vn "), 20);
        assert_eq!(count("f "), 9);
        assert_eq!(count("usemtl "), 2);
        let usemtl: Vec<_> = lines.iter().filter(|l| l.starts_with("usemtl")).collect();
        assert_eq!(usemtl, [&"usemtl colour_0", &"usemtl colour_8"]);
        // The leaf is one quad face, its corners with their normals, all +z.
        assert_eq!(lines.last().unwrap(), &"f 17//17 18//18 19//19 20//20");
        assert!(lines[2].starts_with("v ") && lines[22].starts_with("vn "));
        assert_eq!(lines[42..44], ["g colour_0", "usemtl colour_0"]);
        assert_eq!(lines[48..50], ["g colour_8", "usemtl colour_8"]);
        let vn: Vec<[f64; 3]> = lines
            .iter()
            .filter_map(|l| l.strip_prefix("vn "))
            .map(|l| {
                let c: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                [c[0], c[1], c[2]]
            })
            .collect();
        assert_eq!(vn[16], [0.0, 0.0, 1.0]);
        for n in &vn {
            assert!((dot(*n, *n) - 1.0).abs() < 1e-4, "{n:?}");
        }
        // Every face corner names a vertex and its own normal.
        for l in lines.iter().filter_map(|l| l.strip_prefix("f ")) {
            for corner in l.split(' ') {
                let (v, n) = corner.split_once("//").unwrap();
                assert_eq!(v, n);
                assert!((1..=20).contains(&v.parse::<usize>().unwrap()));
            }
        }
        let mtl = std::fs::read_to_string(dir.path().join("plant.mtl")).unwrap();
        assert_eq!(
            mtl,
            "# morphogen materials\nnewmtl colour_0\nKd 0.39608 0.26275 0.12941\nillum 1\n\
             newmtl colour_8\nKd 0.19608 0.50980 0.17647\nillum 1\n"
        );
        // Vertex colours, when the mesh has them, extend the `v` lines.
        let mut c = Mesh::new();
        c.push_coloured_vertex([0.0; 3], [255, 0, 51]).unwrap();
        assert_eq!(c.push_vertex([1.0; 3]), Err(MeshError::MixedColours));
        assert!(
            obj_text(&c, ObjStyle::FULL, None)
                .contains("v 0.00000 0.00000 0.00000 1.00000 0.00000 0.20000\n")
        );
        assert!(obj_text(&c, ObjStyle::PLAIN, None).contains("v 0.00000 0.00000 0.00000\n"));
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

    /// A closed box of 8 vertices (0..=1 scaled by `s`), its bottom four
    /// red and top four `top`; with `extra`, a ninth vertex and a fan.
    fn cube(s: f64, top: Rgb, extra: bool) -> Mesh {
        let mut m = Mesh::new();
        for k in 0..8u32 {
            let p = [k & 1, (k >> 1) & 1, k >> 2].map(|b| f64::from(b) * s);
            m.push_coloured_vertex(p, if k < 4 { [255, 0, 0] } else { top })
                .unwrap();
        }
        let g = m.group(Some("box"), None).unwrap();
        for f in [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            m.push_face(g, &f).unwrap();
        }
        if extra {
            let apex = m
                .push_coloured_vertex([0.5 * s, 0.5 * s, 2.0 * s], [0, 0, 255])
                .unwrap();
            let mat = m.material("spike", [0, 0, 255]).unwrap();
            let spike = m.group(Some("spike"), Some(mat)).unwrap();
            m.push_face(spike, &[4, 5, apex]).unwrap();
        }
        m
    }

    fn scene() -> Scene {
        Scene {
            name: "cubes".into(),
            metres_per_unit: 0.01,
            frames: vec![
                (0.0, cube(1.0, [128, 128, 128], false)),
                (0.5, cube(2.0, [128, 128, 128], false)),
                (1.25, cube(3.0, [255, 255, 255], true)),
            ],
        }
    }

    #[test]
    fn glb_reads_back_with_counts_bounds_colours_and_animation() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cubes.glb");
        write_glb(&path, &scene()).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // The container: header, a JSON chunk padded with spaces, BIN.
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!((word(4), word(8)), (2, bytes.len()));
        let json_len = word(12);
        assert_eq!((json_len % 4, &bytes[16..20]), (0, &b"JSON"[..]));
        let bin_at = 20 + json_len;
        assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
        assert_eq!(bin_at + 8 + word(bin_at), bytes.len());
        // Parsing validates the JSON against the glTF rules the crate knows.
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let blob = gltf.blob.clone().unwrap();
        let buffers = |b: gltf::Buffer<'_>| match b.source() {
            gltf::buffer::Source::Bin => Some(&blob[..]),
            gltf::buffer::Source::Uri(_) => None,
        };
        // Every view inside the buffer, 4-aligned; every accessor fills its view.
        for a in gltf.accessors() {
            let v = a.view().unwrap();
            assert_eq!(v.offset() % 4, 0);
            assert!(v.offset() + v.length() <= blob.len());
            assert_eq!(a.offset(), 0);
            assert_eq!(a.count() * a.size(), v.length());
        }
        let scene = gltf.default_scene().unwrap();
        let root = scene.nodes().next().unwrap();
        assert_eq!(root.name(), Some("cubes"));
        assert_eq!(root.transform().decomposed().2, [0.01; 3]);
        let frames: Vec<_> = root.children().collect();
        assert_eq!(frames.len(), 3);
        assert_eq!(gltf.meshes().count(), 3);
        let (mut index_accessors, mut colour_accessors) = (Vec::new(), Vec::new());
        for (k, node) in frames.iter().enumerate() {
            assert_eq!(node.name(), Some(format!("frame_{k}").as_str()));
            let scale = node.transform().decomposed().2;
            assert_eq!(scale, if k == 0 { [1.0; 3] } else { [0.0; 3] });
            let mesh = node.mesh().unwrap();
            let s = [1.0f32, 2.0, 3.0][k];
            let prims: Vec<_> = mesh.primitives().collect();
            assert_eq!(prims.len(), if k == 2 { 2 } else { 1 });
            let p = &prims[0];
            let pos = p.get(&gltf::Semantic::Positions).unwrap();
            let vertices = if k == 2 { 9 } else { 8 };
            assert_eq!(pos.count(), vertices);
            let top = if k == 2 { 2.0 * s } else { s };
            assert_eq!(pos.min().unwrap(), serde_json::json!([0.0, 0.0, 0.0]));
            assert_eq!(pos.max().unwrap(), serde_json::json!([s, s, top]));
            let r = p.reader(buffers);
            let points: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
            assert_eq!(points[7], [s, s, s]);
            let normals: Vec<[f32; 3]> = r.read_normals().unwrap().collect();
            let third = (1.0f32 / 3.0).sqrt();
            assert_eq!(normals.len(), vertices);
            if k < 2 {
                // The corners' normals point out along the diagonals.
                assert!(
                    (normals[0][0] + third).abs() < 1e-6 && (normals[7][2] - third).abs() < 1e-6
                );
            }
            let colours: Vec<[u8; 4]> = r.read_colors(0).unwrap().into_rgba_u8().collect();
            // sRGB 128 is linear 0.2158 (55 of 255); 255 stays 255.
            let grey = if k == 2 { 255 } else { 55 };
            assert_eq!(colours[0], [255, 0, 0, 255]);
            assert_eq!(colours[7], [grey, grey, grey, 255]);
            let indices: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
            assert_eq!(indices.len(), 36);
            assert_eq!(&indices[..6], &[0, 2, 3, 0, 3, 1]);
            index_accessors.push(p.indices().unwrap().index());
            colour_accessors.push(p.get(&gltf::Semantic::Colors(0)).unwrap().index());
            let material = p.material();
            assert_eq!(material.name(), Some("default"));
            assert_eq!(material.pbr_metallic_roughness().metallic_factor(), 0.0);
            if k == 2 {
                let spike = &prims[1];
                assert_eq!(spike.material().name(), Some("spike"));
                let r = spike.reader(buffers);
                assert_eq!(
                    r.read_indices().unwrap().into_u32().collect::<Vec<_>>(),
                    [4, 5, 8]
                );
            }
        }
        // The box's index block is stored once (the spike's is its own);
        // frames 0 and 1 share their colours, frame 2 has other colours.
        assert_eq!(index_accessors[0], index_accessors[1]);
        assert_eq!(index_accessors[1], index_accessors[2]);
        assert_eq!(colour_accessors[0], colour_accessors[1]);
        assert_ne!(colour_accessors[1], colour_accessors[2]);
        let spike = frames[2].mesh().unwrap().primitives().nth(1).unwrap();
        assert_ne!(spike.indices().unwrap().index(), index_accessors[2]);
        assert_eq!(gltf.accessors().count(), 3 * 2 + 2 + 2 + 1 + 3);
        // One animation: each node's scale, STEP, on the frames' times
        // (the last frame lasts as long as the one before it).
        let animations: Vec<_> = gltf.animations().collect();
        assert_eq!(animations.len(), 1);
        let channels: Vec<_> = animations[0].channels().collect();
        assert_eq!(channels.len(), 3);
        for (k, c) in channels.iter().enumerate() {
            assert_eq!(c.target().node().index(), frames[k].index());
            assert_eq!(c.target().property(), gltf::animation::Property::Scale);
            assert_eq!(
                c.sampler().interpolation(),
                gltf::animation::Interpolation::Step
            );
            let r = c.reader(buffers);
            let times: Vec<f32> = r.read_inputs().unwrap().collect();
            assert_eq!(times, [0.0, 0.5, 1.25, 2.0]);
            let gltf::animation::util::ReadOutputs::Scales(scales) = r.read_outputs().unwrap()
            else {
                panic!("channel {k} does not animate scales");
            };
            let on: Vec<bool> = scales.map(|s| s == [1.0; 3]).collect();
            let expected: Vec<bool> = (0..4).map(|key| key == k || (k == 2 && key == 3)).collect();
            assert_eq!(on, expected, "channel {k}");
        }
    }

    #[test]
    fn glb_bytes_are_deterministic_and_a_single_frame_is_still() {
        let a = GlbWriter::new("x", 1.0);
        let scene = scene();
        let mut a = a;
        let mut b = GlbWriter::new("x", 1.0);
        for (t, m) in &scene.frames {
            a.push_frame(m, *t).unwrap();
            b.push_frame(m, *t).unwrap();
        }
        assert_eq!(a.finish().unwrap(), b.finish().unwrap());
        let mut one = GlbWriter::new("one", 1.0);
        one.push_frame(&scene.frames[0].1, 0.0).unwrap();
        let bytes = one.finish().unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        assert_eq!(gltf.animations().count(), 0);
        let root = gltf.default_scene().unwrap().nodes().next().unwrap();
        assert_eq!(root.transform().decomposed().2, [1.0; 3]);
        // An empty frame is a node without a mesh; no data, no BIN chunk.
        let mut empty = GlbWriter::new("empty", 1.0);
        empty.push_frame(&Mesh::new(), 0.0).unwrap();
        let bytes = empty.finish().unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        assert!(gltf.blob.is_none() && gltf.meshes().count() == 0);
    }

    /// A horse-sized frame: a 80 × 80 grid of 6 400 vertices, 12 482
    /// triangles, coloured, moving from frame to frame; 48 frames.
    #[test]
    fn a_horse_sized_animation_stores_topology_and_colours_once() {
        let side = 80u32;
        let mut glb = GlbWriter::new("trot", 0.01);
        for frame in 0..48u32 {
            let mut m = Mesh::new();
            for i in 0..side * side {
                let (x, y) = (f64::from(i % side), f64::from(i / side));
                let z = (x * 0.1 + f64::from(frame) * 0.3).sin();
                m.push_coloured_vertex([x, y, z], [(i % 256) as u8, 90, 40])
                    .unwrap();
            }
            let g = m.group(None, None).unwrap();
            for y in 0..side - 1 {
                for x in 0..side - 1 {
                    let a = y * side + x;
                    m.push_face(g, &[a, a + 1, a + side + 1]).unwrap();
                    m.push_face(g, &[a, a + side + 1, a + side]).unwrap();
                }
            }
            glb.push_frame(&m, frame as f32 / 24.0).unwrap();
        }
        let bin = glb.bin.len();
        let bytes = glb.finish().unwrap();
        let triangles = 2 * 79 * 79;
        // Positions and normals per frame; indices (u16) and colours once;
        // then (written by `finish`) the key times and 48 scale tracks of
        // 49 keys.
        let expected = 48 * 6_400 * 24 + (triangles * 6usize).next_multiple_of(4) + 6_400 * 4;
        assert_eq!(bin, expected);
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let bin_len = u32::from_le_bytes(bytes[20 + json_len..24 + json_len].try_into().unwrap());
        assert_eq!(bin_len as usize, expected + 49 * 4 + 48 * 49 * 12);
        eprintln!(
            "horse-sized 6 400 vertices x 48 frames: {} bytes ({} binary)",
            bytes.len(),
            bin
        );
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        assert_eq!(gltf.nodes().count(), 49);
        assert_eq!(gltf.accessors().count(), 48 * 2 + 2 + 1 + 48);
    }
}
