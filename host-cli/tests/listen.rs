//! `morphogen listen` on a file, on a damaged file and on a live
//! pseudo-terminal.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use morphogen::rig::Bounds;
use morphogen::stream::{Decoder, Encoder, Record, Sink, StreamDigest};
use morphogen_cli::{exec, rig};

/// The fixtures of the workspace.
fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// A preset's stream, made by the same code as `morphogen run`.
fn stream(preset: &str) -> Vec<u8> {
    let scenario = exec::find(preset, &[]).unwrap();
    exec::run(&scenario, scenario.seed(), false).unwrap().stream
}

fn listen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .arg("listen")
        .args(args)
        .args(["--fixtures", fixtures().to_str().unwrap()])
        .output()
        .unwrap()
}

#[test]
fn a_file_of_two_streams_is_verified_and_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let capture = dir.path().join("capture.bin");
    let mut bytes = stream("growth-curve");
    bytes.extend(stream("long-bone"));
    std::fs::write(&capture, &bytes).unwrap();
    let out = dir.path().join("out");
    let o = listen(&[
        capture.to_str().unwrap(),
        "--rig",
        "32x16",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("ok        growth-curve (10304 bytes, digest 3796d9cd8193fce1)"));
    assert!(stdout.contains("ok        long-bone"), "{stdout}");
    assert!(stdout.contains("2 stream(s), 0 bad frame(s)"), "{stdout}");
    for name in ["growth-curve", "long-bone"] {
        let png = out.join(name).join("rig-32x16.png");
        assert!(std::fs::metadata(&png).unwrap().len() > 100, "{name}");
    }
}

#[test]
fn a_flipped_bit_costs_its_frame_and_fails_the_check() {
    let dir = tempfile::tempdir().unwrap();
    let capture = dir.path().join("capture.bin");
    let mut bytes = stream("growth-curve");
    bytes[5000] ^= 0x10;
    bytes.extend(stream("long-bone"));
    std::fs::write(&capture, &bytes).unwrap();
    let o = listen(&[capture.to_str().unwrap()]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("growth-curve: bad frame at byte 4989 of the stream (4989 of the source), skipped: CRC mismatch"),
        "{stderr}"
    );
    // Only that record is lost: the check names it, and the next stream
    // is whole.
    assert!(
        stdout.contains("MISMATCH  growth-curve (digest e7751bc4831d9828, fixture 3796d9cd8193fce1, 1 bad frame(s) skipped): first difference in frame 0, record 359 (byte 4989)"),
        "{stdout}"
    );
    assert!(stdout.contains("ok        long-bone"), "{stdout}");
    assert!(stdout.contains("2 stream(s), 1 bad frame(s)"), "{stdout}");
}

#[test]
fn a_run_of_bad_frames_is_reported_once_with_its_count() {
    // Line noise: a megabyte of zero bytes (each ends an empty frame), then
    // a stream, then garbage inside a second copy of it.
    let dir = tempfile::tempdir().unwrap();
    let capture = dir.path().join("noise.bin");
    let mut bytes = vec![0u8; 1 << 20];
    bytes.extend(stream("growth-curve"));
    let mut damaged = stream("growth-curve");
    damaged[3000..4000].fill(0x55);
    bytes.extend(damaged);
    std::fs::write(&capture, &bytes).unwrap();
    let o = listen(&[capture.to_str().unwrap()]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("ok        growth-curve"), "{stdout}");
    assert!(
        stderr.lines().count() < 12,
        "a line per bad frame: {} lines",
        stderr.lines().count()
    );
    assert!(
        stderr.contains("more bad frame(s) in a row after it"),
        "{stderr}"
    );
}

/// `bytes` with the extent a firmware sends after each header: the
/// bounds of everything its stream draws.
fn with_extent(bytes: &[u8]) -> Vec<u8> {
    let records: Vec<Record> = Decoder::new(bytes).map(|d| d.result.unwrap()).collect();
    let mut bounds = Bounds::new();
    records.iter().for_each(|r| bounds.include(r));
    let mut sent = Encoder::new(Vec::new());
    sent.record(&records[0]).unwrap();
    sent.link(&bounds.to_record()).unwrap();
    for r in &records[1..] {
        sent.record(r).unwrap();
    }
    assert_eq!(sent.digest(), StreamDigest::of(bytes));
    sent.into_writer()
}

