//! `glb`: the frames' meshes as one binary glTF scene (`model.glb`), a
//! frame every animation step, or a mesh streamed into it while it stays
//! small.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::{Format, Kind, MeshFiles, MeshSeries, MeshStream, Product, StreamedMesh};
use crate::outputs::mesh::{GlbWriter, GroupId, Mesh};
use crate::outputs::slots::ANIMATION_DELAY_MS;

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "glb",
    about: "model.glb",
    by_default: true,
    format: &Glb,
};

/// The scene's file name.
const FILE: &str = "model.glb";

struct Glb;

impl Format for Glb {
    fn takes(&self, product: Product) -> bool {
        product == Product::FrameMeshes
    }

    fn mesh_stream(
        &self,
        dir: &Path,
        stream: &StreamedMesh<'_>,
    ) -> Result<Option<Box<dyn MeshStream>>> {
        let mut mesh = Mesh::new();
        let group = mesh.group(None, None)?;
        Ok(Some(Box::new(Streamed {
            path: dir.join(FILE),
            name: stream.stem.to_owned(),
            what: stream.what.to_owned(),
            max_vertices: stream.max_vertices,
            held: Some((mesh, group)),
        })))
    }

    fn frame_meshes(&self, dir: &Path, files: &MeshFiles) -> Option<Box<dyn MeshSeries>> {
        Some(Box::new(Series {
            path: dir.join(FILE),
            scene: GlbWriter::new(&files.scene, files.metres),
        }))
    }
}

/// The frames' scene, a frame every animation step.
struct Series {
    path: PathBuf,
    scene: GlbWriter,
}

impl MeshSeries for Series {
    fn push(&mut self, mesh: &Mesh, position: usize) -> Result<()> {
        let seconds = position as f32 * f32::from(ANIMATION_DELAY_MS) / 1000.0;
        Ok(self.scene.push_frame(mesh, seconds)?)
    }

    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>> {
        self.scene.write(&self.path)?;
        Ok(vec![self.path])
    }
}

/// A streamed mesh held whole, as long as it has at most `max_vertices`.
struct Streamed {
    path: PathBuf,
    name: String,
    what: String,
    max_vertices: usize,
    /// The mesh so far and its one group; `None` once too large.
    held: Option<(Mesh, GroupId)>,
}

impl MeshStream for Streamed {
    fn piece(&mut self, piece: &Mesh) -> Result<()> {
        if let Some((mesh, group)) = &mut self.held {
            mesh.append(*group, piece)?;
            if mesh.positions().len() > self.max_vertices {
                self.held = None;
            }
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>> {
        let Some((mesh, _)) = self.held else {
            eprintln!(
                "note: no {FILE}: {} has more than {} vertices",
                self.what, self.max_vertices
            );
            return Ok(Vec::new());
        };
        let mut scene = GlbWriter::new(&self.name, 1.0);
        scene.push_frame(&mesh, 0.0)?;
        scene.write(&self.path)?;
        Ok(vec![self.path])
    }
}
