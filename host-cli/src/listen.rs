//! `morphogen listen SOURCE`: frames decoded live, one byte at a time by
//! the core's [`Reader`], from a serial port, a file or standard input;
//! each stream is checked against its fixture as it completes and drawn
//! as a rig picture (docs/stream-format.md, "Receiving").

use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use morphogen::stream::{FrameError, Header, MAX_FRAME, Reader, Record};
use morphogen_stream_text::verify;

use crate::fixture::{self, Fixture};
use crate::{Outcome, say, serial};

/// Arguments of `morphogen listen`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Where the bytes come from: a serial port (`/dev/ttyUSB0`,
    /// `/dev/pts/3`, `COM3`), a file (a capture, read to its end), or `-`
    /// for standard input.
    source: String,
    /// The serial port's speed in baud (8N1, no flow control).
    #[arg(long, default_value_t = 115_200)]
    baud: u32,
    /// Also draw each stream as a receiving W×H rig shows it (its last
    /// frame that came whole, fitted to the extent the sender sent or else
    /// to the stream's records), into
    /// `OUT/PRESET/rig-WxH.png` (`WxH:grey4`: as a 4-bit grey OLED, into
    /// `rig-WxH-grey4.png`).
    #[arg(long, value_name = "WxH[:grey4]", value_parser = crate::rig::parse_rig)]
    rig: Option<crate::rig::RigSpec>,
    /// The folder of the rig pictures.
    #[arg(long, default_value = "out/listen")]
    out: PathBuf,
    /// The fixtures folder (default: as `verify`).
    #[arg(long)]
    fixtures: Option<PathBuf>,
    /// Stop after this many streams (default: at the end of the source).
    #[arg(long, value_name = "N")]
    streams: Option<u32>,
    /// Exit 1 on any bad frame, even one outside a stream.
    #[arg(long)]
    strict: bool,
}

/// How long a read of a serial port waits before trying again.
const PORT_TIMEOUT: Duration = Duration::from_millis(200);

/// Runs `listen`.
///
/// # Errors
/// A source that cannot be opened or read, a picture that
/// cannot be written, or a source without any stream.
pub fn run(args: &Args) -> Result<Outcome> {
    let rig = args.rig;
    if rig.is_some_and(|r| r.chain.is_some()) {
        anyhow::bail!(
            "--rig …:ws2812: listen draws the rig's picture only; `morphogen run … --rig WxH:ws2812` writes a chain's bytes"
        );
    }
    let fixtures = fixture::locate(args.fixtures.clone(), false)?;
    let (mut source, port) = open(&args.source, args.baud)?;
    eprintln!(
        "listening on {}{}",
        args.source,
        if port {
            format!(" at {} baud", args.baud)
        } else {
            String::new()
        }
    );
    let mut listener = Listener {
        fixtures,
        rig,
        out: args.out.clone(),
        reader: Reader::new(),
        frame: Vec::with_capacity(MAX_FRAME),
        offset: 0,
        stream: None,
        seen: 0,
        bad_outside: 0,
        bad: 0,
        unreported: None,
        failed: 0,
    };
    let mut buf = [0u8; 4096];
    'reading: while args.streams.is_none_or(|n| listener.seen < n) {
        let n = match source.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::Interrupted
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::WouldBlock
                ) =>
            {
                continue;
            }
            // A serial port whose other end hung up (a pty's master closed).
            Err(e) if port && e.kind() == io::ErrorKind::BrokenPipe => break,
            Err(e) => return Err(e).with_context(|| format!("cannot read {}", args.source)),
        };
        for &byte in &buf[..n] {
            listener.byte(byte)?;
            if args.streams.is_some_and(|n| listener.seen >= n) {
                break 'reading;
            }
        }
    }
    listener.end()?;
    say!(
        "{} stream(s), {} bad frame(s) from {}",
        listener.seen,
        listener.bad,
        args.source
    )?;
    if listener.seen == 0 {
        bail!(
            "{}: no stream (no readable header) in {} bytes",
            args.source,
            listener.offset
        );
    }
    Ok(
        if listener.failed > 0 || (args.strict && listener.bad > 0) {
            Outcome::Mismatch
        } else {
            Outcome::Ok
        },
    )
}

