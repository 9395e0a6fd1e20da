//! Fuzzes the stream decoder: any bytes are split into frames that tile
//! the input (each `Decoded` starts where the last one ended and lies
//! within the input), every record decoded re-encodes to a frame that
//! decodes to the same record, and a `Reader` fed the bytes one at a time
//! gives the same frames. No input may panic.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run decode` from `core/` (or
//! `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen::stream::{Decoder, Encoder, FrameError, Reader, Sink};

fuzz_target!(|data: &[u8]| {
    let mut reader = Reader::new();
    let live: Vec<_> = data.iter().filter_map(|&b| reader.push(b)).collect();
    let mut whole: Vec<_> = Decoder::new(data).map(|d| d.result).collect();
    if whole.last() == Some(&Err(FrameError::Truncated)) {
        whole.pop();
        assert!(reader.pending() > 0, "a truncated frame is pending");
    } else {
        assert_eq!(reader.pending(), 0);
    }
    assert_eq!(live, whole, "the reader and the decoder differ");

    let mut next = 0;
    for frame in Decoder::new(data) {
        assert_eq!(frame.offset, next, "frames must tile the input");
        assert!(frame.len > 0, "an empty frame at {}", frame.offset);
        // Saturating: a sum past `usize::MAX` is past the input too.
        let end = frame.offset.saturating_add(frame.len);
        assert!(
            end <= data.len(),
            "frame {}+{} past the input",
            frame.offset,
            frame.len
        );
        next = end;
        if let Ok(record) = frame.result {
            let mut encoder = Encoder::new(Vec::new());
            assert_eq!(
                encoder.record(&record),
                Ok(()),
                "a decoded record re-encodes"
            );
            let bytes = encoder.into_writer();
            let back: Vec<_> = Decoder::new(&bytes).collect();
            assert_eq!(back.len(), 1);
            assert_eq!(back[0].len, bytes.len());
            assert_eq!(back[0].result, Ok(record));
        }
    }
    assert_eq!(next, data.len(), "frames must cover the input");
});