#[test]
fn an_extent_is_left_out_of_the_check_and_fits_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let plain = stream("long-bone");
    let sent = with_extent(&plain);
    assert!(sent.len() > plain.len());
    let mut pictures = Vec::new();
    for (name, bytes) in [("plain", &plain), ("sent", &sent)] {
        let capture = dir.path().join(format!("{name}.bin"));
        std::fs::write(&capture, bytes).unwrap();
        let out = dir.path().join(name);
        let o = listen(&[
            capture.to_str().unwrap(),
            "--rig",
            "48x32:grey4",
            "--out",
            out.to_str().unwrap(),
        ]);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{stdout}");
        assert!(
            stdout.contains(&format!("ok        long-bone ({} bytes", plain.len())),
            "{stdout}"
        );
        pictures.push(std::fs::read(out.join("long-bone/rig-48x32-grey4.png")).unwrap());
    }
    // Both as `run --rig` draws the stream.
    let spec = rig::parse_rig("48x32:grey4").unwrap();
    let records: Vec<Record> = Decoder::new(&plain).map(|d| d.result.unwrap()).collect();
    let run = rig::render_rig(&records, spec, None).unwrap();
    let expected = dir.path().join("run");
    std::fs::create_dir_all(&expected).unwrap();
    let [png, _] = rig::save_rig_png(&run, spec, &expected).unwrap();
    let expected = std::fs::read(png).unwrap();
    assert!(pictures.iter().all(|p| *p == expected));
}

#[test]
fn a_missing_port_is_named() {
    let o = listen(&["/dev/no-such-port"]);
    assert_eq!(o.status.code(), Some(2));
    // Between the two: the ports this machine has, or that it has none.
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with("error: no serial port /dev/no-such-port: "),
        "{stderr}"
    );
    assert!(
        stderr.ends_with(" (SOURCE is a serial port, a file, or - for standard input)\n"),
        "{stderr}"
    );
    // Elsewhere a missing path is most likely a file.
    let o = listen(&["no-such-capture.bin"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "error: no file or serial port no-such-capture.bin (SOURCE is a serial port, a file, or - for standard input)\n"
    );
}

#[test]
fn a_live_stream_through_a_pseudo_terminal_is_verified() {
    let pty = nix::pty::openpty(None, None).unwrap();
    let port = nix::unistd::ttyname(&pty.slave).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(["listen", port.to_str().unwrap(), "--streams", "1"])
        .args(["--fixtures", fixtures().to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The port is ours once `listen` says so (opening it flushes what
    // came before).
    let (said, lines) = mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            if said.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    // Opening a port takes no time: a minute without a word is a hang.
    let first = lines
        .recv_timeout(Duration::from_secs(60))
        .expect("listen said nothing in 60 s, or ended without a word");
    assert_eq!(
        first,
        format!("listening on {} at 115200 baud", port.display())
    );
    let mut master = std::fs::File::from(pty.master);
    let bytes = stream("growth-curve");
    let total = bytes.len();
    let written = Arc::new(AtomicUsize::new(0));
    let writer = std::thread::spawn({
        let written = Arc::clone(&written);
        move || {
            // A device's pace: the stream in pieces.
            bytes.chunks(512).try_for_each(|piece| {
                master.write_all(piece)?;
                written.fetch_add(piece.len(), Ordering::Relaxed);
                Ok::<_, std::io::Error>(())
            })
        }
    });
    // listen takes as it verifies, however slowly: it fails only when it
    // has taken no byte for a minute, or has not ended a minute after the
    // last.
    let (mut taken, mut since) = (0, Instant::now());
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        let now = written.load(Ordering::Relaxed);
        if now != taken {
            (taken, since) = (now, Instant::now());
        }
        assert!(
            since.elapsed() < Duration::from_secs(60),
            "listen went a minute without taking a byte or ending ({taken} of {total} bytes written)"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    // Closing our end of the port ends a write still waiting.
    drop(pty.slave);
    writer.join().unwrap().unwrap();
    let mut stdout = String::new();
    std::io::Read::read_to_string(&mut child.stdout.take().unwrap(), &mut stdout).unwrap();
    assert!(status.success(), "{stdout}");
    assert!(
        stdout.starts_with("ok        growth-curve (10304 bytes, digest 3796d9cd8193fce1)\n"),
        "{stdout}"
    );
    assert!(stdout.contains("1 stream(s), 0 bad frame(s)"), "{stdout}");
}
