//! Where a surface mosaic keeps its mesh: a [`MeshStore`] gives the
//! buffers a mesh is built in at each start and the arrays it is viewed
//! from at each step. The host sizes its buffers for each mesh; the MCU
//! holds fixed arrays ([`ArrayMeshStore`]: vertices 12 B, and per face its
//! corners, neighbours and normal, 36 B, without the inward normals and
//! the edge scratch, which [`MeshParts`] may leave out).

use super::MeshBuffers;
use crate::Error;
use crate::mosaic::mesh::{MeshArrays, MeshParts};

/// The name of the limit in [`Error::Capacity`] when a mesh has more
/// vertices than an [`ArrayMeshStore`] holds.
pub const MESH_VERTEX_LIMIT: &str = "surface mesh vertices";
/// The name of the limit in [`Error::Capacity`] when a mesh has more
/// faces than an [`ArrayMeshStore`] holds.
pub const MESH_FACE_LIMIT: &str = "surface mesh faces";

/// Storage for the mesh of a surface mosaic and the anisotropy field on
/// it.
pub trait MeshStore {
    /// The buffers for a mesh of `vertices` and `faces`, and for its
    /// anisotropy field (one entry per face; empty in a store that keeps
    /// none).
    ///
    /// # Errors
    /// [`Error::Capacity`] naming the limit the mesh exceeds.
    fn buffers(
        &mut self,
        vertices: usize,
        faces: usize,
    ) -> Result<(MeshBuffers<'_>, &mut [[i32; 3]]), Error>;

    /// The arrays as the last build filled them, and the field.
    fn arrays(&self) -> (MeshArrays<'_>, &[[i32; 3]]);

    /// The arrays, and the field to fill.
    fn arrays_mut(&mut self) -> (MeshArrays<'_>, &mut [[i32; 3]]);
}

/// A mesh store held inline: up to `V` vertices and `F` faces, no
/// anisotropy field (runs with anisotropy are refused, naming
/// [`FIELD_LIMIT`](super::FIELD_LIMIT)).
pub struct ArrayMeshStore<const V: usize, const F: usize> {
    vertices: [[i32; 3]; V],
    faces: [[u32; 3]; F],
    neighbours: [[u32; 3]; F],
    normals: [[i32; 3]; F],
}

impl<const V: usize, const F: usize> ArrayMeshStore<V, F> {
    /// The most vertices it holds.
    pub const VERTICES: usize = V;
    /// The most faces it holds.
    pub const FACES: usize = F;

    /// An empty store (`const`, all zero bytes, so that it is written in
    /// place).
    pub const EMPTY: Self = ArrayMeshStore {
        vertices: [[0; 3]; V],
        faces: [[0; 3]; F],
        neighbours: [[0; 3]; F],
        normals: [[0; 3]; F],
    };
}

impl<const V: usize, const F: usize> core::fmt::Debug for ArrayMeshStore<V, F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "ArrayMeshStore<{V}, {F}>")
    }
}

impl<const V: usize, const F: usize> MeshStore for ArrayMeshStore<V, F> {
    fn buffers(
        &mut self,
        vertices: usize,
        faces: usize,
    ) -> Result<(MeshBuffers<'_>, &mut [[i32; 3]]), Error> {
        if vertices > V {
            return Err(Error::Capacity {
                limit: MESH_VERTEX_LIMIT,
                capacity: V as u32,
            });
        }
        if faces > F {
            return Err(Error::Capacity {
                limit: MESH_FACE_LIMIT,
                capacity: F as u32,
            });
        }
        let buffers = MeshBuffers {
            vertices: &mut self.vertices,
            faces: &mut self.faces,
            parts: MeshParts {
                neighbours: &mut self.neighbours,
                normals: &mut self.normals,
                inward: &mut [],
                edges: &mut [],
            },
        };
        Ok((buffers, &mut []))
    }

    fn arrays(&self) -> (MeshArrays<'_>, &[[i32; 3]]) {
        (self.view(), &[])
    }

    fn arrays_mut(&mut self) -> (MeshArrays<'_>, &mut [[i32; 3]]) {
        (self.view(), &mut [])
    }
}

impl<const V: usize, const F: usize> ArrayMeshStore<V, F> {
    fn view(&self) -> MeshArrays<'_> {
        MeshArrays {
            vertices: &self.vertices,
            faces: &self.faces,
            neighbours: &self.neighbours,
            normals: &self.normals,
            inward: &[],
        }
    }
}
