//! Running a [`Preset`] on a computer: every model in the core's
//! [`Runner`] (the MCU's fixed capacity), except mosaics, whose cells go in
//! a [`VecStore`] sized for the run and relaxed on all cores, bodies, with room for a user's
//! [`USER_CYLINDERS`] cylinders, context-sensitive L-systems, derived in
//! two heap buffers, and bones, with the MCU's mesh capacity and a field
//! cache ([`HOST_FIELD_CACHE`]) the MCU has no RAM for (a context-sensitive
//! skeleton grammar, too, derived in two heap buffers). Both use the core's one run loop
//! ([`morphogen::preset::drive`]), so the stream is the same bytes the
//! firmware writes.

use crate::body_files::USER_CYLINDERS;
use crate::store::VecStore;
use morphogen::body::Body;
use morphogen::bones::{Bones, HOST_FIELD_CACHE, MCU_TRIANGLES, MCU_VERTICES};
use morphogen::lsys::{Buffered, Grammar, LSystem, LsysError, Module, Neighbours};
use morphogen::mosaic::{
    MAX_FACES, MAX_VERTICES, MeshArrays, MeshBuffers, MeshError, MeshParts, MeshStore, Mosaic,
    MosaicError, OnMesh, Params as MosaicParams, SurfaceMosaic, host_capacity,
};
use morphogen::preset::{self, Model, Preset, Runner};
use morphogen::sim::{Progress, Start};
use morphogen::stream::Sink;

/// The heap buffers of a surface's mesh, sized for each mesh, with its
/// inward normals and edge scratch (the fast build and walk), and its
/// anisotropy field.
#[derive(Debug, Default)]
pub struct MeshVecs {
    vertices: Vec<[i32; 3]>,
    faces: Vec<[u32; 3]>,
    neighbours: Vec<[u32; 3]>,
    normals: Vec<[i32; 3]>,
    inward: Vec<[[i32; 3]; 3]>,
    edges: Vec<u64>,
    field: Vec<[i32; 3]>,
}

impl MeshVecs {
    fn arrays(&self) -> MeshArrays<'_> {
        MeshArrays {
            vertices: &self.vertices,
            faces: &self.faces,
            neighbours: &self.neighbours,
            normals: &self.normals,
            inward: &self.inward,
        }
    }
}

impl MeshStore for MeshVecs {
    fn buffers(
        &mut self,
        vertices: usize,
        faces: usize,
    ) -> Result<(MeshBuffers<'_>, &mut [[i32; 3]]), morphogen::Error> {
        // Refused before the buffers (some 120 B a triangle) are allocated.
        if vertices > MAX_VERTICES || faces > MAX_FACES {
            return Err(MosaicError::Mesh(MeshError::TooLarge).into());
        }
        self.vertices.resize(vertices, [0; 3]);
        self.faces.resize(faces, [0; 3]);
        self.neighbours.resize(faces, [0; 3]);
        self.normals.resize(faces, [0; 3]);
        self.inward.resize(faces, [[0; 3]; 3]);
        self.edges.resize(3 * faces, 0);
        self.field.resize(faces, [0; 3]);
        let buffers = MeshBuffers {
            vertices: &mut self.vertices,
            faces: &mut self.faces,
            parts: MeshParts {
                neighbours: &mut self.neighbours,
                normals: &mut self.normals,
                inward: &mut self.inward,
                edges: &mut self.edges,
            },
        };
        Ok((buffers, &mut self.field))
    }

    fn arrays(&self) -> (MeshArrays<'_>, &[[i32; 3]]) {
        (MeshVecs::arrays(self), &self.field)
    }

    fn arrays_mut(&mut self) -> (MeshArrays<'_>, &mut [[i32; 3]]) {
        let arrays = MeshArrays {
            vertices: &self.vertices,
            faces: &self.faces,
            neighbours: &self.neighbours,
            normals: &self.normals,
            inward: &self.inward,
        };
        (arrays, &mut self.field)
    }
}

/// Modules in each of the two buffers of a context-sensitive L-system's
/// derivation on the host (32 MB each); the core's streaming derivation,
/// which the MCU uses, handles context-free grammars only.
pub const HOST_BUFFER_MODULES: usize = 1 << 21;