/// Opens `source`: `-`, a file, or a serial port at `baud`; says whether
/// it is a port.
fn open(source: &str, baud: u32) -> Result<(Box<dyn Read>, bool)> {
    if source == "-" {
        return Ok((Box::new(io::stdin().lock()), false));
    }
    let path = Path::new(source);
    if path.is_file() {
        let file = std::fs::File::open(path).with_context(|| format!("cannot read {source}"))?;
        return Ok((Box::new(io::BufReader::new(file)), false));
    }
    let usage = "SOURCE is a serial port, a file, or - for standard input";
    if serial::is_missing_device(source) {
        return Err(serial::missing(source, usage));
    }
    if cfg!(unix) && !path.exists() {
        bail!("no file or serial port {source} ({usage})");
    }
    Ok((serial::open(source, baud, PORT_TIMEOUT)?, true))
}

/// The state of a live decode.
struct Listener {
    fixtures: PathBuf,
    rig: Option<crate::rig::RigSpec>,
    out: PathBuf,
    reader: Reader,
    /// The frame in progress (its first [`MAX_FRAME`] bytes).
    frame: Vec<u8>,
    /// Bytes read so far.
    offset: u64,
    stream: Option<Stream>,
    /// Streams completed.
    seen: u32,
    /// Bad frames before the first header.
    bad_outside: u32,
    /// Bad frames in all.
    bad: u32,
    /// Bad frames since the last one reported (a run of them is reported
    /// by its first and its count, not a line each), and the source byte
    /// the last of them started at.
    unreported: Option<(u32, u64)>,
    /// Streams that differ from their fixture or have none.
    failed: u32,
}

/// A stream being received: from its header frame to the next one.
struct Stream {
    header: Header,
    /// The fixture of its preset, or why there is none.
    fixture: Result<Fixture>,
    /// Its bytes so far, its header frame first, without the frames of
    /// link records ([`Record::Extent`]: not part of the stream).
    bytes: Vec<u8>,
    /// What its frames after the header decode to, bad ones included
    /// (for the rig).
    frames: Vec<Result<Record, FrameError>>,
    bad: u32,
    bar: ProgressBar,
}

impl Listener {
    fn byte(&mut self, byte: u8) -> Result<()> {
        let len = self.reader.pending() + 1;
        let at = self.offset;
        self.offset += 1;
        if self.frame.len() < MAX_FRAME {
            self.frame.push(byte);
        }
        if let Some(stream) = &mut self.stream {
            stream.bytes.push(byte);
        }
        let Some(result) = self.reader.push(byte) else {
            return Ok(());
        };
        let frame_start = at + 1 - len as u64;
        if result.is_ok() {
            self.report_bad_run();
        }
        match result {
            Ok(Record::Header(header)) => {
                if let Some(mut stream) = self.stream.take() {
                    let end = stream.bytes.len().saturating_sub(len);
                    stream.bytes.truncate(end);
                    self.complete(stream)?;
                }
                self.start(header);
            }
            Ok(record) => {
                if let Some(stream) = &mut self.stream {
                    if let Record::Extent { .. } = record {
                        let end = stream.bytes.len().saturating_sub(len);
                        stream.bytes.truncate(end);
                    }
                    if self.rig.is_some() {
                        stream.frames.push(Ok(record));
                    }
                }
            }
            Err(e) if e.is_corrupt() => self.bad_frame(e, frame_start, len),
            Err(_) => {}
        }
        self.frame.clear();
        self.progress()
    }

    /// Counts the corrupt frame `e` (at `frame_start` of the source,
    /// `len` bytes) against the stream being read, or against the bytes
    /// before any header; only the first of a run of them is named.
    fn bad_frame(&mut self, e: FrameError, frame_start: u64, len: usize) {
        self.bad += 1;
        // The first of a run of bad frames is reported here, the
        // rest by their count once the run ends.
        let quiet = match &mut self.unreported {
            Some((count, last)) => {
                *count += 1;
                *last = frame_start;
                true
            }
            None => {
                self.unreported = Some((0, frame_start));
                false
            }
        };
        match &mut self.stream {
            Some(stream) => {
                stream.bad += 1;
                if self.rig.is_some() {
                    stream.frames.push(Err(e));
                }
                if !quiet {
                    let line = format!(
                        "  {}: bad frame at byte {} of the stream ({frame_start} of the source), skipped: {e}",
                        stream.header.preset,
                        stream.bytes.len() - len
                    );
                    stream.bar.suspend(|| eprintln!("{line}"));
                }
            }
            None => {
                self.bad_outside += 1;
                if !quiet {
                    eprintln!("  bad frame at byte {frame_start}, before any header: {e}");
                }
            }
        }
    }

