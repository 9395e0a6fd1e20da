//! Splitting a device capture into the streams it holds: each starts with
//! a header record, back to back.

use std::ops::Range;

use morphogen::stream::{Decoder, Header, Record};

/// One stream within a capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Its header (`None` for bytes before the first readable header).
    pub header: Option<Header>,
    /// Its bytes within the capture.
    pub range: Range<usize>,
}

/// The streams of a capture, in order. Bytes before the first readable
/// header form a part without a header.
#[must_use]
pub fn split(capture: &[u8]) -> Vec<Part> {
    let mut parts: Vec<Part> = Vec::new();
    for d in Decoder::new(capture) {
        let end = d.offset + d.len;
        match d.result {
            Ok(Record::Header(h)) => parts.push(Part {
                header: Some(h),
                range: d.offset..end,
            }),
            _ => match parts.last_mut() {
                Some(last) => last.range.end = end,
                None => parts.push(Part {
                    header: None,
                    range: d.offset..end,
                }),
            },
        }
    }
    parts
}
