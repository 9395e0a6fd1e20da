//! Where the output writers read records from, as many passes as they
//! need: a slice in memory, or a stream file read back frame by frame
//! through the core's [`Reader`] ([`FrameReader`], the framing of
//! [`Decoder`](morphogen::stream::Decoder) over any [`BufRead`]), so that
//! no writer holds a whole stream (docs/stream-format.md, "Framing").

use std::fs::File;
use std::io::{self, BufRead, BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::stream::{Decoded, FrameError, Reader, Record};

/// Where a record sits in its source: the byte offset of its frame in a
/// stream file, its index in a slice. A later pass may start there.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Place(pub u64);

impl Place {
    /// The first record.
    pub const START: Place = Place(0);
}

/// A sequence of records that can be read again from any [`Place`] it
/// handed out. Unreadable frames are skipped, as the writers always did.
pub trait Records {
    /// Calls `each` with every readable record from `from` on (that one
    /// included) and its place, while `each` returns `true`.
    ///
    /// # Errors
    /// `each`'s error, or when the source cannot be read.
    fn visit_while<F>(&self, from: Place, each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<bool>;

    /// Calls `each` with every readable record from `from` on and its
    /// place.
    ///
    /// # Errors
    /// `each`'s error, or when the source cannot be read.
    fn visit<F>(&self, from: Place, mut each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<()>,
    {
        self.visit_while(from, |place, r| each(place, r).map(|()| true))
    }

    /// The number of `FrameStart` records (a mosaic's days).
    ///
    /// # Errors
    /// When the source cannot be read.
    fn frame_starts(&self) -> Result<usize> {
        count_frame_starts(self)
    }
}

/// The `FrameStart` records of `records`, counted by reading them all.
fn count_frame_starts<R: Records + ?Sized>(records: &R) -> Result<usize> {
    let mut count = 0;
    records.visit(Place::START, |_, r| {
        count += usize::from(matches!(r, Record::FrameStart { .. }));
        Ok(())
    })?;
    Ok(count)
}

impl Records for [Record] {
    fn visit_while<F>(&self, from: Place, mut each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<bool>,
    {
        let start = usize::try_from(from.0).unwrap_or(usize::MAX);
        for (i, r) in self.iter().enumerate().skip(start) {
            if !each(Place(i as u64), r)? {
                break;
            }
        }
        Ok(())
    }
}

impl Records for Vec<Record> {
    fn visit_while<F>(&self, from: Place, each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<bool>,
    {
        self.as_slice().visit_while(from, each)
    }
}

impl<const N: usize> Records for [Record; N] {
    fn visit_while<F>(&self, from: Place, each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<bool>,
    {
        self.as_slice().visit_while(from, each)
    }
}

/// A stream file on disk, read back in passes.
#[derive(Debug, Clone)]
pub struct StreamFile {
    path: PathBuf,
    /// Its `FrameStart` records, when the run that wrote it counted them.
    frame_starts: Option<usize>,
}

impl StreamFile {
    /// The stream file at `path`.
    #[must_use]
    pub fn new(path: &Path) -> StreamFile {
        StreamFile {
            path: path.to_path_buf(),
            frame_starts: None,
        }
    }

    /// The stream file, holding `count` `FrameStart` records (counted by
    /// the run that wrote it, so [`Records::frame_starts`] need not read
    /// it).
    #[must_use]
    pub fn with_frame_starts(self, count: usize) -> StreamFile {
        StreamFile {
            frame_starts: Some(count),
            ..self
        }
    }

    /// Its path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Its frames from the byte offset `from` on.
    ///
    /// # Errors
    /// When the file cannot be opened or sought.
    pub fn frames(&self, from: Place) -> Result<FrameReader<BufReader<File>>> {
        let mut file = morphogen_scenario::open_regular(&self.path)
            .map_err(|e| anyhow::anyhow!(e))
            .with_context(|| format!("cannot read {}", self.path.display()))?;
        if from.0 > 0 {
            file.seek(SeekFrom::Start(from.0))
                .with_context(|| format!("cannot read {}", self.path.display()))?;
        }
        Ok(FrameReader::new(
            BufReader::with_capacity(1 << 16, file),
            from.0,
        ))
    }
}

impl Records for StreamFile {
    fn frame_starts(&self) -> Result<usize> {
        match self.frame_starts {
            Some(count) => Ok(count),
            None => count_frame_starts(self),
        }
    }

    fn visit_while<F>(&self, from: Place, mut each: F) -> Result<()>
    where
        F: FnMut(Place, &Record) -> Result<bool>,
    {
        let mut frames = self.frames(from)?;
        while let Some(d) = frames
            .next_frame()
            .with_context(|| format!("cannot read {}", self.path.display()))?
        {
            if let Ok(r) = &d.result
                && !each(Place(d.offset as u64), r)?
            {
                break;
            }
        }
        Ok(())
    }
}

/// Reads frames one by one from a byte reader, exactly as a
/// [`Decoder`](morphogen::stream::Decoder) reads them from a slice (same
/// offsets, lengths and errors): the core [`Reader`] fed the bytes up to
/// each delimiter as one run, holding at most one frame.
#[derive(Debug)]
pub struct FrameReader<R> {
    input: R,
    offset: u64,
    reader: Reader,
}

impl<R: BufRead> FrameReader<R> {
    /// Frames from `input`, whose first byte is at `offset` of the stream.
    pub fn new(input: R, offset: u64) -> FrameReader<R> {
        FrameReader {
            input,
            offset,
            reader: Reader::new(),
        }
    }

    /// The next frame, or `None` at the end of the input.
    ///
    /// # Errors
    /// When the input cannot be read.
    pub fn next_frame(&mut self) -> io::Result<Option<Decoded>> {
        let start = self.offset;
        loop {
            let buf = match self.input.fill_buf() {
                Ok(buf) => buf,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if buf.is_empty() {
                if self.offset == start {
                    return Ok(None);
                }
                self.reader = Reader::new();
                return Ok(Some(Decoded {
                    offset: offset(start)?,
                    len: offset(self.offset - start)?,
                    result: Err(FrameError::Truncated),
                }));
            }
            // The bytes up to the next delimiter, as one run.
            let delimiter = memchr::memchr(0, buf);
            self.reader.take_run(&buf[..delimiter.unwrap_or(buf.len())]);
            let ended = delimiter.and_then(|_| self.reader.push(0));
            let taken = delimiter.map_or(buf.len(), |at| at + 1);
            self.input.consume(taken);
            self.offset += taken as u64;
            if let Some(result) = ended {
                return Ok(Some(Decoded {
                    offset: offset(start)?,
                    len: offset(self.offset - start)?,
                    result,
                }));
            }
        }
    }
}

/// A byte count as `usize` (a stream longer than the address space is an
/// input error).
fn offset(n: u64) -> io::Result<usize> {
    usize::try_from(n).map_err(|_| io::Error::other("stream offset past the address space"))
}

impl<R: BufRead> Iterator for FrameReader<R> {
    type Item = io::Result<Decoded>;

    fn next(&mut self) -> Option<io::Result<Decoded>> {
        self.next_frame().transpose()
    }
}

#[cfg(test)]
mod tests {
    use morphogen::fx::Fx;
    use morphogen::stream::{Decoder, Encoder, Sink};

    use super::*;

    fn stream() -> Vec<u8> {
        let mut encoder = Encoder::new(Vec::new());
        for i in 0..50u32 {
            encoder
                .record(&Record::FrameStart {
                    frame: i,
                    time: Fx::from_int(i as i32),
                })
                .unwrap();
            encoder
                .record(&Record::Segment {
                    a: [Fx::from_bits(i as i32 * 77_777); 3],
                    b: [Fx::MIN, Fx::MAX, Fx::ZERO],
                    width: Fx::HALF,
                    colour: 3,
                })
                .unwrap();
            encoder.record(&Record::FrameEnd { frame: i }).unwrap();
        }
        encoder.into_writer()
    }

    /// Every frame as the reader sees it through a tiny buffer.
    fn read(bytes: &[u8]) -> Vec<Decoded> {
        FrameReader::new(BufReader::with_capacity(7, bytes), 0)
            .map(Result::unwrap)
            .collect()
    }

    #[test]
    fn reads_frames_as_the_decoder_does_even_when_damaged() {
        let clean = stream();
        let mut damaged = clean.clone();
        damaged[40] ^= 0x21;
        damaged[100] = 0;
        // A run of 300 non-zero bytes: longer than any frame.
        damaged.splice(200..200, std::iter::repeat_n(9u8, 300));
        let mut truncated = clean.clone();
        truncated.truncate(clean.len() - 3);
        for bytes in [clean, damaged, truncated, Vec::new(), vec![0, 0, 5]] {
            let want: Vec<Decoded> = Decoder::new(&bytes).collect();
            assert_eq!(read(&bytes), want);
        }
    }

    #[test]
    fn reads_any_bytes_as_the_decoder_does_through_any_buffer() {
        // Bytes overwritten and runs inserted at random; each stream read
        // through buffers that end inside frames, at delimiters, or hold
        // the whole stream.
        let clean = stream();
        let mut rng = morphogen::rng::KeyedRng::new(5, 0);
        let mut random = |n: usize| rng.below(n as u32) as usize;
        for round in 0..300 {
            let mut bytes = clean.clone();
            for _ in 0..random(6) {
                let i = random(bytes.len());
                bytes[i] = if round % 2 == 0 { 0 } else { random(256) as u8 };
            }
            if round % 4 == 0 {
                let (at, byte) = (random(bytes.len()), random(255) as u8 + 1);
                bytes.splice(at..at, std::iter::repeat_n(byte, random(400)));
            }
            bytes.truncate(bytes.len() - random(4));
            let want: Vec<Decoded> = Decoder::new(&bytes).collect();
            for capacity in [1, 7, 64, 1 << 16] {
                let got: Vec<Decoded> =
                    FrameReader::new(BufReader::with_capacity(capacity, &bytes[..]), 0)
                        .map(Result::unwrap)
                        .collect();
                assert_eq!(got, want, "round {round}, buffer {capacity}");
            }
        }
    }

    #[test]
    fn a_file_is_visited_from_any_place_it_handed_out() {
        let bytes = stream();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("stream.bin");
        std::fs::write(&path, &bytes).unwrap();
        let file = StreamFile::new(&path);
        let records: Vec<Record> = Decoder::new(&bytes).map(|d| d.result.unwrap()).collect();
        let mut places = Vec::new();
        let mut seen = Vec::new();
        file.visit(Place::START, |place, r| {
            places.push(place);
            seen.push(r.clone());
            Ok(())
        })
        .unwrap();
        assert_eq!(seen, records);
        let mut tail = Vec::new();
        file.visit_while(places[31], |_, r| {
            tail.push(r.clone());
            Ok(tail.len() < 4)
        })
        .unwrap();
        assert_eq!(tail, records[31..35]);
        let mut from_slice = Vec::new();
        records
            .visit(Place(31), |_, r| {
                from_slice.push(r.clone());
                Ok(())
            })
            .unwrap();
        assert_eq!(from_slice, records[31..]);
    }
}
