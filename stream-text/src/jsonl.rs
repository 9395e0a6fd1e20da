//! Records as JSON Lines: one object per record, with a `kind` field and
//! fixed-point values as exact decimals (field names in
//! docs/stream-format.md). Lines are written straight into a byte buffer
//! (no JSON tree per record); strings go through `serde_json` for their
//! escaping.

use std::fmt;
use std::io::{self, Write};

use morphogen::fx::Fx;
use morphogen::stream::{Decoded, Decoder, FrameError, Record, Sink, SinkError};

use crate::text::{self, Whole};

/// A JSON object being written field by field into a line buffer.
struct Object<'a> {
    out: &'a mut Vec<u8>,
}

impl<'a> Object<'a> {
    /// Opens the object with its `kind`.
    fn new(out: &'a mut Vec<u8>, kind: &str) -> Object<'a> {
        out.extend_from_slice(b"{\"kind\":");
        name(out, kind);
        Object { out }
    }

    fn key(&mut self, name: &str) -> &mut Vec<u8> {
        self.out.extend_from_slice(b",\"");
        self.out.extend_from_slice(name.as_bytes());
        self.out.extend_from_slice(b"\":");
        self.out
    }

    fn int(&mut self, name: &str, n: impl itoa::Integer) -> &mut Self {
        text::int(self.key(name), n);
        self
    }

    fn fx(&mut self, name: &str, v: Fx) -> &mut Self {
        text::fx(self.key(name), v, Whole::PointZero);
        self
    }

    fn fxs(&mut self, name: &str, v: &[Fx]) -> &mut Self {
        let out = self.key(name);
        out.push(b'[');
        for (i, &x) in v.iter().enumerate() {
            if i > 0 {
                out.push(b',');
            }
            text::fx(out, x, Whole::PointZero);
        }
        out.push(b']');
        self
    }

    fn ints<I: itoa::Integer + Copy>(&mut self, name: &str, v: &[I]) -> &mut Self {
        let out = self.key(name);
        out.push(b'[');
        for (i, &x) in v.iter().enumerate() {
            if i > 0 {
                out.push(b',');
            }
            text::int(out, x);
        }
        out.push(b']');
        self
    }

    fn bool(&mut self, name: &str, b: bool) -> &mut Self {
        let text: &[u8] = if b { b"true" } else { b"false" };
        self.key(name).extend_from_slice(text);
        self
    }

    fn string(&mut self, name: &str, s: &str) -> &mut Self {
        string(self.key(name), s);
        self
    }

    fn close(&mut self) {
        self.out.push(b'}');
    }
}

/// Appends `s` as a JSON string: a name of letters, digits and `_` (every
/// record kind) as it is, anything else through [`string`].
fn name(out: &mut Vec<u8>, s: &str) {
    if s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
        out.push(b'"');
        out.extend_from_slice(s.as_bytes());
        out.push(b'"');
    } else {
        string(out, s);
    }
}

/// Appends `s` as a JSON string.
fn string(out: &mut Vec<u8>, s: &str) {
    // Writing into a Vec cannot fail, and a &str always serialises.
    let _ = serde_json::to_writer(out, s);
}

/// Appends one record as a JSON object (no newline).
pub fn record(out: &mut Vec<u8>, r: &Record) {
    let mut o = Object::new(out, r.kind());
    match r {
        Record::Header(h) => o
            .int("version", h.version)
            .string("preset", h.preset.as_str())
            .int("seed", h.seed)
            .string("params", &format!("{:016x}", h.params)),
        Record::FrameStart { frame, time } => o.int("frame", *frame).fx("time", *time),
        Record::FrameEnd { frame } => o.int("frame", *frame),
        Record::Point { p } => o.fxs("p", p),
        Record::Segment {
            a,
            b,
            width,
            colour,
        } => o
            .fxs("a", a)
            .fxs("b", b)
            .fx("width", *width)
            .int("colour", *colour),
        Record::Polygon { vertices, colour } => o.int("vertices", *vertices).int("colour", *colour),
        Record::MeshVertex { id, p } => o.int("id", *id).fxs("p", p),
        Record::Triangle { v } => o.ints("v", v),
        Record::Cell {
            id,
            kind: cell_type,
            p,
        } => o.int("id", *id).int("type", *cell_type).fxs("p", p),
        Record::SurfaceCell {
            id,
            kind: cell_type,
            p,
        } => o.int("id", *id).int("type", *cell_type).fxs("p", p),
        Record::Sample { series, x, y } => o.int("series", *series).fx("x", *x).fx("y", *y),
        Record::Ring {
            module,
            ring,
            points,
        } => o
            .int("module", *module)
            .int("ring", *ring)
            .int("points", *points),
        Record::Extent {
            min,
            max,
            chart,
            frames,
        } => o
            .ints("min", min)
            .ints("max", max)
            .bool("chart", *chart)
            .int("frames", *frames),
        _ => &mut o,
    }
    .close();
}

/// Appends a decoded frame as one JSON object (no newline): the record, or
/// an `error` object naming the byte offset and what is wrong.
pub fn decoded(out: &mut Vec<u8>, d: &Decoded) {
    match &d.result {
        Ok(r) => record(out, r),
        Err(FrameError::UnknownKind { tag }) => Object::new(out, "unknown")
            .int("offset", d.offset)
            .int("tag", *tag)
            .close(),
        Err(e) => Object::new(out, "error")
            .int("offset", d.offset)
            .string("error", &e.to_string())
            .close(),
    }
}

