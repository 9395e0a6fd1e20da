//! What `verify` found for one fixture, and its line in a terminal.

use std::path::PathBuf;

use morphogen_scenario::Scenario;
use morphogen_stream_text::verify::{self, Difference, Tally};

use crate::fixture;
use crate::report::{self, Pictures};

/// One fixture checked.
#[derive(Debug, Clone)]
pub struct Case {
    /// The fixture's name.
    pub name: String,
    /// Its folder.
    pub folder: PathBuf,
    /// Seconds spent re-running and comparing it.
    pub seconds: f64,
    /// What was found.
    pub verdict: Verdict,
    /// A note for the reader (a scenario file run with the fixture's seed).
    pub note: Option<String>,
}

/// The new stream of a mismatch, and whether it was left for `bless
/// --accept`.
#[derive(Debug, Clone)]
pub enum Pending {
    /// Written beside the fixture.
    Written(PathBuf),
    /// Not written: CI is set and `--pending` was not given.
    HeldBack,
    /// Could not be written (the reason).
    Failed(String),
}

/// How a stream differs from its fixture.
#[derive(Debug, Clone)]
pub struct Mismatch {
    /// The first differing record.
    pub first: Difference,
    /// Every differing record.
    pub tally: Tally,
    /// The scenario keys whose values are not those the fixture was
    /// blessed with (`key: blessed -> now`).
    pub changed: Vec<String>,
    /// The new stream.
    pub pending: Pending,
    /// The pictures of the first frame that differs, or why there are
    /// none.
    pub pictures: Result<Pictures, String>,
}

impl Mismatch {
    /// How the stream of `run` differs from `blessed`'s (the fixture's
    /// scenario and stream), `first` its first difference: every record
    /// tallied, the changed keys named and the pictures drawn into their
    /// folder (or why not); `pending` is where the new stream went.
    #[must_use]
    pub fn new(
        first: Difference,
        (blessed, expected): (&Scenario, &[u8]),
        (run, actual): (&Scenario, &[u8]),
        pictures: Result<PathBuf, String>,
        pending: Pending,
    ) -> Mismatch {
        let pictures = pictures.and_then(|dir| {
            report::draw((blessed, expected), (run, actual), &dir)
                .map_err(|e| format!("could not be drawn: {e:#}"))
        });
        Mismatch {
            first,
            tally: verify::tally(expected, actual),
            changed: fixture::changed_keys(blessed, run),
            pending,
            pictures,
        }
    }

    /// The first difference, the tally, the changed keys and the
    /// pictures, a line each (the first difference on three).
    #[must_use]
    pub fn text(&self) -> String {
        let pictures = match &self.pictures {
            Ok(p) => p.line(4),
            Err(why) => format!("pictures {why}"),
        };
        let changed = if self.changed.is_empty() {
            String::new()
        } else {
            format!("\n  changed since the bless: {}", self.changed.join("; "))
        };
        format!("{}\n  {}{changed}\n  {pictures}", self.first, self.tally)
    }
}

/// What `verify` found.
#[derive(Debug, Clone)]
pub enum Verdict {
    /// The stream equals the fixture.
    Ok {
        /// Frames streamed.
        frames: u32,
        /// The stream's digest.
        digest: u64,
    },
    /// It differs.
    Mismatch(Box<Mismatch>),
    /// There is no fixture (how to make one).
    Missing(String),
    /// The fixture could not be checked (why).
    Error(String),
}

impl Case {
    /// The verdict's word: `ok`, `mismatch`, `missing` or `error`.
    #[must_use]
    pub fn word(&self) -> &'static str {
        match self.verdict {
            Verdict::Ok { .. } => "ok",
            Verdict::Mismatch(_) => "mismatch",
            Verdict::Missing(_) => "missing",
            Verdict::Error(_) => "error",
        }
    }

    /// What is wrong, in one line (none for ok).
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        match &self.verdict {
            Verdict::Ok { .. } => None,
            Verdict::Mismatch(m) => Some(format!(
                "{}; first in {}, record {}{}",
                m.tally,
                m.first
                    .frame
                    .map_or("the header".to_string(), |f| format!("frame {f}")),
                m.first.record,
                if m.changed.is_empty() {
                    String::new()
                } else {
                    format!("; changed since the bless: {}", m.changed.join("; "))
                }
            )),
            Verdict::Missing(why) | Verdict::Error(why) => Some(why.clone()),
        }
    }

    /// The case as `verify` prints it in a terminal (a line, and for a
    /// mismatch the records and the new stream).
    #[must_use]
    pub fn text(&self) -> String {
        let name = &self.name;
        let note = self
            .note
            .as_ref()
            .map_or(String::new(), |n| format!("\n  note: {n}"));
        match &self.verdict {
            Verdict::Ok { frames, digest } => {
                format!("ok        {name} ({frames} frames, digest {digest:016x}){note}")
            }
            Verdict::Mismatch(m) => {
                let pending = match &m.pending {
                    Pending::Written(path) => format!(
                        "new stream: {} (take it with `morphogen bless --accept {name}`)",
                        path.display()
                    ),
                    Pending::HeldBack => "new stream not written: CI is set (give --pending to \
                                          leave it beside the fixture)"
                        .to_string(),
                    Pending::Failed(e) => {
                        format!("the new stream could not be left beside it: {e}")
                    }
                };
                format!("MISMATCH  {name}: {}\n  {pending}{note}", m.text())
            }
            Verdict::Missing(why) => format!("MISSING   {name}: {why}"),
            Verdict::Error(why) => format!("ERROR     {name}: {why}"),
        }
    }
}

/// How many cases of each verdict.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    /// Streams equal to their fixtures.
    pub ok: usize,
    /// Streams that differ.
    pub mismatch: usize,
    /// Cases without a fixture.
    pub missing: usize,
    /// Fixtures that could not be checked.
    pub error: usize,
}

impl Counts {
    /// The counts of `cases`.
    #[must_use]
    pub fn of(cases: &[Case]) -> Counts {
        let mut counts = Counts::default();
        for case in cases {
            *match case.verdict {
                Verdict::Ok { .. } => &mut counts.ok,
                Verdict::Mismatch(_) => &mut counts.mismatch,
                Verdict::Missing(_) => &mut counts.missing,
                Verdict::Error(_) => &mut counts.error,
            } += 1;
        }
        counts
    }
}

impl std::fmt::Display for Counts {
    /// `verify`'s last line: `1 ok, 1 mismatch, 0 missing` (and `, N not
    /// checked` when any could not be).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ok, {} mismatch, {} missing",
            self.ok, self.mismatch, self.missing
        )?;
        if self.error > 0 {
            write!(f, ", {} not checked", self.error)?;
        }
        Ok(())
    }
}