/// Modules of each buffer of a context-sensitive bone grammar's
/// derivation: 8 × a skeleton string's limit
/// ([`morphogen::bones::MAX_SKELETON_MODULES`]), for strings that shrink.
pub const BONE_BUFFER_MODULES: usize = 8 * morphogen::bones::MAX_SKELETON_MODULES as usize;

/// Runs `preset` with `seed` into `sink`: header, then every step.
///
/// # Errors
/// The model's refusal of its parameters (naming the limit or parameter),
/// then the first error of a step or of the sink.
pub fn run(
    preset: &Preset<'_>,
    seed: u64,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), morphogen::Error> {
    let header = preset::header(preset.name, seed, preset.model.params_digest());
    match preset.model {
        Model::Mosaic(
            params @ &MosaicParams {
                surface: Some(_), ..
            },
        ) => {
            let store = VecStore::<OnMesh>::new(host_capacity(params));
            let mut mosaic = SurfaceMosaic::on_mesh(store, MeshVecs::default());
            mosaic.start(params, seed)?;
            preset::drive(&mut mosaic, &header, sink, progress)
        }
        Model::Mosaic(params) => {
            let mut mosaic = Mosaic::new(VecStore::new(host_capacity(params)));
            mosaic.start(params, seed)?;
            preset::drive(&mut mosaic, &header, sink, progress)
        }
        Model::LSystem(text) => {
            let mut grammar = Box::new(Grammar::new());
            grammar
                .parse(text)
                .map_err(|e| morphogen::Error::Lsys(LsysError::Parse(e)))?;
            if grammar.needs_buffer() {
                let mut a = vec![Module::default(); HOST_BUFFER_MODULES];
                let mut b = vec![Module::default(); HOST_BUFFER_MODULES];
                let mut links = vec![Neighbours::default(); HOST_BUFFER_MODULES];
                let mut sim = Box::new(LSystem::<_>::with_derivation(Buffered::new(
                    &mut a, &mut b, &mut links,
                )));
                sim.start(text, seed)?;
                preset::drive(sim.as_mut(), &header, sink, progress)
            } else {
                let mut runner = Box::new(Runner::new());
                runner.start(&preset.model, seed)?;
                preset::drive(runner.as_mut(), &header, sink, progress)
            }
        }
        Model::Bones(params) => {
            let mut grammar = Box::new(Grammar::new());
            grammar
                .parse(params.grammar)
                .map_err(|e| morphogen::Error::Lsys(LsysError::Parse(e)))?;
            if grammar.needs_buffer() {
                // A context-sensitive skeleton grammar (the paper's, Sec. 3).
                let mut a = vec![Module::default(); BONE_BUFFER_MODULES];
                let mut b = vec![Module::default(); BONE_BUFFER_MODULES];
                let mut links = vec![Neighbours::default(); BONE_BUFFER_MODULES];
                let mut bones = Box::new(Bones::<
                    '_,
                    MCU_VERTICES,
                    MCU_TRIANGLES,
                    HOST_FIELD_CACHE,
                    Buffered<'_>,
                >::with_derivation(Buffered::new(
                    &mut a, &mut b, &mut links,
                )));
                bones.start(params, seed)?;
                preset::drive(bones.as_mut(), &header, sink, progress)
            } else {
                let mut bones =
                    Box::new(Bones::<'_, MCU_VERTICES, MCU_TRIANGLES, HOST_FIELD_CACHE>::new());
                bones.start(params, seed)?;
                preset::drive(bones.as_mut(), &header, sink, progress)
            }
        }
        Model::Body(params) => {
            let mut body = Box::new(Body::<'_, USER_CYLINDERS>::new());
            body.start(params, seed)?;
            preset::drive(body.as_mut(), &header, sink, progress)
        }
        model @ (Model::GrowthCurve(_) | Model::Horn(_)) => {
            let mut runner = Box::new(Runner::new());
            runner.start(&model, seed)?;
            preset::drive(runner.as_mut(), &header, sink, progress)
        }
    }
}
