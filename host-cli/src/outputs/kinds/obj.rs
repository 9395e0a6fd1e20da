//! `obj`: Wavefront meshes (`*.obj`) with their material library
//! (`.mtl`): a file per frame sharing one library, a mesh of the run, or
//! one streamed a piece at a time.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::{Format, Kind, MeshFiles, MeshSeries, MeshStream, Product, StreamedMesh};
use crate::atomic::OutputFile;
use crate::outputs::mesh::{Library, Mesh, ObjStyle, obj_part, write_frame_obj, write_obj};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "obj",
    about: "meshes and their .mtl",
    by_default: true,
    format: &Obj,
};

struct Obj;

impl Format for Obj {
    fn takes(&self, product: Product) -> bool {
        matches!(
            product,
            Product::FrameMesh | Product::FrameMeshes | Product::Mesh
        )
    }

    fn mesh(&self, mesh: &Mesh, dir: &Path, stem: &str, style: ObjStyle) -> Result<Vec<PathBuf>> {
        write_obj(&dir.join(format!("{stem}.obj")), mesh, style)
    }

    fn mesh_stream(
        &self,
        dir: &Path,
        stream: &StreamedMesh<'_>,
    ) -> Result<Option<Box<dyn MeshStream>>> {
        let name = format!("{}.mtl", stream.stem);
        let mut library = Library::new(dir, &name);
        library.write_once(stream.materials)?;
        let path = dir.join(format!("{}.obj", stream.stem));
        let mut out = OutputFile::create(&path)?;
        writeln!(out, "# {}\nmtllib {name}", stream.comment)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(Some(Box::new(Streamed {
            path,
            out,
            library,
            style: stream.style,
            before: 0,
        })))
    }

    fn frame_mesh(
        &self,
        mesh: &Mesh,
        dir: &Path,
        name: &str,
        files: &MeshFiles,
    ) -> Result<Option<PathBuf>> {
        let path = dir.join(format!("{name}.obj"));
        write_frame_obj(&path, mesh, ObjStyle::PLAIN, files.library)?;
        Ok(Some(path))
    }

    fn frame_meshes(&self, dir: &Path, files: &MeshFiles) -> Option<Box<dyn MeshSeries>> {
        Some(Box::new(Library::new(dir, files.library)))
    }
}

/// The frames' files share the library written from the first frame.
impl MeshSeries for Library {
    fn push(&mut self, mesh: &Mesh, _position: usize) -> Result<()> {
        self.write_once(mesh)
    }

    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>> {
        Ok(self.written().into_iter().collect())
    }
}

/// An OBJ written a piece at a time.
struct Streamed {
    path: PathBuf,
    out: OutputFile,
    library: Library,
    style: ObjStyle,
    /// The vertices written so far.
    before: u64,
}

impl MeshStream for Streamed {
    fn piece(&mut self, piece: &Mesh) -> Result<()> {
        obj_part(piece, self.style, self.before, &mut self.out)
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        self.before += piece.positions().len() as u64;
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>> {
        self.out.finish()?;
        Ok([self.path]
            .into_iter()
            .chain(self.library.written())
            .collect())
    }
}
