//! Reading the frames of a whole byte string (a file, a capture): the
//! [`Reader`]'s frames with their places, and a truncated last frame.

use super::Record;
use super::read::{FrameError, Reader};

/// One frame read from a byte string.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoded {
    /// Offset of the frame's first byte in the input.
    pub offset: usize,
    /// Length of the frame including its zero delimiter (if any).
    pub len: usize,
    /// The record, or why the frame is unreadable.
    pub result: Result<Record, FrameError>,
}

/// Iterates over the frames of an encoded stream.
///
/// ```
/// use morphogen::stream::{Decoder, Encoder, Record, Sink};
/// let mut enc = Encoder::new(Vec::new());
/// enc.record(&Record::FrameEnd { frame: 3 }).unwrap();
/// let bytes = enc.into_writer();
/// let frames: Vec<_> = Decoder::new(&bytes).collect();
/// assert_eq!(frames[0].result, Ok(Record::FrameEnd { frame: 3 }));
/// ```
#[derive(Clone, Debug)]
pub struct Decoder<'a> {
    input: &'a [u8],
    pos: usize,
}

impl<'a> Decoder<'a> {
    /// A decoder over `input`.
    #[must_use]
    pub fn new(input: &'a [u8]) -> Decoder<'a> {
        Decoder { input, pos: 0 }
    }
}

impl Iterator for Decoder<'_> {
    type Item = Decoded;

    fn next(&mut self) -> Option<Decoded> {
        let rest = self.input.get(self.pos..)?;
        if rest.is_empty() {
            return None;
        }
        let offset = self.pos;
        let mut reader = Reader::new();
        // The bytes up to the next delimiter, as one run, then the
        // delimiter.
        let (run, delimiter) = match rest.iter().position(|&b| b == 0) {
            Some(at) => rest.split_at(at),
            None => (rest, &[][..]),
        };
        reader.take_run(run);
        if let Some(result) = delimiter.first().and_then(|&zero| reader.push(zero)) {
            let len = run.len() + 1;
            self.pos += len;
            return Some(Decoded {
                offset,
                len,
                result,
            });
        }
        self.pos = self.input.len();
        Some(Decoded {
            offset,
            len: rest.len(),
            result: Err(FrameError::Truncated),
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::fx::Fx;
    use crate::stream::digest::FRAME_CRC;
    use crate::stream::{Encoder, Header, Sink};

    fn sample_records() -> Vec<Record> {
        std::vec![
            Record::Header(Header {
                version: 1,
                preset: "growth-curve".try_into().unwrap(),
                seed: 7,
                params: 0xdead_beef
            }),
            Record::FrameStart {
                frame: 0,
                time: Fx::from_int(3)
            },
            Record::Segment {
                a: [Fx::ONE; 3],
                b: [Fx::MIN, Fx::MAX, Fx::ZERO],
                width: Fx::HALF,
                colour: 9
            },
            Record::Cell {
                id: 1_000_000,
                kind: 2,
                p: [Fx::from_ratio(1, 3), -Fx::ONE]
            },
            Record::Ring {
                module: 7,
                ring: 300,
                points: 24
            },
            Record::FrameEnd { frame: 0 },
        ]
    }

    fn encode(records: &[Record]) -> Vec<u8> {
        let mut enc = Encoder::new(Vec::new());
        for r in records {
            enc.record(r).unwrap();
        }
        enc.into_writer()
    }

    #[test]
    fn a_record_of_a_newer_kind_is_skipped_not_corrupt() {
        // Tag 13 with two bytes of payload, framed as the encoder frames.
        let record = [13u8, 1, 2];
        let mut raw = Vec::from(record);
        raw.extend_from_slice(&FRAME_CRC.checksum(&record).to_le_bytes());
        let mut framed = [0u8; 32];
        let n = cobs::encode(&raw, &mut framed);
        let mut bytes = Vec::from(&framed[..n]);
        bytes.push(0);
        bytes.extend(encode(&sample_records()[..2]));
        let decoded: Vec<Decoded> = Decoder::new(&bytes).collect();
        assert_eq!(decoded[0].result, Err(FrameError::UnknownKind { tag: 13 }));
        assert!(!FrameError::UnknownKind { tag: 13 }.is_corrupt());
        assert_eq!(decoded.len(), 3);
        assert!(decoded[1].result.is_ok() && decoded[2].result.is_ok());
        // A known tag whose payload does not parse is corrupt.
        assert!(FrameError::Record.is_corrupt());
    }

    #[test]
    fn round_trip() {
        let records = sample_records();
        let bytes = encode(&records);
        let back: Vec<Record> = Decoder::new(&bytes).map(|d| d.result.unwrap()).collect();
        assert_eq!(back, records);
    }

    #[test]
    fn corrupt_frame_is_reported_and_the_next_frame_decodes() {
        let records = sample_records();
        let mut bytes = encode(&records);
        let second = Decoder::new(&bytes).nth(1).unwrap();
        bytes[second.offset + 2] ^= 0x10;
        let decoded: Vec<Decoded> = Decoder::new(&bytes).collect();
        assert_eq!(decoded.len(), records.len());
        assert!(matches!(
            decoded[1].result,
            Err(FrameError::Crc { .. }) | Err(FrameError::Cobs)
        ));
        assert_eq!(decoded[2].result.as_ref().unwrap(), &records[2]);
    }

    #[test]
    fn truncated_stream_ends_with_a_truncated_frame() {
        let bytes = encode(&sample_records());
        let cut = &bytes[..bytes.len() - 3];
        let last = Decoder::new(cut).last().unwrap();
        assert_eq!(last.result, Err(FrameError::Truncated));
    }

    #[test]
    fn every_single_bit_flip_is_detected() {
        let records = sample_records();
        let bytes = encode(&records);
        for i in 0..bytes.len() {
            for bit in 0..8 {
                let mut b = bytes.clone();
                b[i] ^= 1 << bit;
                let back: Vec<Result<Record, FrameError>> =
                    Decoder::new(&b).map(|d| d.result).collect();
                let clean = back.len() == records.len()
                    && back.iter().zip(&records).all(|(x, r)| x.as_ref() == Ok(r));
                assert!(!clean, "flip of bit {bit} at byte {i} went unnoticed");
            }
        }
    }

    #[test]
    fn garbage_never_panics() {
        let mut rng = crate::rng::KeyedRng::new(99, 0);
        for _ in 0..2_000 {
            let len = rng.below(300) as usize;
            let junk: Vec<u8> = (0..len)
                .map(|_| {
                    if rng.below(8) == 0 {
                        0
                    } else {
                        rng.next_u32() as u8
                    }
                })
                .collect();
            for d in Decoder::new(&junk) {
                assert!(d.len > 0);
            }
        }
    }
}
