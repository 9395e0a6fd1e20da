//! The frames of a body stream: each frame's mesh, read from its records
//! (growth paper, Sec. 5), and its solid for OBJ and glTF.

use anyhow::Result;
use morphogen::fx::Real;
use morphogen::stream::Record;

use crate::outputs::mesh;

/// One decoded frame of a body stream.
#[derive(Debug, Default, Clone)]
pub struct Frame {
    /// Frame index.
    pub index: u32,
    /// Age, months.
    pub age: f64,
    /// Vertex positions by id.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles by vertex id.
    pub triangles: Vec<[u32; 3]>,
}

/// Splits a record stream into frames, one record at a time: a frame
/// start begins a frame (dropping one left open), a frame end hands it
/// over.
#[derive(Debug, Default)]
pub struct Framer {
    current: Option<Frame>,
}

impl Framer {
    /// Takes the next record; returns the frame it ends, if any.
    pub fn push(&mut self, r: &Record) -> Option<Frame> {
        match r {
            Record::FrameStart { frame, time } => {
                self.current = Some(Frame {
                    index: *frame,
                    age: f64::from_fx(*time),
                    ..Frame::default()
                });
            }
            Record::MeshVertex { id, p } => {
                if let Some(f) = self.current.as_mut() {
                    let i = *id as usize;
                    if f.vertices.len() <= i {
                        f.vertices.resize(i + 1, [0.0; 3]);
                    }
                    f.vertices[i] = p.map(f64::from_fx);
                }
            }
            Record::Triangle { v } => {
                if let Some(f) = self.current.as_mut() {
                    f.triangles.push(*v);
                }
            }
            Record::FrameEnd { .. } => return self.current.take(),
            _ => {}
        }
        None
    }
}

/// Splits a record stream into frames.
#[must_use]
pub fn frames(records: &[Record]) -> Vec<Frame> {
    let mut framer = Framer::default();
    records.iter().filter_map(|r| framer.push(r)).collect()
}

/// The mesh of a frame for OBJ and glTF: one group of its triangles,
/// named `object`, headed by the comment `header`, every vertex `rgb`,
/// in the material `object` of that colour.
///
/// # Errors
/// When a triangle names a vertex the frame lacks.
pub fn solid(frame: &Frame, header: &str, object: &str, rgb: [u8; 3]) -> Result<mesh::Mesh> {
    let mut m = mesh::Mesh::from_triangles(frame.vertices.clone(), &frame.triangles)?;
    m.comment(header);
    m.set_object(object)?;
    m.set_colours(vec![rgb; frame.vertices.len()])?;
    let material = m.material(object, rgb)?;
    m.paint(material)?;
    Ok(m)
}
