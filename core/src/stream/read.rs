//! Receiving frames one byte at a time, as a device reads its UART or a
//! host its serial port: each zero byte ends a frame and gives its record
//! or why it is unreadable, and the next frame starts after it
//! (docs/stream-format.md, "Receiving").

use cobs::{DecodeResult, DecoderState};

use super::Record;
use super::digest::FRAME_CRC;
use super::encode::{MAX_FRAME, MAX_RECORD};

/// Why a frame could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// The bytes between two delimiters are not valid COBS.
    Cobs,
    /// Longer than [`MAX_FRAME`]: not a frame of this format.
    TooLong,
    /// Fewer than 5 decoded bytes: no room for a record and its CRC.
    TooShort,
    /// The CRC-32 does not match the record bytes.
    Crc {
        /// The CRC carried by the frame.
        carried: u32,
        /// The CRC of the bytes received.
        computed: u32,
    },
    /// The CRC matches but the bytes are not a record of this version.
    Record,
    /// A well-formed frame (its CRC checks) of a record kind this reader
    /// does not know: a newer writer's. Receivers skip it
    /// (docs/stream-format.md); it is not a corrupt frame.
    UnknownKind {
        /// The record's tag.
        tag: u32,
    },
    /// The input ended without a closing zero byte.
    Truncated,
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FrameError::Cobs => f.write_str("invalid COBS encoding"),
            FrameError::TooLong => write!(f, "frame longer than MAX_FRAME = {MAX_FRAME} bytes"),
            FrameError::TooShort => f.write_str("frame too short for a record and its CRC"),
            FrameError::Crc { carried, computed } => {
                write!(
                    f,
                    "CRC mismatch (frame carries {carried:#010x}, bytes give {computed:#010x})"
                )
            }
            FrameError::Record => f.write_str("CRC is valid but the bytes are not a known record"),
            FrameError::UnknownKind { tag } => {
                write!(f, "a record of unknown kind (tag {tag}), skipped")
            }
            FrameError::Truncated => f.write_str("truncated: the stream ends inside a frame"),
        }
    }
}

impl core::error::Error for FrameError {}

impl FrameError {
    /// Whether the frame is damaged (and not merely of a newer kind).
    #[must_use]
    pub fn is_corrupt(&self) -> bool {
        !matches!(self, FrameError::UnknownKind { .. })
    }
}

/// The decoded bytes of the largest frame: a record and its CRC-32.
const MAX_DECODED: usize = MAX_RECORD + 4;

/// Takes COBS frames off the wire one byte at a time into a buffer `B`
/// (`[u8; N]`, or a `&mut [u8]` its owner lends) and gives each frame's
/// payload once its CRC-32 checks: the framing of every record
/// (docs/stream-format.md, "Layers"), for payloads of any size up to the
/// buffer's less the CRC. [`Reader`] is one for records; a device reads a
/// sent scenario with another (`crate::sent`).
#[derive(Debug)]
pub struct Deframer<B> {
    cobs: DecoderState,
    decoded: B,
    /// Bytes decoded into `decoded`.
    len: usize,
    /// Bytes of the frame so far, its delimiter not included.
    wire: usize,
    /// The frame's first fault, reported at its delimiter.
    fault: Option<FrameError>,
}

impl<B: AsRef<[u8]> + AsMut<[u8]>> Deframer<B> {
    /// A deframer decoding into `buffer`, waiting for a frame's first byte.
    pub const fn new(buffer: B) -> Deframer<B> {
        Deframer {
            cobs: DecoderState::Idle,
            decoded: buffer,
            len: 0,
            wire: 0,
            fault: None,
        }
    }

    /// Bytes of the frame in progress (0 between frames).
    #[must_use]
    pub const fn pending(&self) -> usize {
        self.wire
    }