    /// The progress bar of the stream being read, and its end once it has
    /// its fixture's size (or a run's stream cap where it has none).
    fn progress(&mut self) -> Result<()> {
        if let Some(stream) = &self.stream {
            stream.bar.set_position(stream.bytes.len() as u64);
            stream.bar.set_message(format!(
                "{} frames, {} bad",
                stream.frames.len() + 1,
                stream.bad
            ));
            // Complete at its fixture's size, or at a run's stream cap
            // where it has none: its memory is bounded either way.
            let size = match &stream.fixture {
                Ok(fixture) => fixture.summary.bytes,
                Err(_) => u64::from(crate::exec::DEFAULT_MAX_STREAM_MB) << 20,
            };
            if stream.bytes.len() as u64 >= size
                && let Some(stream) = self.stream.take()
            {
                self.complete(stream)?;
            }
        }
        Ok(())
    }

    /// A new stream, starting with the header frame just read.
    fn start(&mut self, header: Header) {
        let fixture = fixture::load(&self.fixtures, &header.preset);
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{prefix} [{bar:30}] {bytes}/{total_bytes} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        bar.set_prefix(header.preset.to_string());
        if let Ok(fixture) = &fixture {
            bar.set_length(fixture.summary.bytes);
        }
        eprintln!(
            "stream {}: {} seed {}",
            self.seen + 1,
            header.preset.escape_debug(),
            header.seed
        );
        self.stream = Some(Stream {
            header,
            fixture,
            bytes: self.frame.clone(),
            frames: Vec::new(),
            bad: 0,
            bar,
        });
    }

    /// Checks a complete stream against its fixture and draws its rig.
    fn complete(&mut self, stream: Stream) -> Result<()> {
        stream.bar.finish_and_clear();
        self.seen += 1;
        let name = stream.header.preset.as_str();
        let bad = match stream.bad {
            0 => String::new(),
            n => format!(", {n} bad frame(s) skipped"),
        };
        match &stream.fixture {
            Err(e) => {
                self.failed += 1;
                say!("MISSING   {}: {e:#}", name.escape_debug())?;
            }
            Ok(fixture) => match verify::compare(&fixture.stream, &stream.bytes) {
                None => say!(
                    "ok        {name} ({} bytes, digest {:016x}{bad})",
                    stream.bytes.len(),
                    morphogen::stream::StreamDigest::of(&stream.bytes)
                )?,
                Some(diff) => {
                    self.failed += 1;
                    say!(
                        "MISMATCH  {name} (digest {:016x}, fixture {}{bad}): {diff}",
                        morphogen::stream::StreamDigest::of(&stream.bytes),
                        fixture.summary.stream_digest
                    )?;
                }
            },
        }
        if let Some(rig) = self.rig {
            if morphogen_scenario::check::name(name).is_err() {
                say!(
                    "  no rig picture: '{}' is not a preset name",
                    name.escape_debug()
                )?;
                return Ok(());
            }
            let dir = self.out.join(name);
            std::fs::create_dir_all(&dir)
                .with_context(|| format!("cannot create output folder {}", dir.display()))?;
            let picture = crate::rig::render_received(&stream.header, &stream.frames, rig)?;
            crate::written::say_wrote(&crate::rig::save_rig_png(&picture, rig, &dir)?)?;
        }
        Ok(())
    }

    /// Reports how many bad frames followed the last one reported.
    fn report_bad_run(&mut self) {
        if let Some((count, last)) = self.unreported.take()
            && count > 0
        {
            let line = format!(
                "  {count} more bad frame(s) in a row after it, the last at byte {last} of the source, skipped"
            );
            match &self.stream {
                Some(stream) => stream.bar.suspend(|| eprintln!("{line}")),
                None => eprintln!("{line}"),
            }
        }
    }

    /// The source ended: a frame in progress is truncated, a stream in
    /// progress complete as it is.
    fn end(&mut self) -> Result<()> {
        self.report_bad_run();
        if self.reader.pending() > 0 {
            self.bad += 1;
            match &mut self.stream {
                Some(stream) => stream.bad += 1,
                None => self.bad_outside += 1,
            }
            eprintln!(
                "  truncated frame at byte {}: the source ends inside it",
                self.offset - self.reader.pending() as u64
            );
        }
        if let Some(stream) = self.stream.take() {
            self.complete(stream)?;
        }
        if self.bad_outside > 0 {
            eprintln!(
                "{} bad frame(s) outside any stream (bytes before the first header)",
                self.bad_outside
            );
        }
        Ok(())
    }
}
