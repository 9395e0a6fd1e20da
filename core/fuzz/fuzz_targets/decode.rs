//! Fuzzes the stream decoder: any bytes are split into frames that tile
//! the input (each `Decoded` starts where the last one ended and lies
//! within the input), and every record decoded re-encodes to a frame that
//! decodes to the same record. No input may panic.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run decode` from `core/` (or
//! `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen::stream::{ByteSink, Decoder, Encoder, Sink, SinkError};

/// The bytes an [`Encoder`] wrote.
struct Bytes(Vec<u8>);

impl ByteSink for Bytes {
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), SinkError> {
        self.0.extend_from_slice(bytes);
        Ok(())
    }
}

fuzz_target!(|data: &[u8]| {
    let mut next = 0;
    for frame in Decoder::new(data) {
        assert_eq!(frame.offset, next, "frames must tile the input");
        assert!(frame.len > 0, "an empty frame at {}", frame.offset);
        let end = frame
            .offset
            .checked_add(frame.len)
            .expect("offset + len overflows");
        assert!(
            end <= data.len(),
            "frame {}+{} past the input",
            frame.offset,
            frame.len
        );
        next = end;
        if let Ok(record) = frame.result {
            let mut encoder = Encoder::new(Bytes(Vec::new()));
            encoder
                .record(&record)
                .expect("a decoded record re-encodes");
            let bytes = encoder.into_writer().0;
            let back: Vec<_> = Decoder::new(&bytes).collect();
            assert_eq!(back.len(), 1);
            assert_eq!(back[0].len, bytes.len());
            assert_eq!(back[0].result, Ok(record));
        }
    }
    assert_eq!(next, data.len(), "frames must cover the input");
});