    /// Takes one byte off the wire. At a zero byte, the payload of the
    /// frame it ends — CRC checked and removed — or why the frame is
    /// unreadable ([`FrameError::Cobs`], [`FrameError::TooLong`] beyond the
    /// buffer, [`FrameError::TooShort`], [`FrameError::Crc`]); the next byte
    /// starts a new frame.
    pub fn push(&mut self, byte: u8) -> Option<Result<&[u8], FrameError>> {
        if byte != 0 {
            self.take(byte);
            return None;
        }
        let (fault, wire, len) = (self.fault.take(), self.wire, self.len);
        let end = self.cobs.feed(0);
        (self.cobs, self.len, self.wire) = (DecoderState::Idle, 0, 0);
        Some(match (fault, wire, end) {
            (Some(fault), _, _) => Err(fault),
            // An empty frame is not valid COBS.
            (None, 1.., Ok(DecodeResult::DataComplete)) => {
                payload(self.decoded.as_ref().get(..len).unwrap_or_default())
            }
            (None, _, _) => Err(FrameError::Cobs),
        })
    }

    /// Takes a run of bytes none of which is zero: the same as pushing
    /// them one at a time (none ends a frame), but the data of a COBS
    /// block is copied at once rather than fed through the decoder.
    ///
    /// Both faults such a run can cause are [`FrameError::TooLong`] (no
    /// non-zero byte is invalid COBS), so it does not matter which of its
    /// bytes would have been first to cause one.
    pub fn take_run(&mut self, run: &[u8]) {
        self.wire = self.wire.saturating_add(run.len());
        if self.refused() {
            return;
        }
        let mut rest = run;
        while let Some((&byte, tail)) = rest.split_first() {
            let (left, chain) = match self.cobs {
                DecoderState::Grab(left) => (left, false),
                DecoderState::GrabChain(left) => (left, true),
                DecoderState::Idle => (0, false),
            };
            if left == 0 {
                // A block's code byte: through the decoder.
                self.decode(byte);
                if self.fault.is_some() {
                    return;
                }
                rest = tail;
                continue;
            }
            // Inside a block: its next `left` bytes are data as they are.
            let (data, tail) = rest.split_at(rest.len().min(usize::from(left)));
            let Some(slots) = self
                .decoded
                .as_mut()
                .get_mut(self.len..self.len + data.len())
            else {
                self.fault = Some(FrameError::TooLong);
                return;
            };
            slots.copy_from_slice(data);
            self.len += data.len();
            let left = left - u8::try_from(data.len()).unwrap_or(left);
            self.cobs = if chain {
                DecoderState::GrabChain(left)
            } else {
                DecoderState::Grab(left)
            };
            rest = tail;
        }
    }

    fn take(&mut self, byte: u8) {
        self.wire = self.wire.saturating_add(1);
        if !self.refused() {
            self.decode(byte);
        }
    }

    /// Whether the frame has a fault: one found before, or now that it is
    /// longer than any frame the buffer holds, refused before decoding
    /// (COBS adds a byte per 254, the delimiter is not counted).
    fn refused(&mut self) -> bool {
        let capacity = self.decoded.as_ref().len();
        if self.fault.is_none() && self.wire > capacity + capacity.div_ceil(254) {
            self.fault = Some(FrameError::TooLong);
        }
        self.fault.is_some()
    }

    /// Feeds a byte of the frame to the COBS decoder.
    fn decode(&mut self, byte: u8) {
        match self.cobs.feed(byte) {
            Ok(DecodeResult::DataContinue(b)) => match self.decoded.as_mut().get_mut(self.len) {
                Some(slot) => {
                    *slot = b;
                    self.len += 1;
                }
                None => self.fault = Some(FrameError::TooLong),
            },
            Ok(DecodeResult::NoData | DecodeResult::DataComplete) => {}
            Err(_) => self.fault = Some(FrameError::Cobs),
        }
    }
}

