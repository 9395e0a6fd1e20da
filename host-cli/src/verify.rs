//! Comparing a stream with its fixture and naming the first difference.

use morphogen::stream::{Decoded, Decoder, Record};

use crate::jsonl;

/// Where two streams first differ.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// The frame (the last `frame_start` seen on the expected side), if any.
    pub frame: Option<u32>,
    /// Index of the first differing record (0 is the header).
    pub record: usize,
    /// Byte offset of that record in the expected stream.
    pub offset: usize,
    /// The expected record as JSON, or `end of stream`.
    pub expected: String,
    /// The actual record as JSON, or `end of stream`.
    pub actual: String,
}

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.frame {
            Some(frame) => write!(f, "first difference in frame {frame}, ")?,
            None => write!(f, "first difference before any frame, ")?,
        }
        write!(
            f,
            "record {} (byte {}):\n  expected: {}\n  actual:   {}",
            self.record, self.offset, self.expected, self.actual
        )
    }
}

fn describe(d: Option<&Decoded>) -> String {
    d.map_or_else(|| "end of stream".to_string(), jsonl::line)
}

/// `None` when `actual` equals `expected` byte for byte; otherwise the
/// first record whose frame bytes differ, decoded on both sides.
#[must_use]
pub fn compare(expected: &[u8], actual: &[u8]) -> Option<Difference> {
    if expected == actual {
        return None;
    }
    let frames = |bytes: &'_ [u8]| -> Vec<(Decoded, Vec<u8>)> {
        Decoder::new(bytes)
            .map(|d| {
                let raw = bytes[d.offset..d.offset + d.len].to_vec();
                (d, raw)
            })
            .collect()
    };
    let (e, a) = (frames(expected), frames(actual));
    let mut frame = None;
    for i in 0..e.len().max(a.len()) {
        let (ei, ai) = (e.get(i), a.get(i));
        if ei.map(|x| &x.1) != ai.map(|x| &x.1) {
            return Some(Difference {
                frame,
                record: i,
                offset: ei.map_or(expected.len(), |x| x.0.offset),
                expected: describe(ei.map(|x| &x.0)),
                actual: describe(ai.map(|x| &x.0)),
            });
        }
        if let Some((
            Decoded {
                result: Ok(Record::FrameStart { frame: f, .. }),
                ..
            },
            _,
        )) = ei
        {
            frame = Some(*f);
        }
    }
    // Same frames, different bytes: only possible with trailing garbage.
    Some(Difference {
        frame,
        record: e.len(),
        offset: expected.len(),
        expected: "end of stream".into(),
        actual: "extra bytes".into(),
    })
}
