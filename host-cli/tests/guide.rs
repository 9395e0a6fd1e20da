//! docs/golden-files.md, followed in a new empty folder: every `sh` block
//! run in order, line by line (a line commented `exit 1` must exit 1, any
//! other 0; `morphogen review` answered at a pseudo-terminal as its
//! comment says), what its lines printed compared with the `text` block
//! after it, and each CI job's `morphogen verify` run with that CI
//! system's variables.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

mod markdown;
mod terminal;
use markdown::{Block, blocks};
use terminal::{read_to_end, read_until, review_on_a_terminal};

/// The folder of the `morphogen` under test, first on `PATH`.
fn path_with_morphogen() -> std::ffi::OsString {
    let bin = Path::new(env!("CARGO_BIN_EXE_morphogen")).parent().unwrap();
    let mut paths = vec![bin.to_path_buf()];
    paths.extend(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    ));
    std::env::join_paths(paths).unwrap()
}

/// `line` run by bash in `dir`, with the CI variables `ci`: its exit code
/// and what it printed.
fn bash(line: &str, dir: &Path, ci: &[(&str, &Path)]) -> (Option<i32>, String) {
    let o = Command::new("bash")
        .args(["-c", line])
        .current_dir(dir)
        .env("PATH", path_with_morphogen())
        .env_remove("MORPHOGEN_FIXTURES")
        .env_remove("CI")
        .env_remove("GITHUB_ACTIONS")
        .env_remove("GITHUB_STEP_SUMMARY")
        .env_remove("GITHUB_WORKSPACE")
        .env_remove("GITLAB_CI")
        .envs(ci.iter().copied())
        .output()
        .expect("run bash");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    (o.status.code(), text)
}

/// Answers `morphogen review` with `answer` at a pseudo-terminal; what it
/// showed.
fn review(dir: &Path, answer: &str) -> String {
    let (mut child, mut master) = review_on_a_terminal(&[], dir);
    let mut shown = String::new();
    read_until(&mut master, &mut shown, "[a/r/s/A/q] ", 1);
    master.write_all(format!("{answer}\n").as_bytes()).unwrap();
    let all = read_to_end(&mut master, &mut shown);
    assert!(child.wait().unwrap().success(), "{all}");
    all
}

/// Whether `printed` is what a `text` block shows: its lines in order,
/// each line `…` standing for any number of lines (ends of lines, and
/// the carriage returns of a terminal, left out).
fn shows(block: &[String], printed: &str) -> bool {
    let printed: Vec<&str> = printed
        .lines()
        .map(|l| l.trim_end_matches('\r').trim_end())
        .collect();
    let mut at = 0;
    let mut skipping = false;
    for line in block.iter().map(|l| l.trim_end()) {
        if line.trim() == "…" {
            skipping = true;
            continue;
        }
        let found = if skipping {
            printed[at..]
                .iter()
                .position(|p| *p == line)
                .map(|k| at + k)
        } else {
            (printed.get(at) == Some(&line)).then_some(at)
        };
        let Some(k) = found else { return false };
        (at, skipping) = (k + 1, false);
    }
    skipping || at == printed.len()
}

/// Runs the `morphogen verify` line of a CI job (a `yaml` block) as that
/// CI system would, in `dir`: it must pass and write its JUnit report.
fn ci_job(block: &Block, dir: &Path, scratch: &Path) {
    let line = block
        .lines
        .iter()
        .find_map(|l| l.split_once("morphogen verify").map(|(_, rest)| rest))
        .map(|rest| format!("morphogen verify{rest}"))
        .expect("a CI job without `morphogen verify`");
    let summary = scratch.join("step-summary.md");
    let github = block.lines.iter().any(|l| l.contains("runs-on:"));
    let ci: Vec<(&str, &Path)> = if github {
        vec![
            ("CI", Path::new("true")),
            ("GITHUB_ACTIONS", Path::new("true")),
            ("GITHUB_STEP_SUMMARY", &summary),
            ("GITHUB_WORKSPACE", dir),
        ]
    } else {
        vec![("CI", Path::new("true")), ("GITLAB_CI", Path::new("true"))]
    };
    let junit = dir.join("morphogen-junit.xml");
    let _ = fs::remove_file(&junit);
    let (code, out) = bash(&line, dir, &ci);
    assert_eq!(code, Some(0), "{line}\n{out}");
    let report = fs::read_to_string(&junit).unwrap_or_else(|_| panic!("{line}: no JUnit report"));
    assert!(report.contains("<testcase name=\"my-horn\""), "{report}");
    if github {
        let table = fs::read_to_string(&summary).unwrap();
        assert!(table.contains("| `my-horn` | ok |"), "{table}");
    }
}

