//! Fuzzes mask images (`morphogen_scenario::mask::read`): PBM (P1, P4) or
//! PNG bytes. No input may panic or allocate past libFuzzer's
//! `-malloc_limit_mb`. A mask read has `height × ⌈width/8⌉` bytes with
//! clear padding bits, and a small one survives `mask::to_pbm` and back.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run mask` from the repository root (or
//! `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen::mosaic::Mask;
use morphogen_scenario::mask;

/// Masks up to this many pixels are written back as PBM and re-read.
const ROUND_TRIP_PIXELS: u64 = 1 << 16;

fuzz_target!(|data: &[u8]| {
    let (width, height, bits) = match mask::read(data) {
        Ok(mask) => mask,
        Err(e) => {
            assert!(e.len() < 4096, "error of {} bytes", e.len());
            return;
        }
    };
    let pixels = u64::from(width) * u64::from(height);
    assert!(pixels > 0 && pixels <= mask::MAX_PIXELS, "{width}×{height}");
    let stride = usize::from(width).div_ceil(8);
    assert_eq!(bits.len(), stride * usize::from(height), "{width}×{height}");
    let pad = (stride * 8 - usize::from(width)) as u32;
    for row in bits.chunks(stride) {
        let last = row[stride - 1];
        assert_eq!(
            last & !(0xFFu8 << pad),
            0,
            "padding bits set in {width}×{height}"
        );
    }
    if pixels <= ROUND_TRIP_PIXELS {
        let pbm = mask::to_pbm(&Mask {
            width,
            height,
            bits: &bits,
        });
        assert_eq!(mask::read(pbm.as_bytes()), Ok((width, height, bits)));
    }
});
