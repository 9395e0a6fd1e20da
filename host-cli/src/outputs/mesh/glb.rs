//! Binary glTF 2.0 of [`Mesh`]es: `POSITION`, `NORMAL`, `COLOR_0` and
//! indices, one mesh per frame.
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

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result};
use gltf_json as json;
use json::validation::{Checked, Checked::Valid, USize64};

use super::{Mesh, MeshError};
use crate::atomic::write_atomic;

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

    /// An accessor of `points` as `VEC3` of `f32` for a vertex attribute,
    /// with their least and greatest coordinates when `bounded` (glTF
    /// requires them of `POSITION`).
    fn vec3(
        &mut self,
        points: &[[f32; 3]],
        bounded: bool,
    ) -> Result<json::Index<json::Accessor>, MeshError> {
        use json::accessor::{ComponentType as C, Type as T};
        let bounds = bounded.then(|| {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for p in points {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            (lo.to_vec(), hi.to_vec())
        });
        let bytes: Vec<u8> = points
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        let count = points.len();
        self.accessor(
            &bytes,
            Some(ARRAY_BUFFER),
            count,
            C::F32,
            T::Vec3,
            false,
            bounds,
        )
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
        let frame = self.frames.len();
        if !seconds.is_finite() || self.frames.last().is_some_and(|&(t, _)| seconds <= t) {
            return Err(MeshError::TimeNotIncreasing { frame });
        }
        let name = format!("frame_{frame}");
        let mut json_mesh = None;
        let vertices = mesh.positions.len();
        if vertices > 0 && mesh.triangle_count() > 0 {
            let mut attributes = BTreeMap::new();
            // POSITION, with the bounds glTF requires (of the f32 values).
            let points: Vec<[f32; 3]> =
                mesh.positions.iter().map(|p| p.map(|c| c as f32)).collect();
            let a = self.vec3(&points, true)?;
            attributes.insert(Valid(json::mesh::Semantic::Positions), a);
            let a = self.vec3(&mesh.vertex_normals(), false)?;
            attributes.insert(Valid(json::mesh::Semantic::Normals), a);
            if let Some(colours) = mesh.resolved_colours() {
                let a = self.colours(&colours, vertices)?;
                attributes.insert(Valid(json::mesh::Semantic::Colors(0)), a);
            }
            let primitives = self.primitives(mesh, &attributes)?;
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

    /// The accessor of the vertex colours `colours` (linear RGBA bytes),
    /// the previous frame's when they are the same.
    fn colours(
        &mut self,
        colours: &[[u8; 3]],
        vertices: usize,
    ) -> Result<json::Index<json::Accessor>, MeshError> {
        use json::accessor::{ComponentType as C, Type as T};
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
        if let Some((b, a)) = &self.shared.colours
            && *b == bytes
        {
            return Ok(*a);
        }
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
        Ok(a)
    }

    /// One primitive per group of `mesh` with triangles, each with the
    /// vertex `attributes` and its material; an index accessor the
    /// previous frame has with the same bytes is used again.
    fn primitives(
        &mut self,
        mesh: &Mesh,
        attributes: &BTreeMap<Checked<json::mesh::Semantic>, json::Index<json::Accessor>>,
    ) -> Result<Vec<json::mesh::Primitive>, MeshError> {
        use json::accessor::{ComponentType as C, Type as T};
        let vertices = mesh.positions.len();
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
        Ok(primitives)
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
    use crate::outputs::mesh::Rgb;

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

    /// `scene()` as GLB: its bytes, and them parsed (which validates the
    /// JSON against the glTF rules the crate knows).
    fn cubes() -> (Vec<u8>, gltf::Gltf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cubes.glb");
        write_glb(&path, &scene()).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        (bytes, gltf)
    }

    /// The frame nodes under the scene's root.
    fn frame_nodes(gltf: &gltf::Gltf) -> Vec<gltf::Node<'_>> {
        let scene = gltf.default_scene().unwrap();
        let root = scene.nodes().next().unwrap();
        assert_eq!(root.name(), Some("cubes"));
        assert_eq!(root.transform().decomposed().2, [0.01; 3]);
        root.children().collect()
    }

    #[test]
    fn glb_container_is_aligned_and_every_accessor_fills_its_view() {
        let (bytes, gltf) = cubes();
        // The container: header, a JSON chunk padded with spaces, BIN.
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!((word(4), word(8)), (2, bytes.len()));
        let json_len = word(12);
        assert_eq!((json_len % 4, &bytes[16..20]), (0, &b"JSON"[..]));
        let bin_at = 20 + json_len;
        assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
        assert_eq!(bin_at + 8 + word(bin_at), bytes.len());
        let blob = gltf.blob.clone().unwrap();
        // Every view inside the buffer, 4-aligned; every accessor fills its view.
        for a in gltf.accessors() {
            let v = a.view().unwrap();
            assert_eq!(v.offset() % 4, 0);
            assert!(v.offset() + v.length() <= blob.len());
            assert_eq!(a.offset(), 0);
            assert_eq!(a.count() * a.size(), v.length());
        }
    }

    #[test]
    fn glb_frames_read_back_with_counts_bounds_colours_and_shared_blocks() {
        let (_, gltf) = cubes();
        let blob = gltf.blob.clone().unwrap();
        let buffers = |b: gltf::Buffer<'_>| match b.source() {
            gltf::buffer::Source::Bin => Some(&blob[..]),
            gltf::buffer::Source::Uri(_) => None,
        };
        let frames = frame_nodes(&gltf);
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
    }

    #[test]
    fn glb_animation_shows_one_frame_at_a_time() {
        let (_, gltf) = cubes();
        let blob = gltf.blob.clone().unwrap();
        let buffers = |b: gltf::Buffer<'_>| match b.source() {
            gltf::buffer::Source::Bin => Some(&blob[..]),
            gltf::buffer::Source::Uri(_) => None,
        };
        let frames = frame_nodes(&gltf);
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
