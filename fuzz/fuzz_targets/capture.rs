//! Fuzzes what `morphogen verify --stream CAPTURE` reads: a device capture
//! split into its streams (`capture::split`), each compared with a fixture
//! (`verify::compare`), and any stream written as JSON Lines
//! (`jsonl::stream`). The parts tile the capture, a part differs from the
//! fixture exactly when its bytes do, and there is one JSON line per
//! frame. No input may panic.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run capture` from the repository root (or
//! `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen::stream::Decoder;
use morphogen_stream_text::{capture, jsonl, verify};

/// A real stream: the fixture of `growth-curve`.
const STREAM: &[u8] = include_bytes!("../../fixtures/growth-curve/stream.bin");
/// Bytes of [`STREAM`] compared with each part: its frames in the first
/// 1 KB (a whole stream would make every input ten times slower).
const PREFIX: usize = 1024;

fuzz_target!(|data: &[u8]| {
    let cut = STREAM[..PREFIX]
        .iter()
        .rposition(|&b| b == 0)
        .map_or(0, |at| at + 1);
    let fixture = &STREAM[..cut];
    let parts = capture::split(data);
    let mut next = 0;
    for (i, part) in parts.iter().enumerate() {
        assert_eq!(part.range.start, next, "parts must tile the capture");
        assert!(part.range.end > part.range.start && part.range.end <= data.len());
        assert!(
            part.header.is_some() || i == 0,
            "only the first part may lack a header"
        );
        next = part.range.end;
        let bytes = &data[part.range.clone()];
        let diff = verify::compare(fixture, bytes);
        assert_eq!(diff.is_none(), bytes == fixture);
        if let Some(diff) = diff {
            assert!(diff.offset <= fixture.len());
            let _ = diff.to_string();
        }
    }
    assert_eq!(next, data.len(), "parts must cover the capture");
    let text = jsonl::stream(data);
    assert_eq!(text.lines().count(), Decoder::new(data).count());
});
