//! The record vocabulary shared by every model and consumer.

use serde::{Deserialize, Serialize};

use crate::fx::Fx;

/// The wire format version in every [`Header`]; bump it on any change to
/// the encoding of an existing record.
pub const FORMAT_VERSION: u16 = 1;

/// A preset's name as carried in the header (at most 32 bytes of UTF-8).
pub type PresetName = heapless::String<32>;

/// The first record of every stream: it identifies the capture.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Header {
    /// [`FORMAT_VERSION`] of the encoder.
    pub version: u16,
    /// The preset that produced the stream.
    pub preset: PresetName,
    /// The run's seed.
    pub seed: u64,
    /// CRC-64 of the preset's postcard-encoded parameters.
    pub params: u64,
}

/// One unit of simulation output. Variants are appended, never reordered
/// (their index is the wire tag).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Record {
    /// Starts the stream (tag 0).
    Header(Header),
    /// Starts frame `frame` at model time `time` (tag 1); the unit of time
    /// is the model's (days for growth curves and mosaics, years for horns).
    FrameStart {
        /// Frame index, from 0.
        frame: u32,
        /// Model time.
        time: Fx,
    },
    /// Ends frame `frame` (tag 2).
    FrameEnd {
        /// Frame index.
        frame: u32,
    },
    /// A point in model space (tag 3); also the vertices of a polygon or
    /// ring run.
    Point {
        /// x, y, z.
        p: [Fx; 3],
    },
    /// A drawn segment (tag 4).
    Segment {
        /// Start point.
        a: [Fx; 3],
        /// End point.
        b: [Fx; 3],
        /// Line width.
        width: Fx,
        /// Colour-map index.
        colour: u16,
    },
    /// A filled polygon whose `vertices` [`Record::Point`]s follow (tag 5).
    Polygon {
        /// Number of vertex records that follow.
        vertices: u16,
        /// Colour-map index.
        colour: u16,
    },
    /// A mesh vertex (tag 6); ids count from 0 within a frame.
    MeshVertex {
        /// Vertex id.
        id: u32,
        /// Position.
        p: [Fx; 3],
    },
    /// A mesh triangle by vertex ids, counter-clockwise seen from outside
    /// (tag 7).
    Triangle {
        /// Vertex ids.
        v: [u32; 3],
    },
    /// A cell of a 2D mosaic (tag 8).
    Cell {
        /// Cell id, stable over the run.
        id: u32,
        /// Cell type index.
        kind: u8,
        /// Position in the domain (u, v).
        p: [Fx; 2],
    },
    /// A sample `(x, y)` of curve `series` (tag 9).
    Sample {
        /// Which curve.
        series: u16,
        /// Abscissa.
        x: Fx,
        /// Ordinate.
        y: Fx,
    },
    /// A closed ring of a swept surface whose `points` [`Record::Point`]s
    /// follow (tag 10).
    Ring {
        /// Module (or part) id.
        module: u16,
        /// Ring index within the module.
        ring: u16,
        /// Number of point records that follow.
        points: u16,
    },
    /// A cell of a mosaic on a surface (tag 11).
    SurfaceCell {
        /// Cell id, stable over the run.
        id: u32,
        /// Cell type index.
        kind: u8,
        /// Position on the mesh (x, y, z).
        p: [Fx; 3],
    },
    /// The extent of what the stream draws and its number of frames
    /// (tag 12): a *link* record, sent right after the header by a sender
    /// that measured its run first (the firmware does, to fit its OLED), so
    /// that a receiver can fit its own view before frame 0. It is not part
    /// of the stream: not in `stream.bin`, fixtures or digests
    /// (docs/stream-format.md, "The extent").
    Extent {
        /// Lowest projected `(u, v)` (`rig::project`), in I16F16 bits;
        /// above `max` when nothing is drawn.
        min: [i64; 2],
        /// Highest projected `(u, v)`, in I16F16 bits.
        max: [i64; 2],
        /// Whether only samples are drawn (a chart, stretched to fill).
        chart: bool,
        /// Frames in the stream.
        frames: u32,
    },
}

impl Record {
    /// The record's kind as a lower-case name (the `kind` field of JSONL).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Record::Header(_) => "header",
            Record::FrameStart { .. } => "frame_start",
            Record::FrameEnd { .. } => "frame_end",
            Record::Point { .. } => "point",
            Record::Segment { .. } => "segment",
            Record::Polygon { .. } => "polygon",
            Record::MeshVertex { .. } => "mesh_vertex",
            Record::Triangle { .. } => "triangle",
            Record::Cell { .. } => "cell",
            Record::Sample { .. } => "sample",
            Record::Ring { .. } => "ring",
            Record::SurfaceCell { .. } => "surface_cell",
            Record::Extent { .. } => "extent",
        }
    }
}
