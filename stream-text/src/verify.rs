//! Comparing a stream with its fixture: the first difference, and how
//! many records differ, of which kinds, in which frames.

use std::collections::BTreeMap;

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

/// Every difference between two streams, record by record (the n-th
/// against the n-th).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Tally {
    /// Records that differ, one side's extra records included.
    pub records: usize,
    /// How many of them are of each kind (the expected record's, or the
    /// actual one's past the end of the expected stream).
    pub kinds: BTreeMap<&'static str, usize>,
    /// The frames they are in, in order (the expected stream's numbering;
    /// none for records before the first frame).
    pub frames: Vec<u32>,
}

impl Tally {
    /// The frames as runs, `3, 7-9` (at most `runs` of them, then `...`).
    #[must_use]
    pub fn frame_runs(&self, runs: usize) -> String {
        let mut out: Vec<String> = Vec::new();
        let mut i = 0;
        while i < self.frames.len() {
            let start = self.frames[i];
            let mut end = start;
            while self.frames.get(i + 1) == Some(&(end + 1)) {
                end += 1;
                i += 1;
            }
            i += 1;
            if out.len() == runs {
                out.push("...".into());
                break;
            }
            out.push(if end == start {
                start.to_string()
            } else {
                format!("{start}-{end}")
            });
        }
        out.join(", ")
    }
}

impl std::fmt::Display for Tally {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kinds: Vec<String> = self.kinds.iter().map(|(k, n)| format!("{k} {n}")).collect();
        write!(f, "{} records differ ({})", self.records, kinds.join(", "))?;
        match self.frames.len() {
            0 => Ok(()),
            1 => write!(f, ", in frame {}", self.frames[0]),
            n => write!(f, ", in {n} frames: {}", self.frame_runs(8)),
        }
    }
}

/// How `actual` differs from `expected` as a whole ([`Tally`]); empty when
/// they are equal.
#[must_use]
pub fn tally(expected: &[u8], actual: &[u8]) -> Tally {
    let mut tally = Tally::default();
    if expected == actual {
        return tally;
    }
    let raw = |bytes: &[u8], d: &Decoded| bytes[d.offset..d.offset + d.len].to_vec();
    let (mut e, mut a) = (Decoder::new(expected), Decoder::new(actual));
    let mut frame = None;
    loop {
        let (ei, ai) = (e.next(), a.next());
        if ei.is_none() && ai.is_none() {
            break;
        }
        if let Some(Decoded {
            result: Ok(Record::FrameStart { frame: f, .. }),
            ..
        }) = &ei
        {
            frame = Some(*f);
        }
        let same = match (&ei, &ai) {
            (Some(x), Some(y)) => raw(expected, x) == raw(actual, y),
            _ => false,
        };
        if same {
            continue;
        }
        tally.records += 1;
        let kind = ei.as_ref().or(ai.as_ref()).map_or("unreadable", |d| {
            d.result.as_ref().map_or("unreadable", Record::kind)
        });
        *tally.kinds.entry(kind).or_default() += 1;
        if let Some(f) = frame
            && tally.frames.last() != Some(&f)
        {
            tally.frames.push(f);
        }
    }
    tally
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_read_as_runs() {
        let t = Tally {
            frames: vec![0, 3, 4, 5, 9, 11, 12],
            ..Tally::default()
        };
        assert_eq!(t.frame_runs(8), "0, 3-5, 9, 11-12");
        assert_eq!(t.frame_runs(2), "0, 3-5, ...");
    }
}
