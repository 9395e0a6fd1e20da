//! What `verify` tells CI systems: a JUnit XML report (`--junit FILE`, what
//! GitLab, Jenkins, Buildkite and GitHub's test reporters read), JSON lines
//! (`--format json`), and on GitHub Actions an `::error` annotation per
//! fixture that fails and a table in the job summary.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};

use crate::verdict::{Case, Counts, Pending, Verdict};

/// Whether this runs under CI: `CI` set to anything but empty, `0` or
/// `false` (as GitHub Actions, GitLab CI, Buildkite, CircleCI and Travis set
/// it).
#[must_use]
pub fn detected() -> bool {
    std::env::var("CI").is_ok_and(|v| !matches!(v.as_str(), "" | "0" | "false"))
}

/// Whether this runs on GitHub Actions (`GITHUB_ACTIONS=true`).
#[must_use]
pub fn on_github() -> bool {
    std::env::var("GITHUB_ACTIONS").is_ok_and(|v| v == "true")
}

/// The JUnit XML of `cases` checked in `fixtures`: one test suite, one test
/// case per fixture (its time in seconds), a `failure` for a mismatch or
/// a missing fixture, an `error` for one that could not be checked.
///
/// # Errors
/// When the report cannot be serialised.
pub fn junit(cases: &[Case], fixtures: &Path) -> anyhow::Result<String> {
    let mut suite = TestSuite::new(format!("morphogen verify {}", fixtures.display()));
    let mut total = Duration::ZERO;
    for case in cases {
        let status = match &case.verdict {
            Verdict::Ok { .. } => TestCaseStatus::success(),
            verdict => {
                let (kind, ty) = match verdict {
                    Verdict::Error(_) => (NonSuccessKind::Error, "error"),
                    Verdict::Missing(_) => (NonSuccessKind::Failure, "missing"),
                    _ => (NonSuccessKind::Failure, "mismatch"),
                };
                let mut status = TestCaseStatus::non_success(kind);
                status
                    .set_type(ty)
                    .set_message(case.problem().unwrap_or_default())
                    .set_description(case.text());
                status
            }
        };
        let mut test = TestCase::new(case.name.as_str(), status);
        let time = Duration::from_secs_f64(case.seconds.max(0.0));
        total += time;
        test.set_classname("morphogen.fixtures").set_time(time);
        suite.add_test_case(test);
    }
    suite.set_time(total);
    let mut report = Report::new("morphogen verify");
    report.set_time(total).add_test_suite(suite);
    Ok(report.to_string()?)
}

/// `case` as one JSON object (a line of `verify --format json`).
#[must_use]
pub fn json(case: &Case) -> serde_json::Value {
    let mut o = serde_json::json!({
        "name": case.name,
        "verdict": case.word(),
        "seconds": case.seconds,
        "fixture": case.folder,
    });
    match &case.verdict {
        Verdict::Ok { frames, digest } => {
            o["frames"] = (*frames).into();
            o["digest"] = format!("{digest:016x}").into();
        }
        Verdict::Mismatch(m) => {
            let (first, tally) = (&m.first, &m.tally);
            o["first"] = serde_json::json!({
                "frame": first.frame,
                "record": first.record,
                "byte": first.offset,
                "expected": first.expected,
                "actual": first.actual,
            });
            o["records_differing"] = tally.records.into();
            o["kinds"] = serde_json::json!(tally.kinds);
            o["frames_differing"] = serde_json::json!(tally.frames);
            o["changed_keys"] = serde_json::json!(m.changed);
            o["pending"] = match &m.pending {
                Pending::Written(path) => serde_json::json!(path),
                Pending::HeldBack | Pending::Failed(_) => serde_json::Value::Null,
            };
            o["pictures"] = match &m.pictures {
                Ok(p) => serde_json::json!({
                    "frame": p.frame,
                    "dir": p.dir,
                    "differing": p.differing.iter().map(|d| serde_json::json!({
                        "name": d.name,
                        "pixels": d.pixels,
                        "difference": p.difference(d),
                    })).collect::<Vec<_>>(),
                }),
                Err(_) => serde_json::Value::Null,
            };
        }
        Verdict::Missing(why) | Verdict::Error(why) => o["message"] = why.as_str().into(),
    }
    if let Some(note) = &case.note {
        o["note"] = note.as_str().into();
    }
    o
}

/// The last line of `verify --format json`: the counts.
#[must_use]
pub fn json_summary(counts: Counts) -> serde_json::Value {
    serde_json::json!({ "summary": counts })
}

/// GitHub's escaping of a workflow command's message.
fn escape_data(s: &str) -> String {
    s.replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// GitHub's escaping of a workflow command's property.
fn escape_property(s: &str) -> String {
    escape_data(s).replace(':', "%3A").replace(',', "%2C")
}

/// `path` as GitHub names a file in an annotation: relative to the
/// workspace (`GITHUB_WORKSPACE`, else the current folder) where it can be.
fn repository_path(path: &Path) -> String {
    let base = std::env::var_os("GITHUB_WORKSPACE")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::current_dir().ok());
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    base.and_then(|b| absolute.strip_prefix(b).ok().map(Path::to_path_buf))
        .unwrap_or(absolute)
        .display()
        .to_string()
}

/// The `::error` workflow command for a case that failed (none for ok).
#[must_use]
pub fn annotation(case: &Case) -> Option<String> {
    let problem = case.problem()?;
    let (file, title) = match &case.verdict {
        Verdict::Missing(_) => (case.folder.clone(), format!("{}: no fixture", case.name)),
        Verdict::Error(_) => (
            case.folder.clone(),
            format!("{}: cannot be checked", case.name),
        ),
        _ => (
            case.folder.join(crate::fixture::STREAM_FILE),
            format!("{}: the stream differs from its fixture", case.name),
        ),
    };
    Some(format!(
        "::error file={},title={}::{}",
        escape_property(&repository_path(&file)),
        escape_property(&title),
        escape_data(&format!("{problem}\n{}", case.text()))
    ))
}

/// A Markdown table of `cases` for the job summary (`GITHUB_STEP_SUMMARY`).
#[must_use]
pub fn step_summary(cases: &[Case]) -> String {
    let c = Counts::of(cases);
    let mut out = format!(
        "### morphogen verify: {} ok, {} mismatch, {} missing, {} not checked\n\n\
         | fixture | verdict | seconds | what differs |\n|---|---|---:|---|\n",
        c.ok, c.mismatch, c.missing, c.error
    );
    for case in cases {
        let what = case
            .problem()
            .unwrap_or_default()
            .replace('|', "\\|")
            .replace('\n', " ");
        let _ = writeln!(
            out,
            "| `{}` | {} | {:.2} | {what} |",
            case.name,
            case.word(),
            case.seconds
        );
    }
    out
}

/// Appends `text` to the file GitHub names in `GITHUB_STEP_SUMMARY`, if it
/// names one.
///
/// # Errors
/// When that file cannot be written.
pub fn append_step_summary(text: &str) -> anyhow::Result<()> {
    use std::io::Write as _;
    let Some(path) = std::env::var_os("GITHUB_STEP_SUMMARY").filter(|p| !p.is_empty()) else {
        return Ok(());
    };
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(&path)
        .map_err(|e| anyhow::anyhow!("cannot open GITHUB_STEP_SUMMARY {}: {e}", path.display()))?;
    file.write_all(text.as_bytes())
        .map_err(|e| anyhow::anyhow!("cannot write GITHUB_STEP_SUMMARY {}: {e}", path.display()))
}
