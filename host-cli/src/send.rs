//! `morphogen send SCENARIO DEST`: a scenario sent to a device, which runs
//! it and streams and draws the result without being reflashed
//! (`morphogen::sent`; docs/stream-format.md, "Sending a scenario").

use std::io::{self, Write};
use std::path::Path;
use std::time::Duration;

use anyhow::{Context, Result, anyhow};
use morphogen::sent::MAX_SENT;

use crate::{Outcome, exec, say, serial};

/// Arguments of `morphogen send`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The scenario: a built-in preset's name or a scenario file. A growth
    /// curve, a horn, an L-system or a bone can be sent; bodies and
    /// mosaics are built into the firmware (MORPHOGEN_SCENARIOS).
    scenario: String,
    /// Where it goes: a serial port (`/dev/ttyUSB0`, `COM3`), a file (the
    /// message, for a test or to send later), or `-` for standard output.
    dest: String,
    /// Change a parameter (as `run --set`); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// The seed (default: the scenario's own).
    #[arg(long)]
    seed: Option<u64>,
    /// The serial port's speed in baud (8N1, no flow control).
    #[arg(long, default_value_t = 115_200)]
    baud: u32,
}

/// How long a write to a serial port may wait.
const PORT_TIMEOUT: Duration = Duration::from_secs(2);

/// Runs `send`.
///
/// # Errors
/// A scenario that does not load or cannot be sent (its model, or a part
/// bigger than the message holds), or a destination that cannot be written.
pub fn run(args: &Args) -> Result<Outcome> {
    let sets = args
        .sets
        .iter()
        .map(|s| exec::parse_set(s))
        .collect::<Result<Vec<_>>>()?;
    let scenario = exec::find(&args.scenario, &sets)?;
    let seed = args.seed.unwrap_or(scenario.seed());
    let sent = morphogen_scenario::firmware::sent(&scenario, seed)
        .map_err(|e| anyhow!("{}: {e}", scenario.name()))?;
    // A zero byte first: it ends any partial frame the device has (line
    // noise, a byte its UART took before the program started).
    let mut message = vec![0; 1 + MAX_SENT + 3];
    let len = 1 + sent
        .encode(&mut message[1..])
        .map_err(|e| anyhow!("{}: {e}", scenario.name()))?;
    write(&args.dest, args.baud, &message[..len])?;
    say!(
        "sent {} (seed {seed}, {len} bytes) to {}",
        scenario.name(),
        args.dest
    )?;
    Ok(Outcome::Ok)
}

/// Writes `bytes` to `dest`: `-`, a serial port (an existing file that is
/// not a regular one), or a file (created or replaced) but not one under
/// `/dev/`, where a missing file is an unplugged or mistyped port.
fn write(dest: &str, baud: u32, bytes: &[u8]) -> Result<()> {
    if dest == "-" {
        let mut out = io::stdout().lock();
        out.write_all(bytes)?;
        return Ok(out.flush()?);
    }
    if serial::is_missing_device(dest) {
        return Err(serial::missing(
            dest,
            "DEST is a serial port, a file, or - for standard output",
        ));
    }
    let path = Path::new(dest);
    let port = path.exists() && !path.is_file() && !path.is_dir();
    if port || (cfg!(windows) && dest.starts_with("COM")) {
        let mut port = serial::open(dest, baud, PORT_TIMEOUT)?;
        port.write_all(bytes)
            .and_then(|()| port.flush())
            .with_context(|| format!("cannot write to serial port {dest}"))?;
        return Ok(());
    }
    // Whole or not at all: a full disk leaves no empty file.
    crate::atomic::OutputFile::write_with(path, |f| f.write_all(bytes))
}
