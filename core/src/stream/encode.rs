//! Framing records for the wire: postcard, CRC-32, COBS, zero delimiter.

use embedded_io::Write;

use super::digest::{FRAME_CRC, StreamDigest};
use super::{Record, Sink, SinkError};

/// The largest encoded record, in bytes (postcard, before CRC and COBS).
pub const MAX_RECORD: usize = 96;
/// The largest frame on the wire: the record, its 4-byte CRC, COBS
/// overhead (1 byte per 254) and the zero delimiter.
pub const MAX_FRAME: usize = MAX_RECORD + 4 + (MAX_RECORD + 4) / 254 + 2;

/// The sink that frames records onto an [`embedded_io::Write`] — a
/// UART, a `&mut [u8]`, a `Vec<u8>` (with the `std` feature) — and
/// digests the stream.
///
/// ```
/// use morphogen::stream::{Encoder, Record, Sink};
/// let mut buffer = [0u8; 64];
/// let mut encoder = Encoder::new(&mut buffer[..]);
/// encoder.record(&Record::FrameEnd { frame: 3 }).unwrap();
/// let len = encoder.bytes() as usize;
/// assert_eq!(buffer[..len], [0x07, 0x02, 0x03, 0xc7, 0x21, 0xe6, 0xea, 0x00]);
/// ```
///
/// A `std::io::Write`, such as a file, through the `std` feature's
/// adapter:
///
/// ```
/// # #[cfg(feature = "std")] {
/// use morphogen::embedded_io_adapters::std::FromStd;
/// use morphogen::stream::{Encoder, Record, Sink};
/// let path = std::env::temp_dir().join("morphogen-doc-stream.bin");
/// let mut encoder = Encoder::new(FromStd::new(std::fs::File::create(&path).unwrap()));
/// encoder.record(&Record::FrameEnd { frame: 3 }).unwrap();
/// drop(encoder);
/// assert_eq!(std::fs::read(&path).unwrap().len(), 8);
/// # }
/// ```
#[derive(Debug)]
pub struct Encoder<W> {
    writer: W,
    digest: StreamDigest,
    frames: u32,
    bytes: u64,
}

impl<W: Write> Encoder<W> {
    /// An encoder writing to `writer`.
    pub fn new(writer: W) -> Encoder<W> {
        Encoder {
            writer,
            digest: StreamDigest::new(),
            frames: 0,
            bytes: 0,
        }
    }

    /// The CRC-64/XZ of every byte written so far.
    #[must_use]
    pub fn digest(&self) -> u64 {
        self.digest.value()
    }

    /// Frames written so far.
    #[must_use]
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Bytes written so far.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut W {
        &mut self.writer
    }

    /// Gives the writer back.
    pub fn into_writer(self) -> W {
        self.writer
    }

    /// Writes a link record ([`Record::Extent`]) beside the stream: framed
    /// like any record, but not counted in [`Encoder::digest`],
    /// [`Encoder::frames`] or [`Encoder::bytes`] — it is not part of the
    /// stream (docs/stream-format.md, "The extent").
    ///
    /// # Errors
    /// As [`Sink::record`].
    pub fn link(&mut self, record: &Record) -> Result<(), SinkError> {
        let mut frame = [0u8; MAX_FRAME];
        let len = Self::encode_frame(record, &mut frame)?;
        let bytes = frame.get(..len).ok_or(SinkError::RecordTooLarge)?;
        self.writer.write_all(bytes).map_err(|_| SinkError::Write)
    }

    /// Encodes one record into `frame` and returns the frame's length.
    ///
    /// # Errors
    /// [`SinkError::RecordTooLarge`] when the record exceeds [`MAX_RECORD`].
    pub fn encode_frame(record: &Record, frame: &mut [u8; MAX_FRAME]) -> Result<usize, SinkError> {
        let mut raw = [0u8; MAX_RECORD + 4];
        let len = postcard::to_slice(record, &mut raw[..MAX_RECORD])
            .map_err(|_| SinkError::RecordTooLarge)?
            .len();
        frame_payload(&mut raw, len, frame).ok_or(SinkError::RecordTooLarge)
    }
}

impl<W: Write> Sink for Encoder<W> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        let mut frame = [0u8; MAX_FRAME];
        let len = Self::encode_frame(record, &mut frame)?;
        let bytes = frame.get(..len).ok_or(SinkError::RecordTooLarge)?;
        self.writer.write_all(bytes).map_err(|_| SinkError::Write)?;
        self.digest.update(bytes);
        self.frames += 1;
        self.bytes += len as u64;
        Ok(())
    }
}

/// Frames the payload `raw[..len]` into `frame`: appends its CRC-32 in
/// `raw` (which needs 4 bytes to spare), COBS-encodes, ends with the zero
/// delimiter; the frame's length, or `None` when `raw` or `frame` is too
/// small.
pub(crate) fn frame_payload(raw: &mut [u8], len: usize, frame: &mut [u8]) -> Option<usize> {
    let crc = FRAME_CRC.checksum(raw.get(..len)?).to_le_bytes();
    raw.get_mut(len..len + 4)?.copy_from_slice(&crc);
    let room = frame.len().checked_sub(1)?;
    let encoded = cobs::try_encode(raw.get(..len + 4)?, frame.get_mut(..room)?).ok()?;
    *frame.get_mut(encoded)? = 0;
    Some(encoded + 1)
}