#[test]
fn the_golden_files_guide_runs_as_written() {
    let guide: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/golden-files.md");
    let text = fs::read_to_string(&guide).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let project = tmp.path().join("my-project");
    fs::create_dir(&project).unwrap();
    let (mut commands, mut jobs, mut outputs) = (0, 0, 0);
    // What the lines of the last `sh` block printed.
    let mut printed = String::new();
    for block in blocks(&text) {
        match block.info.as_str() {
            "sh" => {
                printed.clear();
                for line in block.lines.iter().filter(|l| !l.trim().is_empty()) {
                    commands += 1;
                    let comment = line.split_once(" # ").map_or("", |(_, c)| c.trim());
                    if line.starts_with("morphogen review") {
                        let answer = comment
                            .strip_prefix("answer ")
                            .and_then(|a| a.split(':').next())
                            .expect("a review line says its answer");
                        let shown = review(&project, answer);
                        assert!(shown.contains("1 accepted, 0 rejected"), "{shown}");
                        printed.push_str(&shown);
                        continue;
                    }
                    let expected = if comment.starts_with("exit 1") { 1 } else { 0 };
                    let (code, out) = bash(line, &project, &[]);
                    assert_eq!(code, Some(expected), "{line}\n{out}");
                    printed.push_str(&out);
                }
            }
            "text" => {
                assert!(
                    shows(&block.lines, &printed),
                    "the text block at line {} is not what was printed:\n{printed}",
                    block.line
                );
                outputs += 1;
            }
            "sh skip" => assert!(
                block.lines.iter().all(|l| l.starts_with("cargo install ")),
                "only the installation is skipped: {:?}",
                block.lines
            ),
            "yaml" => {
                ci_job(&block, &project, tmp.path());
                jobs += 1;
            }
            _ => {}
        }
    }
    assert!(
        commands >= 8 && jobs == 2 && outputs == 2,
        "{commands} commands, {jobs} CI jobs, {outputs} outputs"
    );
    // Where the guide leaves the project: the accepted change blessed, by
    // this Morphogen, nothing pending.
    let summary = fs::read_to_string(project.join("fixtures/my-horn/summary.toml")).unwrap();
    assert!(summary.contains("blessed_by = \"morphogen "), "{summary}");
    assert!(!project.join("fixtures/my-horn/stream.bin.pending").exists());
    let scenario = fs::read_to_string(project.join("fixtures/my-horn/scenario.toml")).unwrap();
    assert!(scenario.contains("width = 26"), "{scenario}");
}

/// The README's example of a mismatch is what `verify` prints: a scenario
/// file `my-curve.toml` (the growth curve renamed) blessed, then its
/// sigmoid widened from 22 to 25 days.
#[test]
fn the_readme_mismatch_is_what_verify_prints() {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
    let text = fs::read_to_string(&readme).unwrap();
    let shown = blocks(&text)
        .into_iter()
        .find(|b| {
            b.lines
                .first()
                .is_some_and(|l| l.starts_with("MISMATCH  my-curve"))
        })
        .expect("the README's mismatch example");
    let project = tempfile::tempdir().unwrap();
    let dir = project.path();
    for line in [
        r#"morphogen show growth-curve | sed 's/^name = "growth-curve"/name = "my-curve"/' > my-curve.toml"#,
        "morphogen bless my-curve.toml",
        "sed -i 's/width = 22/width = 25/' my-curve.toml",
    ] {
        let (code, out) = bash(line, dir, &[]);
        assert_eq!(code, Some(0), "{line}\n{out}");
    }
    let (code, printed) = bash("morphogen verify my-curve.toml", dir, &[]);
    assert_eq!(code, Some(1), "{printed}");
    assert!(
        shows(&shown.lines, &printed),
        "README.md line {} is not what was printed:\n{printed}",
        shown.line
    );
}
