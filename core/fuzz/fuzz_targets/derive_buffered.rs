//! Fuzzes the buffered derivation (the path context-sensitive grammars
//! take): any UTF-8 input is parsed, derived in two module buffers of
//! [`BUFFER_MODULES`] and drawn, bounded. No input may panic or hang; a
//! full buffer is the `BUFFER_MODULES` capacity error. For a context-free
//! grammar the streaming derivation must emit the same records (the two
//! agree module for module, `core/src/lsys/mod.rs`).
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run derive_buffered` from `core/` (or
//! `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

mod refusal;

use libfuzzer_sys::fuzz_target;
use morphogen::Error;
use morphogen::lsys::{Buffered, LSystem, LsysError, Module, Neighbours};
use morphogen::sim::{Simulation, Start};
use morphogen::stream::{Record, Sink, SinkError};

/// Modules per buffer: a few thousand, so that capacity errors are reached.
const BUFFER_MODULES: usize = 4096;
/// Records drawn per input at most.
const RECORDS: usize = 5000;
/// Simulation steps per input at most.
const STEPS: usize = 64;

/// Keeps a bounded number of records.
struct Budget(Vec<Record>);

impl Sink for Budget {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        if self.0.len() == RECORDS {
            return Err(SinkError::Full { capacity: 0 });
        }
        self.0.push(record.clone());
        Ok(())
    }
}

/// How a bounded run ended.
#[derive(Debug, PartialEq)]
enum End {
    /// Finished, or out of steps.
    Stopped,
    /// A step failed.
    Failed(Error),
}

fn drive(sim: &mut dyn Simulation) -> (Vec<Record>, End) {
    let mut sink = Budget(Vec::new());
    for _ in 0..STEPS {
        match sim.step(&mut sink) {
            Ok(p) if !p.finished() => {}
            Ok(_) => return (sink.0, End::Stopped),
            Err(e) => return (sink.0, End::Failed(e)),
        }
    }
    (sink.0, End::Stopped)
}

fn is_capacity(end: &End) -> bool {
    matches!(
        end,
        End::Failed(Error::Capacity { .. } | Error::Lsys(LsysError::Capacity { .. }))
    )
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = core::str::from_utf8(data) else {
        return;
    };
    let mut a = vec![Module::default(); BUFFER_MODULES];
    let mut b = vec![Module::default(); BUFFER_MODULES];
    let mut links = vec![Neighbours::default(); BUFFER_MODULES];
    let mut buffered = Box::new(LSystem::<_>::with_derivation(Buffered::new(
        &mut a, &mut b, &mut links,
    )));
    if let Err(e) = buffered.start(text, 1) {
        refusal::assert_located(text, &e);
        return;
    }
    let (records, end) = drive(buffered.as_mut());
    if let End::Failed(Error::Lsys(LsysError::Capacity {
        limit: "BUFFER_MODULES",
        capacity,
    })) = end
    {
        assert_eq!(capacity as usize, BUFFER_MODULES);
    }
    assert!(
        buffered.derivation().peak_modules() <= 2 * BUFFER_MODULES,
        "peak {} modules in two buffers of {BUFFER_MODULES}",
        buffered.derivation().peak_modules()
    );
    if buffered.grammar().needs_buffer() {
        return;
    }
    let mut streaming = Box::new(LSystem::new());
    assert_eq!(
        streaming.start(text, 1),
        Ok(()),
        "the buffered simulation parsed it"
    );
    let (streamed, streamed_end) = drive(streaming.as_mut());
    if is_capacity(&end) || is_capacity(&streamed_end) {
        // One derivation ran out of room: they agree up to there.
        let n = records.len().min(streamed.len());
        assert!(
            records[..n] == streamed[..n],
            "streams differ before a capacity error"
        );
    } else {
        assert!(records == streamed, "buffered and streaming records differ");
        assert_eq!(end, streamed_end);
    }
});
