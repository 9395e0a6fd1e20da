//! Running a scenario from Python: on a thread of its own with the
//! interpreter released, so other Python threads go on, while the calling
//! thread checks for signals every [`SIGNAL_CHECK`]; a Ctrl-C stops the run
//! at its next record and raises `KeyboardInterrupt`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use morphogen::stream::{Encoder, Record, Sink, SinkError};
use pyo3::exceptions::{PyMemoryError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::scenario::Scenario;

/// How often the calling thread looks for a pending signal (Ctrl-C).
const SIGNAL_CHECK: Duration = Duration::from_millis(50);

/// Runs `scenario` with `seed` (default: its own) into memory; returns the
/// stream's bytes, its CRC-64/XZ digest and its number of frames. A stream
/// past `max_stream_mb` MiB is stopped.
#[pyfunction]
#[pyo3(signature = (scenario, seed = None, max_stream_mb = morphogen_cli::exec::DEFAULT_MAX_STREAM_MB))]
pub fn run<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    seed: Option<u64>,
    max_stream_mb: u32,
) -> PyResult<(Bound<'py, PyBytes>, u64, u32)> {
    let scenario = &scenario.inner;
    let seed = seed.unwrap_or(scenario.seed());
    let limit = u64::from(max_stream_mb) << 20;
    let stop = AtomicBool::new(false);
    let mut interrupted = None;
    let ran = py.detach(|| {
        let (done, finished) = mpsc::channel();
        std::thread::scope(|threads| {
            let worker = threads.spawn(|| {
                let ran = stream(scenario, seed, limit, &stop);
                // The receiver waits until the scope ends.
                let _ = done.send(());
                ran
            });
            while let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(SIGNAL_CHECK) {
                if interrupted.is_none()
                    && let Err(e) = Python::attach(|py| py.check_signals())
                {
                    interrupted = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
            worker.join()
        })
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    let name = scenario.name();
    match ran {
        Ok(Ok(Streamed::Done(bytes, digest, frames))) => {
            Ok((PyBytes::new(py, &bytes), digest, frames))
        }
        Ok(Ok(Streamed::PastCap)) => Err(PyMemoryError::new_err(format!(
            "{name}: the stream passed {max_stream_mb} MiB and was stopped (raise the cap with max_stream_mb)"
        ))),
        Ok(Err(e)) => Err(PyRuntimeError::new_err(format!("{name}: {e}"))),
        Err(_) => Err(PyRuntimeError::new_err(format!(
            "{name}: the run stopped unexpectedly"
        ))),
    }
}

/// How a run into memory ended, when the core raised no error.
enum Streamed {
    /// The stream, its digest and its frames.
    Done(Vec<u8>, u64, u32),
    /// Stopped at the cap on its size.
    PastCap,
}

/// Runs `scenario` into memory on a worker of rayon's pool (a mosaic's
/// relaxation goes parallel from there without waking a worker for each
/// step), stopping at the next record once `stop` is set.
fn stream(
    scenario: &morphogen_scenario::Scenario,
    seed: u64,
    limit: u64,
    stop: &AtomicBool,
) -> Result<Streamed, morphogen::Error> {
    let mut encoder = Encoder::new(Vec::new());
    let mut sink = Stoppable {
        encoder: &mut encoder,
        limit,
        stop,
        past_cap: false,
    };
    let ran = scenario.with_preset(|preset| {
        rayon::scope(|_| morphogen_scenario::run::run(preset, seed, &mut sink, &mut |_| {}))
    });
    if sink.past_cap {
        return Ok(Streamed::PastCap);
    }
    ran?;
    let (digest, frames) = (encoder.digest(), encoder.frames());
    Ok(Streamed::Done(encoder.into_writer(), digest, frames))
}

/// An encoder into memory that refuses records once `stop` is set or its
/// stream has passed `limit` bytes.
struct Stoppable<'a> {
    encoder: &'a mut Encoder<Vec<u8>>,
    limit: u64,
    stop: &'a AtomicBool,
    past_cap: bool,
}

impl Sink for Stoppable<'_> {
    fn record(&mut self, record: &Record) -> Result<(), SinkError> {
        if self.stop.load(Ordering::Relaxed) {
            return Err(SinkError::Write);
        }
        if self.encoder.bytes() > self.limit {
            self.past_cap = true;
            return Err(SinkError::Write);
        }
        self.encoder.record(record)
    }
}