/// The payload of a COBS-decoded frame: the bytes before its CRC-32, if
/// the CRC matches.
fn payload(decoded: &[u8]) -> Result<&[u8], FrameError> {
    let Some(split) = decoded.len().checked_sub(4).filter(|&n| n > 0) else {
        return Err(FrameError::TooShort);
    };
    let (payload, crc) = decoded.split_at(split);
    let carried = u32::from_le_bytes(crc.try_into().map_err(|_| FrameError::TooShort)?);
    let computed = FRAME_CRC.checksum(payload);
    if carried != computed {
        return Err(FrameError::Crc { carried, computed });
    }
    Ok(payload)
}

/// Reads frames one byte at a time, holding at most one frame: one byte
/// in, at most one record out. A damaged frame costs that frame only.
///
/// ```
/// use morphogen::stream::{Encoder, Reader, Record, Sink};
/// let mut wire = Vec::new();
/// let mut encoder = Encoder::new(&mut wire);
/// encoder.record(&Record::FrameEnd { frame: 3 }).unwrap();
/// encoder.record(&Record::FrameEnd { frame: 4 }).unwrap();
/// wire[2] ^= 0x40; // a flipped bit in the first frame
///
/// let mut reader = Reader::new();
/// let frames: Vec<_> = wire.iter().filter_map(|&byte| reader.push(byte)).collect();
/// assert!(frames[0].is_err());
/// assert_eq!(frames[1], Ok(Record::FrameEnd { frame: 4 }));
/// ```
#[derive(Debug)]
pub struct Reader {
    frames: Deframer<[u8; MAX_DECODED]>,
}

impl Reader {
    /// A reader waiting for the first byte of a frame.
    #[must_use]
    pub const fn new() -> Reader {
        Reader {
            frames: Deframer::new([0; MAX_DECODED]),
        }
    }

    /// Takes one byte off the wire. At a zero byte, the frame it ends:
    /// its record, or why the frame is unreadable (checked in the order
    /// of docs/stream-format.md); the reader then starts a new frame.
    pub fn push(&mut self, byte: u8) -> Option<Result<Record, FrameError>> {
        self.frames.push(byte).map(|frame| frame.and_then(record))
    }

    /// Takes a run of bytes none of which is zero, as pushing them one
    /// at a time would ([`Deframer::take_run`]).
    pub fn take_run(&mut self, run: &[u8]) {
        self.frames.take_run(run);
    }

    /// Bytes of the frame in progress (0 between frames): what a stream
    /// that ends now would leave [`FrameError::Truncated`].
    #[must_use]
    pub const fn pending(&self) -> usize {
        self.frames.pending()
    }
}

impl Default for Reader {
    fn default() -> Reader {
        Reader::new()
    }
}

/// The record in a frame's payload.
fn record(payload: &[u8]) -> Result<Record, FrameError> {
    match postcard::take_from_bytes::<Record>(payload) {
        Ok((r, [])) => Ok(r),
        _ => match tag(payload) {
            Some(tag) if tag >= RECORD_KINDS => Err(FrameError::UnknownKind { tag }),
            _ => Err(FrameError::Record),
        },
    }
}

/// Record kinds of this version (tags 0 to 12, docs/stream-format.md).
const RECORD_KINDS: u32 = 13;

