//! `morphogen decode`: a stream file as JSON Lines, the same as a run's
//! `records.jsonl` (docs/stream-format.md).

use std::path::PathBuf;

use anyhow::{Result, bail};
use morphogen_stream_text::jsonl;

use crate::stdout::StdoutError;
use crate::{Outcome, atomic};

/// `morphogen decode`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The stream file.
    pub file: PathBuf,
    /// Write to this file instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Writes the records of `args.file` as JSON Lines: the stream file read
/// frame by frame, twice (the format check, then the lines), never whole.
///
/// # Errors
/// An unreadable or empty stream, one of another format version, an
/// output that cannot be written, or corrupt frames (after every line).
pub fn run(args: &Args) -> Result<Outcome> {
    let (file, out) = (args.file.as_path(), args.out.as_deref());
    let stream = crate::records::StreamFile::new(file);
    let start = crate::records::Place::START;
    let unreadable = |e: std::io::Error| {
        anyhow::Error::new(e).context(format!("cannot read {}", file.display()))
    };
    let mut empty = true;
    for d in stream.frames(start)? {
        let d = d.map_err(unreadable)?;
        empty = false;
        if let Ok(morphogen::stream::Record::Header(h)) = &d.result
            && h.version != morphogen::stream::FORMAT_VERSION
        {
            bail!(
                "{}: the stream at byte {} is format version {}; this reader knows version {} (docs/stream-format.md)",
                file.display(),
                d.offset,
                h.version,
                morphogen::stream::FORMAT_VERSION
            );
        }
    }
    if empty {
        bail!("{} holds no frames", file.display());
    }
    let mut corrupt = 0usize;
    // Counts the corrupt frames on their way to `w`.
    let mut lines = |w: &mut dyn std::io::Write| -> Result<(), Written> {
        let mut line = Vec::with_capacity(256);
        for d in stream.frames(start).map_err(Written::Input)? {
            let d = d.map_err(|e| Written::Input(unreadable(e)))?;
            if d.result.as_ref().is_err_and(|e| e.is_corrupt()) {
                corrupt += 1;
            }
            line.clear();
            jsonl::decoded(&mut line, &d);
            line.push(b'\n');
            w.write_all(&line).map_err(Written::Output)?;
        }
        w.flush().map_err(Written::Output)
    };
    match out {
        Some(path) => {
            let mut file = atomic::OutputFile::create(path)?;
            lines(&mut file).map_err(|e| match e {
                Written::Input(e) => e,
                Written::Output(e) => {
                    anyhow::Error::new(e).context(format!("cannot write {}", path.display()))
                }
            })?;
            file.finish()?;
        }
        None => {
            let mut stdout = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
            lines(&mut stdout).map_err(|e| match e {
                Written::Input(e) => e,
                Written::Output(e) => StdoutError(e).into(),
            })?;
        }
    }
    if corrupt > 0 {
        bail!(
            "{corrupt} corrupt or truncated frame(s) in {} (shown as \"kind\":\"error\" lines)",
            file.display()
        );
    }
    Ok(Outcome::Ok)
}

/// Why `decode` stopped writing lines.
enum Written {
    /// The stream file could not be read.
    Input(anyhow::Error),
    /// The output could not be written.
    Output(std::io::Error),
}
