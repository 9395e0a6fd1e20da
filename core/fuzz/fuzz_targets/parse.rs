//! Fuzzes the L-system grammar parser, then derives and draws whatever
//! parses (bounded): no input may panic, hang or give an unlocated error.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run parse -- -max_total_time=600` from
//! `core/` (or `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

mod refusal;

use libfuzzer_sys::fuzz_target;
use morphogen::lsys::LSystem;
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};

/// Accepts a bounded number of records.
struct Budget(u32);

impl Sink for Budget {
    fn record(&mut self, _: &Record) -> Result<(), SinkError> {
        self.0 = self
            .0
            .checked_sub(1)
            .ok_or(SinkError::Full { capacity: 0 })?;
        Ok(())
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = core::str::from_utf8(data) else {
        return;
    };
    let mut sim = Box::new(LSystem::new());
    if let Err(e) = sim.start(text, 1) {
        refusal::assert_located(text, &e);
        return;
    }
    let mut sink = Budget(5000);
    for _ in 0..64 {
        match sim.step(&mut sink) {
            Ok(p) if !p.finished() => {}
            _ => break,
        }
    }
});