/// The record's tag: postcard's leading varint.
fn tag(record: &[u8]) -> Option<u32> {
    let mut value = 0u32;
    for (i, &b) in record.iter().take(5).enumerate() {
        value |= u32::from(b & 0x7F) << (7 * i);
        if b & 0x80 == 0 {
            return Some(value);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::fx::Fx;
    use crate::stream::{Encoder, Header, Sink};

    fn records() -> Vec<Record> {
        let mut records = std::vec![Record::Header(Header {
            version: 1,
            preset: "croton".try_into().unwrap(),
            seed: 7,
            params: 0x0123_4567_89ab_cdef,
        })];
        for i in 0..6u32 {
            records.push(Record::Cell {
                id: i * 1000,
                kind: i as u8,
                p: [Fx::from_ratio(i as i32, 3), -Fx::ONE],
            });
        }
        records.push(Record::FrameEnd { frame: 0 });
        records
    }

    /// The stream of `records` and the end of each frame in it.
    fn wire(records: &[Record]) -> (Vec<u8>, Vec<usize>) {
        let mut encoder = Encoder::new(Vec::new());
        let mut ends = Vec::new();
        for r in records {
            encoder.record(r).unwrap();
            ends.push(encoder.bytes() as usize);
        }
        (encoder.into_writer(), ends)
    }

    /// Every frame `bytes` gives, fed one byte at a time.
    fn read(bytes: &[u8]) -> Vec<Result<Record, FrameError>> {
        let mut reader = Reader::new();
        bytes.iter().filter_map(|&b| reader.push(b)).collect()
    }

    /// The frames `bytes` gives a deframer with a buffer of `N` bytes, fed
    /// one byte at a time or each run of non-zero bytes at once, and the
    /// bytes pending at the end.
    fn deframed<const N: usize>(
        bytes: &[u8],
        runs: bool,
    ) -> (Vec<Result<Vec<u8>, FrameError>>, usize) {
        let mut deframer = Deframer::new([0u8; N]);
        let mut frames = Vec::new();
        let mut push = |d: &mut Deframer<[u8; N]>, byte| {
            if let Some(frame) = d.push(byte) {
                frames.push(frame.map(<[u8]>::to_vec));
            }
        };
        if runs {
            let mut pieces = bytes.split(|&b| b == 0).peekable();
            while let Some(run) = pieces.next() {
                deframer.take_run(run);
                if pieces.peek().is_some() {
                    push(&mut deframer, 0);
                }
            }
        } else {
            for &byte in bytes {
                push(&mut deframer, byte);
            }
        }
        (frames, deframer.pending())
    }

    #[test]
    fn a_run_taken_at_once_reads_as_its_bytes_one_by_one() {
        // Clean frames, bytes overwritten, runs of one byte inserted (as
        // long as several frames), with buffers small enough for frames
        // to be too long before or after decoding.
        let (clean, _) = wire(&records());
        let mut rng = crate::rng::KeyedRng::new(11, 0);
        let mut random = |n: usize| rng.below(n as u32) as usize;
        for round in 0..600 {
            let mut bytes = clean.clone();
            for _ in 0..random(4) {
                let i = random(bytes.len());
                bytes[i] = random(256) as u8;
            }
            if round % 3 == 0 {
                let (at, byte, n) = (random(bytes.len()), random(255) as u8 + 1, random(700));
                bytes.splice(at..at, core::iter::repeat_n(byte, n));
            }
            bytes.truncate(bytes.len() - random(3));
            // Frames of long blocks (up to 1,000 bytes, zeros rare) for
            // a deframer whose buffer holds them.
            let mut long = Vec::new();
            for _ in 0..3 {
                let payload: Vec<u8> = (0..random(1000))
                    .map(|_| {
                        if random(300) == 0 {
                            0
                        } else {
                            random(255) as u8 + 1
                        }
                    })
                    .collect();
                let mut frame = std::vec![0; cobs::max_encoding_length(payload.len())];
                let n = cobs::encode(&payload, &mut frame);
                long.extend(&frame[..n]);
                long.push(0);
            }
            if round % 2 == 0 {
                let i = random(long.len());
                long[i] = random(256) as u8;
            }
            assert_eq!(
                deframed::<1024>(&long, true),
                deframed::<1024>(&long, false)
            );
            assert_eq!(deframed::<8>(&bytes, true), deframed::<8>(&bytes, false));
            assert_eq!(deframed::<40>(&bytes, true), deframed::<40>(&bytes, false));
            assert_eq!(
                deframed::<MAX_DECODED>(&bytes, true),
                deframed::<MAX_DECODED>(&bytes, false)
            );
        }
    }

    #[test]
    fn frames_come_out_at_their_delimiters_only() {
        let records = records();
        let (bytes, ends) = wire(&records);
        let mut reader = Reader::new();
        let mut out = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            if let Some(frame) = reader.push(b) {
                assert!(ends.contains(&(i + 1)), "a frame ended at byte {i}");
                assert_eq!(reader.pending(), 0);
                out.push(frame.unwrap());
            }
        }
        assert_eq!(out, records);
    }

    #[test]
    fn a_flipped_bit_costs_exactly_its_frame() {
        let records = records();
        let (bytes, ends) = wire(&records);
        for (k, &end) in ends.iter().enumerate() {
            let start = if k == 0 { 0 } else { ends[k - 1] };
            for i in start..end {
                for bit in 0..8 {
                    let mut damaged = bytes.clone();
                    damaged[i] ^= 1 << bit;
                    let frames = read(&damaged);
                    let good: Vec<&Record> =
                        frames.iter().filter_map(|f| f.as_ref().ok()).collect();
                    // A flipped delimiter joins the frame to the next one.
                    let lost = if i == end - 1 { k..=k + 1 } else { k..=k };
                    let want: Vec<&Record> = records
                        .iter()
                        .enumerate()
                        .filter(|(j, _)| !lost.contains(j))
                        .map(|(_, r)| r)
                        .collect();
                    assert_eq!(good, want, "bit {bit} of byte {i} (frame {k})");
                    // Reported as an error, or (the last delimiter) left
                    // pending as a truncated frame.
                    let last_delimiter = i == bytes.len() - 1;
                    assert_eq!(frames.iter().any(Result::is_err), !last_delimiter);
                }
            }
        }
    }

    #[test]
    fn an_overlong_frame_names_the_limit_and_the_next_one_reads() {
        let mut bytes = std::vec![9u8; 300];
        bytes.push(0);
        let (tail, _) = wire(&records()[..2]);
        bytes.extend(&tail);
        let mut reader = Reader::new();
        for &b in &bytes[..300] {
            assert_eq!(reader.push(b), None);
        }
        assert_eq!(reader.pending(), 300);
        let e = reader.push(0).unwrap().unwrap_err();
        assert_eq!(e, FrameError::TooLong);
        assert_eq!(
            std::format!("{e}"),
            "frame longer than MAX_FRAME = 102 bytes"
        );
        let rest: Vec<_> = bytes[301..]
            .iter()
            .filter_map(|&b| reader.push(b))
            .collect();
        assert_eq!(rest, [Ok(records()[0].clone()), Ok(records()[1].clone())]);
    }

    #[test]
    fn a_reader_that_joins_mid_frame_loses_only_that_frame() {
        let records = records();
        let (bytes, ends) = wire(&records);
        let frames = read(&bytes[ends[2] - 4..]);
        assert!(frames[0].is_err());
        let good: Vec<Record> = frames.into_iter().skip(1).map(Result::unwrap).collect();
        assert_eq!(good, records[3..]);
    }

    #[test]
    fn empty_and_short_frames_are_errors_in_the_documented_order() {
        assert_eq!(read(&[0]), [Err(FrameError::Cobs)]);
        assert_eq!(read(&[3, 1, 0]), [Err(FrameError::Cobs)]);
        assert_eq!(read(&[5, 1, 2, 3, 4, 0]), [Err(FrameError::TooShort)]);
        let mut tagged = std::vec![5u8, 0, 0, 0, 0];
        tagged[1..].copy_from_slice(&FRAME_CRC.checksum(&[5]).to_le_bytes());
        let mut framed = [0u8; 16];
        let n = cobs::encode(&[&[5u8][..], &tagged[1..]].concat(), &mut framed);
        let mut bytes = framed[..n].to_vec();
        bytes.push(0);
        // Tag 5 (a polygon) without its fields.
        assert_eq!(read(&bytes), [Err(FrameError::Record)]);
    }
}
