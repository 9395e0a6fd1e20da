//! `morphogen review`: the pending streams `verify` left, one fixture at a
//! time at a terminal — what differs, the changed keys and the pictures —
//! each then accepted (blessed), rejected (its pending stream removed) or
//! skipped. `bless --accept` does the same without asking, for scripts.

use std::io::{BufRead, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use morphogen_stream_text::verify;

use crate::verdict::{Mismatch, Pending};
use crate::{Outcome, bless, fixture, report, say};

/// `morphogen review`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Presets or scenario files whose pending streams to review.
    pub targets: Vec<String>,
    /// The fixtures folder (default: $MORPHOGEN_FIXTURES, else
    /// `fixtures/` in this folder or the nearest parent that has one).
    #[arg(long)]
    pub fixtures: Option<PathBuf>,
}

/// What to do with one pending stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Answer {
    /// Bless it.
    Accept,
    /// Remove it, and its scenario and pictures.
    Reject,
    /// Leave it.
    Skip,
    /// Bless it and every one after it.
    AcceptAll,
    /// Leave it and every one after it.
    Quit,
}

/// The question asked of each pending stream.
pub const PROMPT: &str = "accept, reject, skip, accept all, quit? [a/r/s/A/q] ";

impl Answer {
    /// The answer a line of input gives (none: ask again).
    fn parse(line: &str) -> Option<Answer> {
        match line.trim() {
            "a" | "accept" => Some(Answer::Accept),
            "r" | "reject" => Some(Answer::Reject),
            "s" | "skip" => Some(Answer::Skip),
            "A" | "all" | "accept all" => Some(Answer::AcceptAll),
            "q" | "quit" => Some(Answer::Quit),
            _ => None,
        }
    }
}

/// The pending streams of `targets` (none: all of them) in `fixtures`,
/// shown and decided one at a time on standard input, which must be a
/// terminal.
///
/// # Errors
/// Standard input not a terminal, a target that is not a fixture, or a
/// fixture or pending stream that cannot be read, blessed or removed.
pub fn run(targets: &[String], fixtures: &Path) -> Result<Outcome> {
    let stdin = std::io::stdin();
    if !stdin.is_terminal() {
        bail!(
            "review asks at a terminal, and standard input is not one (in a script, take the pending streams with `morphogen bless --accept [NAME...]`)"
        );
    }
    let names: Vec<String> = if targets.is_empty() {
        fixture::pending_names(fixtures)?
    } else {
        let pending = fixture::pending_names(fixtures)?;
        let mut names = Vec::new();
        for target in targets {
            let name = fixture::target(target, fixtures)?.name().to_string();
            if !pending.contains(&name) {
                bail!("{name} has no pending stream in {}", fixtures.display());
            }
            names.push(name);
        }
        names
    };
    if names.is_empty() {
        say!(
            "nothing pending in {} (`morphogen verify` leaves a new stream beside each fixture it does not match)",
            fixtures.display()
        )?;
        return Ok(Outcome::Ok);
    }
    let mut input = stdin.lock();
    let mut all = false;
    let (mut accepted, mut rejected) = (0, 0);
    for (i, name) in names.iter().enumerate() {
        show(fixtures, name, (i + 1, names.len()))?;
        let answer = if all {
            Answer::Accept
        } else {
            ask(&mut input)?
        };
        match answer {
            Answer::Accept | Answer::AcceptAll => {
                all |= answer == Answer::AcceptAll;
                bless::accept_one(fixtures, name)?;
                accepted += 1;
            }
            Answer::Reject => {
                fixture::reject_pending(fixtures, name)?;
                say!("rejected  {name}: its pending stream is removed")?;
                rejected += 1;
            }
            Answer::Skip => say!("skipped   {name}")?,
            Answer::Quit => break,
        }
    }
    say!(
        "{accepted} accepted, {rejected} rejected, {} left pending",
        fixture::pending_names(fixtures)?.len()
    )?;
    Ok(Outcome::Ok)
}

/// Prints what differs in `name`'s pending stream, the `n`-th of `of`,
/// and draws its pictures beside it.
fn show(fixtures: &Path, name: &str, (n, of): (usize, usize)) -> Result<()> {
    let blessed = fixture::scenario(fixtures, name)?;
    let expected = fixture::load(fixtures, name)?.stream;
    let scenario = fixture::pending_scenario(fixtures, name)?;
    let actual = fixture::read_pending(fixtures, name)?.stream;
    let path = fixture::dir(fixtures, name).join(fixture::PENDING_FILE);
    let Some(first) = verify::compare(&expected, &actual) else {
        say!("[{n}/{of}] {name}: the pending stream equals the fixture")?;
        return Ok(());
    };
    let mismatch = Mismatch::new(
        first,
        (&blessed, &expected),
        (&scenario, &actual),
        Ok(fixture::dir(fixtures, name).join(report::REPORT_DIR)),
        Pending::Written(path.clone()),
    );
    say!("[{n}/{of}] {name}: {}", mismatch.text())?;
    say!("  new stream: {}", path.display())?;
    Ok(())
}

/// Asks until a line gives an answer; the end of input quits.
fn ask(input: &mut impl BufRead) -> Result<Answer> {
    loop {
        let mut out = std::io::stdout().lock();
        out.write_all(PROMPT.as_bytes())
            .and_then(|()| out.flush())
            .context("cannot write the question")?;
        drop(out);
        let mut line = String::new();
        if input
            .read_line(&mut line)
            .context("cannot read the answer")?
            == 0
        {
            say!("")?;
            return Ok(Answer::Quit);
        }
        if let Some(answer) = Answer::parse(&line) {
            return Ok(answer);
        }
        say!("'{}' is not an answer", line.trim().escape_debug())?;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_read_as_letters_or_words() {
        assert_eq!(Answer::parse("a\n"), Some(Answer::Accept));
        assert_eq!(Answer::parse("A"), Some(Answer::AcceptAll));
        assert_eq!(Answer::parse(" reject "), Some(Answer::Reject));
        assert_eq!(Answer::parse("s"), Some(Answer::Skip));
        assert_eq!(Answer::parse(""), None);
        assert_eq!(Answer::parse("q"), Some(Answer::Quit));
        assert_eq!(Answer::parse("yes"), None);
    }
}
