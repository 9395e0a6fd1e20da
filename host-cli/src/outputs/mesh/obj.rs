//! Wavefront OBJ text of a [`Mesh`] (`v` lines, with vertex colours when
//! asked, `vn`, `g`, `usemtl`, `f`) and its MTL material library, one
//! library shared by the OBJ files of a run's frames ([`Library`]).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen_stream_text::text;

use super::{Material, Mesh};
use crate::atomic::OutputFile;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outputs::mesh::MeshError;
    use crate::outputs::mesh::tests::plant;

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
            let length_squared: f64 = n.iter().map(|c| c * c).sum();
            assert!((length_squared - 1.0).abs() < 1e-4, "{n:?}");
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
}
