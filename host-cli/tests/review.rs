//! `morphogen review` at a terminal (a pseudo-terminal here): each
//! pending stream shown with what differs and its pictures, then
//! accepted, rejected or skipped as answered.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

mod terminal;
use terminal::{read_to_end, read_until, review_on_a_terminal};

/// `morphogen ARGS` in `dir`, outside CI.
fn morphogen(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(args)
        .current_dir(dir)
        .env_remove("MORPHOGEN_FIXTURES")
        .env_remove("CI")
        .env_remove("GITHUB_ACTIONS")
        .output()
        .expect("run morphogen")
}

fn both(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A project whose fixtures `my-a`, `my-b` and `my-c` (growth curves) each
/// have a pending stream: their scenario files changed after the bless.
fn project_with_three_pending(tmp: &Path) -> std::path::PathBuf {
    let project = tmp.join("project");
    fs::create_dir_all(&project).unwrap();
    let shown = morphogen(&["show", "growth-curve"], &project);
    let text = String::from_utf8(shown.stdout).unwrap();
    for name in ["a", "b", "c"] {
        let file = format!("{name}.toml");
        let own = text.replace("name = \"growth-curve\"", &format!("name = \"my-{name}\""));
        fs::write(project.join(&file), &own).unwrap();
        let o = morphogen(&["bless", &file], &project);
        assert!(o.status.success(), "{}", both(&o));
        fs::write(project.join(&file), own.replace("width = 22", "width = 25")).unwrap();
    }
    let o = morphogen(&["verify", "a.toml", "b.toml", "c.toml"], &project);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    project
}

const QUESTION: &str = "[a/r/s/A/q] ";

#[test]
fn review_accepts_rejects_and_skips_as_answered() {
    let tmp = tempfile::tempdir().unwrap();
    let project = project_with_three_pending(tmp.path());
    let fixtures = project.join("fixtures");
    let pending = |name: &str| fixtures.join(name).join("stream.bin.pending");
    let (mut child, mut master) = review_on_a_terminal(&[], &project);
    let mut shown = String::new();
    let first = read_until(&mut master, &mut shown, QUESTION, 1);
    assert!(first.contains("[1/3] my-a: first difference"), "{first}");
    assert!(
        first.contains("changed since the bless: curve.growth.width: 22 -> 25"),
        "{first}"
    );
    assert!(
        first.contains("pictures of frame 0 differ: growth.png ("),
        "{first}"
    );
    assert!(fixtures.join("my-a/report/difference/growth.png").is_file());
    // Not an answer: asked again.
    master.write_all(b"yes\n").unwrap();
    read_until(&mut master, &mut shown, QUESTION, 2);
    master.write_all(b"a\n").unwrap();
    read_until(&mut master, &mut shown, QUESTION, 3);
    master.write_all(b"r\n").unwrap();
    read_until(&mut master, &mut shown, QUESTION, 4);
    master.write_all(b"s\n").unwrap();
    let all = read_to_end(&mut master, &mut shown);
    let status = child.wait().unwrap();
    assert!(status.success(), "{all}");
    assert!(all.contains("'yes' is not an answer"), "{all}");
    assert!(all.contains("blessed   my-a seed 0"), "{all}");
    assert!(
        all.contains("rejected  my-b: its pending stream is removed"),
        "{all}"
    );
    assert!(all.contains("skipped   my-c"), "{all}");
    assert!(
        all.ends_with("1 accepted, 1 rejected, 1 left pending\n"),
        "{all}"
    );
    // my-a is the new stream; my-b's is gone with its pictures; my-c's
    // waits.
    assert!(!pending("my-a").exists() && !pending("my-b").exists());
    assert!(!fixtures.join("my-b/report").exists());
    assert!(pending("my-c").is_file());
    let o = morphogen(&["verify", "a.toml", "b.toml"], &project);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(both(&o).starts_with("ok        my-a"), "{}", both(&o));

    // Accept all takes the rest without asking again.
    let (mut child, mut master) = review_on_a_terminal(&[], &project);
    let mut shown = String::new();
    read_until(&mut master, &mut shown, QUESTION, 1);
    master.write_all(b"A\n").unwrap();
    let all = read_to_end(&mut master, &mut shown);
    assert!(child.wait().unwrap().success(), "{all}");
    assert_eq!(all.matches(QUESTION).count(), 1, "{all}");
    assert!(
        all.contains("[1/2] my-b") && all.contains("[2/2] my-c"),
        "{all}"
    );
    assert!(
        all.ends_with("2 accepted, 0 rejected, 0 left pending\n"),
        "{all}"
    );
}

#[test]
fn review_asks_only_at_a_terminal() {
    let tmp = tempfile::tempdir().unwrap();
    let project = project_with_three_pending(tmp.path());
    let o = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .arg("review")
        .current_dir(&project)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", both(&o));
    assert!(
        both(&o).contains("review asks at a terminal, and standard input is not one"),
        "{}",
        both(&o)
    );
    assert!(project.join("fixtures/my-a/stream.bin.pending").is_file());
}
