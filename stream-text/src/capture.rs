//! Splitting a device capture into the streams it holds: each starts with
//! a header record, back to back.

use std::ops::Range;

use morphogen::stream::{Decoder, Header, Record};

/// One stream within a capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Its header (`None` for bytes before the first readable header).
    pub header: Option<Header>,
    /// Where it lies in the capture.
    pub range: Range<usize>,
    /// Its bytes: those of `range` but the frames of link records
    /// ([`Record::Extent`]), which are not part of a stream.
    pub stream: Vec<u8>,
}

/// The streams of a capture, in order. Bytes before the first readable
/// header form a part without a header.
#[must_use]
pub fn split(capture: &[u8]) -> Vec<Part> {
    let mut parts: Vec<Part> = Vec::new();
    for d in Decoder::new(capture) {
        let end = d.offset + d.len;
        let bytes = &capture[d.offset..end];
        match d.result {
            Ok(Record::Header(h)) => parts.push(Part {
                header: Some(h),
                range: d.offset..end,
                stream: bytes.to_vec(),
            }),
            result => {
                let link = matches!(result, Ok(Record::Extent { .. }));
                match parts.last_mut() {
                    Some(last) => {
                        last.range.end = end;
                        if !link {
                            last.stream.extend_from_slice(bytes);
                        }
                    }
                    None => parts.push(Part {
                        header: None,
                        range: d.offset..end,
                        stream: if link { Vec::new() } else { bytes.to_vec() },
                    }),
                }
            }
        }
    }
    parts
}
