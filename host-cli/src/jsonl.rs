//! Records as JSON Lines: one object per record, with a `kind` field and
//! fixed-point values as decimals (field names in docs/stream-format.md).

use morphogen::fx::Fx;
use morphogen::stream::{Decoded, FrameError, Record};
use serde_json::{Value, json};

/// An `Fx` as its exact decimal value.
#[must_use]
pub fn fx(v: Fx) -> Value {
    json!(f64::from(v.to_bits()) / 65_536.0)
}

fn fx_array<const N: usize>(v: &[Fx; N]) -> Value {
    Value::Array(v.iter().map(|&x| fx(x)).collect())
}

/// One record as a JSON object.
#[must_use]
pub fn record(r: &Record) -> Value {
    let kind = r.kind();
    match r {
        Record::Header(h) => json!({
            "kind": kind, "version": h.version, "preset": h.preset.as_str(),
            "seed": h.seed, "params": format!("{:016x}", h.params),
        }),
        Record::FrameStart { frame, time } => {
            json!({"kind": kind, "frame": frame, "time": fx(*time)})
        }
        Record::FrameEnd { frame } => json!({"kind": kind, "frame": frame}),
        Record::Point { p } => json!({"kind": kind, "p": fx_array(p)}),
        Record::Segment {
            a,
            b,
            width,
            colour,
        } => json!({
            "kind": kind, "a": fx_array(a), "b": fx_array(b), "width": fx(*width), "colour": colour,
        }),
        Record::Polygon { vertices, colour } => {
            json!({"kind": kind, "vertices": vertices, "colour": colour})
        }
        Record::MeshVertex { id, p } => json!({"kind": kind, "id": id, "p": fx_array(p)}),
        Record::Triangle { v } => json!({"kind": kind, "v": v}),
        Record::Cell {
            id,
            kind: cell_type,
            p,
        } => json!({"kind": kind, "id": id, "type": cell_type, "p": fx_array(p)}),
        Record::Sample { series, x, y } => {
            json!({"kind": kind, "series": series, "x": fx(*x), "y": fx(*y)})
        }
        Record::Ring {
            module,
            ring,
            points,
        } => json!({"kind": kind, "module": module, "ring": ring, "points": points}),
        other => json!({"kind": other.kind()}),
    }
}

/// A decoded frame as one JSON line: the record, or an `error` object
/// naming the byte offset and what is wrong.
#[must_use]
pub fn line(d: &Decoded) -> String {
    let value = match &d.result {
        Ok(r) => record(r),
        Err(FrameError::UnknownKind { tag }) => {
            json!({"kind": "unknown", "offset": d.offset, "tag": tag})
        }
        Err(e) => json!({"kind": "error", "offset": d.offset, "error": e.to_string()}),
    };
    value.to_string()
}

/// The JSONL text of a whole stream (each line ends with `\n`).
#[must_use]
pub fn stream(bytes: &[u8]) -> String {
    morphogen::stream::Decoder::new(bytes)
        .map(|d| line(&d) + "\n")
        .collect()
}