/// A decoded frame as one JSON line (without its newline).
#[must_use]
pub fn line(d: &Decoded) -> String {
    let mut out = Vec::new();
    decoded(&mut out, d);
    // Only ASCII and serde_json's UTF-8 strings were written.
    String::from_utf8_lossy(&out).into_owned()
}

/// Writes the JSONL of a whole stream to `w`, a line per frame as it is
/// decoded (each line ends with `\n`).
///
/// # Errors
/// When `w` fails.
pub fn write_stream(bytes: &[u8], w: &mut impl Write) -> io::Result<()> {
    let mut out = Vec::with_capacity(256);
    for d in Decoder::new(bytes) {
        out.clear();
        decoded(&mut out, &d);
        out.push(b'\n');
        w.write_all(&out)?;
    }
    Ok(())
}

/// A [`Sink`] that hands each record on to the next sink and then writes
/// it as a JSON line: a run's `records.jsonl` as the run goes, the same
/// bytes as [`write_stream`] of its stream (a run's own frames always
/// decode), without reading the stream back.
pub struct Lines<'a, W: Write> {
    next: &'a mut (dyn Sink + Send),
    out: W,
    line: Vec<u8>,
    failure: Option<io::Error>,
}

impl<W: Write> fmt::Debug for Lines<'_, W> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Lines")
            .field("failure", &self.failure)
            .finish_non_exhaustive()
    }
}

impl<'a, W: Write> Lines<'a, W> {
    /// Lines to `out` of the records passed on to `next`.
    pub fn new(next: &'a mut (dyn Sink + Send), out: W) -> Self {
        Lines {
            next,
            out,
            line: Vec::with_capacity(256),
            failure: None,
        }
    }

    /// The writer, once every line went in.
    ///
    /// # Errors
    /// The write that failed (the run was stopped there).
    pub fn into_inner(self) -> io::Result<W> {
        self.failure.map_or(Ok(self.out), Err)
    }
}

impl<W: Write> Sink for Lines<'_, W> {
    fn record(&mut self, r: &Record) -> Result<(), SinkError> {
        self.next.record(r)?;
        self.line.clear();
        record(&mut self.line, r);
        self.line.push(b'\n');
        self.out.write_all(&self.line).map_err(|e| {
            self.failure = Some(e);
            SinkError::Write
        })
    }
}

/// The JSONL text of a whole stream (each line ends with `\n`).
#[must_use]
pub fn stream(bytes: &[u8]) -> String {
    let mut out = Vec::new();
    // Writing into a Vec cannot fail.
    let _ = write_stream(bytes, &mut out);
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use morphogen::stream::{Encoder, Header, Sink};

    use super::*;

    #[test]
    fn every_kind_reads_as_the_json_it_was() {
        let fx = Fx::from_bits;
        let records = [
            Record::Header(Header {
                version: 1,
                preset: "a \"quoted\" name".try_into().unwrap(),
                seed: u64::MAX,
                params: 0x65a_4353,
            }),
            Record::FrameStart {
                frame: 3,
                time: fx(65_536),
            },
            Record::Point {
                p: [fx(1), fx(-98_304), fx(0)],
            },
            Record::Segment {
                a: [fx(i32::MIN), fx(i32::MAX), fx(7)],
                b: [fx(0); 3],
                width: fx(100),
                colour: 9,
            },
            Record::Polygon {
                vertices: 4,
                colour: 2,
            },
            Record::MeshVertex {
                id: 12,
                p: [fx(65_537), fx(2), fx(3)],
            },
            Record::Triangle { v: [1, 2, 3] },
            Record::Cell {
                id: 5,
                kind: 1,
                p: [fx(3), fx(4)],
            },
            Record::SurfaceCell {
                id: 6,
                kind: 2,
                p: [fx(3 << 16), fx(4 << 16), fx(-5 << 16)],
            },
            Record::Sample {
                series: 1,
                x: fx(0),
                y: fx(3),
            },
            Record::Ring {
                module: 1,
                ring: 2,
                points: 3,
            },
            Record::FrameEnd { frame: 3 },
        ];
        let mut encoder = Encoder::new(Vec::new());
        for r in &records {
            encoder.record(r).unwrap();
        }
        let text = stream(&encoder.into_writer());
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), records.len());
        assert_eq!(
            lines[0],
            serde_json::json!({"kind": "header", "version": 1, "preset": "a \"quoted\" name",
                "seed": u64::MAX, "params": "00000000065a4353"})
        );
        assert_eq!(
            text.lines().nth(3).unwrap(),
            r#"{"kind":"segment","a":[-32768.0,32767.9999847412109375,0.0001068115234375],"b":[0.0,0.0,0.0],"width":0.00152587890625,"colour":9}"#
        );
        assert_eq!(lines[2]["p"][1], -1.5);
        assert_eq!(lines[6]["v"], serde_json::json!([1, 2, 3]));
        assert_eq!(lines[7]["type"], 1);
        assert_eq!(lines[8]["kind"], "surface_cell");
        assert_eq!(lines[8]["p"], serde_json::json!([3.0, 4.0, -5.0]));
        assert_eq!(lines[10]["points"], 3);
        // Written as they come, the same lines.
        let mut encoder = Encoder::new(Vec::new());
        let mut as_they_come = Lines::new(&mut encoder, Vec::new());
        for r in &records {
            as_they_come.record(r).unwrap();
        }
        let written = as_they_come.into_inner().unwrap();
        assert_eq!(String::from_utf8(written).unwrap(), text);
    }
}
