//! Serial ports by name, for `send` and `listen`: opening one at a speed,
//! and the error for a port that is not there, naming the ports that are
//! (serialport's `available_ports`).

use std::path::Path;
use std::time::Duration;

use anyhow::{Context, Result, anyhow};
use serialport::SerialPort;

/// Opens the serial port `name` at `baud` (8N1, no flow control), its
/// reads and writes waiting at most `timeout`.
///
/// # Errors
/// The port cannot be opened (busy, no permission, not a serial port).
pub fn open(name: &str, baud: u32, timeout: Duration) -> Result<Box<dyn SerialPort>> {
    serialport::new(name, baud)
        .timeout(timeout)
        .open()
        .with_context(|| format!("cannot open serial port {name}"))
}

/// Whether `name` stands for a device node that is not there (on Unix a
/// path under `/dev/`): an unplugged board, or a mistyped port.
#[must_use]
pub fn is_missing_device(name: &str) -> bool {
    cfg!(unix) && name.starts_with("/dev/") && !Path::new(name).exists()
}

/// The error for the port `name` that is not there; `usage` says what
/// the argument may be. It lists the serial ports this computer has.
#[must_use]
pub fn missing(name: &str, usage: &str) -> anyhow::Error {
    anyhow!("no serial port {name}: {} ({usage})", present())
}

/// The serial ports present, as a clause: "serial ports here: …" or
/// "no serial port is present (is the device plugged in?)".
fn present() -> String {
    let mut names: Vec<String> = serialport::available_ports()
        .unwrap_or_default()
        .into_iter()
        .map(|port| port.port_name)
        .collect();
    names.sort();
    if names.is_empty() {
        "no serial port is present (is the device plugged in?)".to_owned()
    } else {
        format!("serial ports here: {}", names.join(", "))
    }
}
