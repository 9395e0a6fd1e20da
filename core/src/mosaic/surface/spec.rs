//! What a surface mosaic grows on: the mesh (a built-in shape or a user's
//! triangles) and how its points map to the (u, v) of the mosaic's domain,
//! where the mask and the anisotropy field are read (thesis Sec. 3.2.2).

use serde::Serialize;

use crate::fx::Fx;
use crate::mosaic::shapes::Tessellation;

/// How a point of the surface maps to the (u, v) of the mosaic's domain,
/// where the mask is read (thesis Sec. 3.2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ControlMap {
    /// A cylinder around z: u the angle (a turn is the domain's width), v
    /// the height (the mesh's z range is the domain's length).
    Cylinder,
    /// The plane z = 0: u along x, v along y, over the mesh's range.
    Plane,
}

/// The mesh a surface mosaic lives on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SurfaceMesh<'a> {
    /// A built-in shape ([`Tessellation`]).
    Shape(Tessellation),
    /// A user's triangles.
    Triangles {
        /// Vertices.
        vertices: &'a [[Fx; 3]],
        /// Triangles by vertex index.
        faces: &'a [[u32; 3]],
    },
}

/// A surface for a mosaic: the mesh and how (u, v) is read on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Surface<'a> {
    /// The mesh.
    pub mesh: SurfaceMesh<'a>,
    /// The map to the domain's (u, v).
    pub control: ControlMap,
}

impl Surface<'_> {
    /// The numbers of vertices and faces its mesh has.
    #[must_use]
    pub fn counts(&self) -> (usize, usize) {
        match self.mesh {
            SurfaceMesh::Shape(t) => t.counts(),
            SurfaceMesh::Triangles { vertices, faces } => (vertices.len(), faces.len()),
        }
    }
}
