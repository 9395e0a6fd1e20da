//! The golden-file workflow: `verify` checks everything and sums up,
//! leaves a mismatch's new stream pending, `bless --accept` takes it,
//! `bless --all` re-blesses; the fixtures folder is found from
//! `--fixtures`, `MORPHOGEN_FIXTURES` or the nearest `fixtures/`.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

/// `morphogen ARGS` in `dir`, with `MORPHOGEN_FIXTURES` set to `env`, and
/// outside CI (whose variables change what `verify` writes and prints).
fn morphogen(args: &[&str], dir: &Path, env: Option<&Path>) -> Output {
    morphogen_in_ci(args, dir, env, &[])
}

/// As [`morphogen`], with the CI variables `ci` set.
fn morphogen_in_ci(args: &[&str], dir: &Path, env: Option<&Path>, ci: &[(&str, &Path)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_morphogen"));
    c.args(args)
        .current_dir(dir)
        .env_remove("MORPHOGEN_FIXTURES")
        .env_remove("CI")
        .env_remove("GITHUB_ACTIONS")
        .env_remove("GITHUB_STEP_SUMMARY")
        .env_remove("GITHUB_WORKSPACE")
        .envs(ci.iter().copied());
    if let Some(fixtures) = env {
        c.env("MORPHOGEN_FIXTURES", fixtures);
    }
    c.output().expect("run morphogen")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn both(o: &Output) -> String {
    format!("{}{}", stdout(o), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn verify_sums_up_leaves_pending_streams_and_bless_accepts_them() {
    let tmp = tempfile::tempdir().unwrap();
    let project = tmp.path().join("project");
    let deep = project.join("src/deeper");
    fs::create_dir_all(&deep).unwrap();
    // A user's scenario blessed from inside the project: a new fixtures/.
    let shown = morphogen(&["show", "growth-curve"], &project, None);
    let text = stdout(&shown).replace("name = \"growth-curve\"", "name = \"my-curve\"");
    fs::write(project.join("my.toml"), &text).unwrap();
    let o = morphogen(&["bless", "my.toml", "growth-curve"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    let fixtures = project.join("fixtures");
    assert!(fixtures.join("my-curve/scenario.toml").is_file());
    // Found from a subfolder, all checked, one summary line.
    let o = morphogen(&["verify"], &deep, None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
    assert!(
        stdout(&o).ends_with("2 ok, 0 mismatch, 0 missing\n"),
        "{}",
        stdout(&o)
    );
    // The fixture's scenario changes: a mismatch, its new stream pending,
    // and the other fixture is still checked.
    let fixture_toml = fixtures.join("my-curve/scenario.toml");
    let changed = fs::read_to_string(&fixture_toml)
        .unwrap()
        .replace("width = 22", "width = 25");
    fs::write(&fixture_toml, changed).unwrap();
    let o = morphogen(&["verify"], &deep, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(stdout(&o).contains("MISMATCH  my-curve"), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("ok        growth-curve"),
        "{}",
        stdout(&o)
    );
    assert!(
        stdout(&o).ends_with("1 ok, 1 mismatch, 0 missing\n"),
        "{}",
        stdout(&o)
    );
    let pending = fixtures.join("my-curve/stream.bin.pending");
    assert!(pending.is_file());
    // Missing fixtures are counted, not fatal.
    let o = morphogen(&["verify", "my-curve", "ram-horn"], &project, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(stdout(&o).contains("MISSING   ram-horn"), "{}", stdout(&o));
    // Accept: the pending stream becomes the fixture, and verify passes
    // (from MORPHOGEN_FIXTURES, anywhere).
    let pending_bytes = fs::read(&pending).unwrap();
    let o = morphogen(&["bless", "--accept"], &deep, None);
    assert!(o.status.success(), "{}", both(&o));
    assert!(stdout(&o).contains("blessed   my-curve"), "{}", stdout(&o));
    assert_eq!(
        fs::read(fixtures.join("my-curve/stream.bin")).unwrap(),
        pending_bytes
    );
    assert!(!pending.exists());
    let o = morphogen(&["verify"], tmp.path(), Some(&fixtures));
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
    // --all re-blesses every fixture; verify still passes.
    let o = morphogen(&["bless", "--all"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    assert_eq!(
        stdout(&o).matches("blessed   ").count(),
        2,
        "{}",
        stdout(&o)
    );
    let o = morphogen(&["verify", "--fixtures", "fixtures"], &project, None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
    // Nothing to find: a clear error, exit 2.
    let empty = tmp.path().join("empty");
    fs::create_dir(&empty).unwrap();
    let o = morphogen(&["verify"], &empty, None);
    assert_eq!(o.status.code(), Some(2), "{}", both(&o));
    assert!(both(&o).contains("no fixtures folder"), "{}", both(&o));
}

/// A copy of the workspace's fixture `name` in `fixtures/as_name`.
fn copy_fixture(name: &str, fixtures: &Path, as_name: &str) {
    let from = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fixtures")
        .join(name);
    let to = fixtures.join(as_name);
    fs::create_dir_all(&to).unwrap();
    for f in ["stream.bin", "summary.toml"] {
        fs::copy(from.join(f), to.join(f)).unwrap();
    }
}

#[test]
fn every_fixture_folder_is_checked_or_named_as_not_checked() {
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = tmp.path().join("fixtures");
    copy_fixture("growth-curve", &fixtures, "growth-curve");
    // A folder without its summary.
    copy_fixture("ram-horn", &fixtures, "ram-horn");
    fs::remove_file(fixtures.join("ram-horn/summary.toml")).unwrap();
    // A summary and a scenario that agree with their folder over a stream
    // of another.
    let shown = morphogen(&["show", "growth-curve"], tmp.path(), None);
    let mine = stdout(&shown).replace("name = \"growth-curve\"", "name = \"my-curve\"");
    copy_fixture("growth-curve", &fixtures, "my-curve");
    let summary = fixtures.join("my-curve/summary.toml");
    let text = fs::read_to_string(&summary).unwrap();
    fs::write(
        &summary,
        text.replace("preset = \"growth-curve\"", "preset = \"my-curve\""),
    )
    .unwrap();
    fs::write(fixtures.join("my-curve/scenario.toml"), &mine).unwrap();
    // A scenario file that names another fixture.
    copy_fixture("growth-curve", &fixtures, "their-curve");
    fs::write(fixtures.join("their-curve/scenario.toml"), &mine).unwrap();
    let o = morphogen(&["verify", "--fixtures", "fixtures"], tmp.path(), None);
    assert_eq!(o.status.code(), Some(2), "{}", both(&o));
    let out = stdout(&o);
    assert!(out.contains("ok        growth-curve"), "{out}");
    assert!(
        out.contains("ERROR     ram-horn: cannot read") && out.contains("summary.toml"),
        "{out}"
    );
    assert!(
        out.contains("ERROR     my-curve: fixture corrupt:")
            && out.contains("is a stream of 'growth-curve', but lives in the folder of 'my-curve'"),
        "{out}"
    );
    assert!(
        out.contains("ERROR     their-curve: fixture corrupt:")
            && out.contains("names 'my-curve', but lives in the folder of 'their-curve'"),
        "{out}"
    );
    assert!(
        out.ends_with("1 ok, 0 mismatch, 0 missing, 3 not checked\n"),
        "{out}"
    );
}

#[test]
fn bless_accept_takes_the_scenario_file_that_verify_ran() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let shown = morphogen(&["show", "growth-curve"], dir, None);
    let mine = stdout(&shown).replace("name = \"growth-curve\"", "name = \"my-curve\"");
    fs::write(dir.join("my.toml"), &mine).unwrap();
    let o = morphogen(&["bless", "my.toml", "--fixtures", "fixtures"], dir, None);
    assert!(o.status.success(), "{}", both(&o));
    // The file changes: verifying it leaves its stream and itself pending.
    fs::write(
        dir.join("my.toml"),
        mine.replace("width = 22", "width = 25"),
    )
    .unwrap();
    let o = morphogen(&["verify", "my.toml", "--fixtures", "fixtures"], dir, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let folder = dir.join("fixtures/my-curve");
    assert!(folder.join("stream.bin.pending").is_file());
    assert!(
        fs::read_to_string(folder.join("scenario.toml.pending"))
            .unwrap()
            .contains("width = 25")
    );
    // The fixture's own scenario still matches: what is pending stays.
    let o = morphogen(&["verify", "--fixtures", "fixtures"], dir, None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
    assert!(folder.join("stream.bin.pending").is_file());
    // Accepted, the fixture is the file's: plain verify agrees with it.
    let o = morphogen(
        &["bless", "--accept", "my-curve", "--fixtures", "fixtures"],
        dir,
        None,
    );
    assert!(o.status.success(), "{}", both(&o));
    assert!(
        fs::read_to_string(folder.join("scenario.toml"))
            .unwrap()
            .contains("width = 25")
    );
    assert!(!folder.join("stream.bin.pending").exists());
    assert!(!folder.join("scenario.toml.pending").exists());
    let o = morphogen(&["verify", "--fixtures", "fixtures"], dir, None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
    let o = morphogen(&["verify", "my.toml", "--fixtures", "fixtures"], dir, None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
}

#[test]
fn a_scenario_with_a_built_in_name_never_takes_the_built_ins_fixture() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let fixtures = dir.join("fixtures");
    copy_fixture("growth-curve", &fixtures, "growth-curve");
    let before = fs::read(fixtures.join("growth-curve/stream.bin")).unwrap();
    let shown = stdout(&morphogen(&["show", "growth-curve"], dir, None));
    fs::write(
        dir.join("mine.toml"),
        shown.replace("width = 22", "width = 25"),
    )
    .unwrap();
    for args in [
        &["bless", "mine.toml"][..],
        &["bless", "growth-curve", "--set", "curve.growth.width=25"],
    ] {
        let o = morphogen(&[args, &["--fixtures", "fixtures"]].concat(), dir, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", both(&o));
        assert!(
            both(&o).contains("is not the built-in preset 'growth-curve' but has its name"),
            "{args:?}: {}",
            both(&o)
        );
    }
    assert_eq!(
        fs::read(fixtures.join("growth-curve/stream.bin")).unwrap(),
        before
    );
    assert!(!fixtures.join("growth-curve/scenario.toml").exists());
    // One put there by hand is refused, not run in the built-in's place.
    fs::copy(
        dir.join("mine.toml"),
        fixtures.join("growth-curve/scenario.toml"),
    )
    .unwrap();
    let o = morphogen(
        &["verify", "growth-curve", "--fixtures", "fixtures"],
        dir,
        None,
    );
    assert_eq!(o.status.code(), Some(2), "{}", both(&o));
    assert!(
        both(&o).contains("replaces the built-in preset 'growth-curve'"),
        "{}",
        both(&o)
    );
}

#[cfg(unix)]
#[test]
fn a_fixture_file_that_is_a_device_is_refused_not_read() {
    // A stream that is a symlink to /dev/zero would be read without end.
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = tmp.path().join("fixtures");
    copy_fixture("growth-curve", &fixtures, "growth-curve");
    let stream = fixtures.join("growth-curve/stream.bin");
    fs::remove_file(&stream).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &stream).unwrap();
    let o = morphogen(&["verify", "--fixtures", "fixtures"], tmp.path(), None);
    assert_eq!(o.status.code(), Some(2), "{}", both(&o));
    assert!(
        stdout(&o).contains("not a regular file but a device"),
        "{}",
        both(&o)
    );
}

/// A project with two fixtures, `growth-curve` and a scenario file's
/// `my-curve`, whose fixture's scenario then changes: verifying it is a
/// mismatch.
fn project_with_a_mismatch(tmp: &Path) -> std::path::PathBuf {
    let project = tmp.join("project");
    fs::create_dir_all(&project).unwrap();
    let shown = morphogen(&["show", "growth-curve"], &project, None);
    let text = stdout(&shown).replace("name = \"growth-curve\"", "name = \"my-curve\"");
    fs::write(project.join("my.toml"), &text).unwrap();
    let o = morphogen(&["bless", "my.toml", "growth-curve"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    let fixture_toml = project.join("fixtures/my-curve/scenario.toml");
    let changed = fs::read_to_string(&fixture_toml)
        .unwrap()
        .replace("width = 22", "width = 25");
    fs::write(&fixture_toml, changed).unwrap();
    project
}

/// `verify --junit` writes a report CI servers read: a test case per
/// fixture with its time, a failure with the first difference and the
/// counts for a mismatch and for a missing fixture.
#[test]
fn verify_writes_a_junit_report() {
    let tmp = tempfile::tempdir().unwrap();
    let project = project_with_a_mismatch(tmp.path());
    let o = morphogen(
        &[
            "verify",
            "my-curve",
            "growth-curve",
            "ram-horn",
            "--junit",
            "report.xml",
        ],
        &project,
        None,
    );
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let xml = fs::read_to_string(project.join("report.xml")).unwrap();
    let report = quick_junit::Report::deserialize_from_str(&xml).expect("a JUnit report");
    assert_eq!(
        (report.tests, report.failures, report.errors),
        (3, 2, 0),
        "{xml}"
    );
    let suite = &report.test_suites[0];
    let cases: Vec<(&str, bool)> = suite
        .test_cases
        .iter()
        .map(|c| {
            (
                c.name.as_str(),
                matches!(c.status, quick_junit::TestCaseStatus::Success { .. }),
            )
        })
        .collect();
    assert_eq!(
        cases,
        [
            ("my-curve", false),
            ("growth-curve", true),
            ("ram-horn", false)
        ]
    );
    let mismatch = &suite.test_cases[0];
    let quick_junit::TestCaseStatus::NonSuccess {
        message,
        ty,
        description,
        ..
    } = &mismatch.status
    else {
        panic!("{xml}")
    };
    assert_eq!(ty.as_ref().map(|t| t.as_str()), Some("mismatch"));
    let message = message.as_ref().unwrap().as_str();
    assert!(
        message.contains("records differ (header 1")
            && message.contains("first in the header, record 0"),
        "{message}"
    );
    assert!(
        description
            .as_ref()
            .unwrap()
            .as_str()
            .contains("expected: {\"kind\":\"header\""),
        "{xml}"
    );
    assert!(mismatch.time.is_some(), "{xml}");
    // The elements and attributes CI servers' JUnit schema asks for.
    for needed in [
        "<testsuites ",
        "<testsuite name=",
        "<testcase name=\"my-curve\" classname=",
        "time=",
        "<failure ",
    ] {
        assert!(xml.contains(needed), "{needed} in {xml}");
    }
}

/// `verify --format json` prints a JSON object per fixture and one with
/// the counts.
#[test]
fn verify_prints_json_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let project = project_with_a_mismatch(tmp.path());
    let o = morphogen(&["verify", "--format", "json"], &project, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let lines: Vec<serde_json::Value> = stdout(&o)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(lines.len(), 3, "{}", stdout(&o));
    assert_eq!(lines[0]["name"], "growth-curve");
    assert_eq!(lines[0]["verdict"], "ok");
    assert_eq!(lines[1]["name"], "my-curve");
    assert_eq!(lines[1]["verdict"], "mismatch");
    assert_eq!(lines[1]["first"]["record"], 0);
    assert!(lines[1]["records_differing"].as_u64().unwrap() >= 1);
    assert_eq!(lines[1]["kinds"]["header"], 1);
    assert!(
        lines[1]["pending"]
            .as_str()
            .unwrap()
            .ends_with("stream.bin.pending")
    );
    assert_eq!(lines[2]["summary"]["mismatch"], 1);
    assert_eq!(lines[2]["summary"]["ok"], 1);
}

/// Under CI, `verify` writes nothing into the fixtures folder unless
/// `--pending` asks, and says so; on GitHub Actions a failing fixture is an
/// `::error` annotation naming its stream, and the counts a table in the
/// job summary.
#[test]
fn under_ci_verify_writes_no_pending_stream_and_annotates() {
    let tmp = tempfile::tempdir().unwrap();
    let project = project_with_a_mismatch(tmp.path());
    let pending = project.join("fixtures/my-curve/stream.bin.pending");
    let summary = tmp.path().join("step-summary.md");
    let ci = [
        ("CI", Path::new("true")),
        ("GITHUB_ACTIONS", Path::new("true")),
        ("GITHUB_STEP_SUMMARY", summary.as_path()),
        ("GITHUB_WORKSPACE", project.as_path()),
    ];
    let o = morphogen_in_ci(&["verify"], &project, None, &ci);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(!pending.exists(), "{}", both(&o));
    let out = stdout(&o);
    assert!(out.contains("new stream not written: CI is set"), "{out}");
    assert!(
        out.contains("CI is set: no new stream was written into"),
        "{out}"
    );
    let annotation = out
        .lines()
        .find(|l| l.starts_with("::error "))
        .unwrap_or_else(|| panic!("no annotation in {out}"));
    assert!(
        annotation.starts_with("::error file=fixtures/my-curve/stream.bin,title=my-curve%3A the stream differs from its fixture::"),
        "{annotation}"
    );
    assert!(
        annotation.contains("%0A") && !annotation.contains('\n'),
        "{annotation}"
    );
    assert_eq!(out.matches("::error ").count(), 1, "{out}");
    let table = fs::read_to_string(&summary).unwrap();
    assert!(
        table.contains("1 ok, 1 mismatch, 0 missing, 0 not checked"),
        "{table}"
    );
    assert!(table.contains("| `my-curve` | mismatch |"), "{table}");
    // --pending leaves it, CI or not.
    let o = morphogen_in_ci(&["verify", "--pending"], &project, None, &ci[..1]);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(pending.is_file(), "{}", both(&o));
    assert!(!stdout(&o).contains("::error"), "{}", stdout(&o));
}

/// A scenario file verified against its fixture names the keys whose
/// values are not those it was blessed with.
#[test]
fn a_mismatch_names_the_keys_changed_since_the_bless() {
    let tmp = tempfile::tempdir().unwrap();
    let project = tmp.path().join("project");
    fs::create_dir_all(&project).unwrap();
    let shown = morphogen(&["show", "growth-curve"], &project, None);
    let text = stdout(&shown).replace("name = \"growth-curve\"", "name = \"my-curve\"");
    fs::write(project.join("my.toml"), &text).unwrap();
    let o = morphogen(&["bless", "my.toml"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    fs::write(
        project.join("my.toml"),
        text.replace("width = 22", "width = 25"),
    )
    .unwrap();
    let o = morphogen(&["verify", "my.toml"], &project, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let out = stdout(&o);
    let line = out
        .lines()
        .find(|l| l.contains("changed since the bless: "))
        .unwrap_or_else(|| panic!("no changed keys in {out}"));
    assert!(line.ends_with("width: 22 -> 25"), "{line}");
    assert_eq!(line.matches(" -> ").count(), 1, "{line}");
}

/// The red pixels of the PNG at `path`, and its size.
fn red_pixels(path: &Path) -> (u64, (u32, u32)) {
    let decoder = png::Decoder::new(std::io::BufReader::new(fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    let red = buf[..info.buffer_size()]
        .chunks_exact(3)
        .filter(|p| p == &[230, 0, 0])
        .count();
    (red as u64, (info.width, info.height))
}

/// A mismatch draws the model's picture of the first frame that differs
/// from the fixture and from the new stream, and their difference, beside
/// the pending stream (or into `--report DIR`, the only place under CI),
/// and names them; an accepted fixture loses them.
#[test]
fn a_mismatch_draws_the_expected_actual_and_difference_pictures() {
    let tmp = tempfile::tempdir().unwrap();
    let project = tmp.path().join("project");
    fs::create_dir_all(&project).unwrap();
    let shown = morphogen(&["show", "ram-horn"], &project, None);
    let text = stdout(&shown).replace("name = \"ram-horn\"", "name = \"my-horn\"");
    fs::write(project.join("horn.toml"), &text).unwrap();
    let o = morphogen(&["bless", "horn.toml"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    let wider = text.replace("width = 22", "width = 30");
    assert_ne!(wider, text);
    fs::write(project.join("horn.toml"), &wider).unwrap();

    let o = morphogen(&["verify", "horn.toml"], &project, None);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let out = stdout(&o);
    let report = project.join("fixtures/my-horn/report");
    let line = out
        .lines()
        .find(|l| l.starts_with("  pictures of frame 0 differ: ") && l.contains(" horn.png ("))
        .unwrap_or_else(|| panic!("no pictures named in {out}"));
    // The fixtures found here are named from here.
    assert!(line.ends_with(" in fixtures/my-horn/report"), "{line}");
    for side in ["expected", "actual", "difference"] {
        assert!(
            report.join(side).join("horn.png").is_file(),
            "{side}: {out}"
        );
    }
    // The count it prints is that of the red pixels it drew, and the
    // horns differ in a part of the picture only.
    let (red, (w, h)) = red_pixels(&report.join("difference/horn.png"));
    assert!(
        line.contains(&format!(" horn.png ({red} pixels)")),
        "{line}"
    );
    assert!(red > 100 && red < u64::from(w * h) / 2, "{red} of {w}x{h}");
    // Pictures the same on both sides are not kept.
    assert!(!report.join("expected/bend.png").exists(), "{out}");

    // Accepted, the fixture is the new one, without the pictures.
    let o = morphogen(&["bless", "--accept", "my-horn"], &project, None);
    assert!(o.status.success(), "{}", both(&o));
    assert!(
        !report.exists(),
        "an accepted fixture keeps the old pictures"
    );

    // Under CI: nothing in the fixtures folder; --report puts them there.
    fs::write(project.join("horn.toml"), &text).unwrap();
    let ci = [("CI", Path::new("true"))];
    let o = morphogen_in_ci(&["verify", "horn.toml"], &project, None, &ci);
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    assert!(
        stdout(&o).contains("pictures not drawn: CI is set (give --report DIR"),
        "{}",
        both(&o)
    );
    assert!(!report.exists());
    let o = morphogen_in_ci(
        &[
            "verify",
            "horn.toml",
            "--report",
            "pictures",
            "--format",
            "json",
        ],
        &project,
        None,
        &ci,
    );
    assert_eq!(o.status.code(), Some(1), "{}", both(&o));
    let case: serde_json::Value = serde_json::from_str(stdout(&o).lines().next().unwrap()).unwrap();
    let difference = project.join("pictures/my-horn/difference/horn.png");
    assert_eq!(case["pictures"]["frame"], 0, "{case}");
    assert!(
        case["pictures"]["differing"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p["difference"] == "pictures/my-horn/difference/horn.png"),
        "{case}"
    );
    assert!(difference.is_file());
    assert!(!report.exists());
}

/// A blessed fixture names the Morphogen that blessed it, as `morphogen
/// --version` names itself (with the commit of a checkout's build); a
/// fixture from before summaries named it still verifies.
#[test]
fn a_fixture_names_the_morphogen_that_blessed_it() {
    let tmp = tempfile::tempdir().unwrap();
    let o = morphogen(&["--version"], tmp.path(), None);
    let version = stdout(&o).trim().to_string();
    assert!(version.starts_with("morphogen 0."), "{version}");
    let o = morphogen(&["bless", "growth-curve"], tmp.path(), None);
    assert!(o.status.success(), "{}", both(&o));
    let summary = tmp.path().join("fixtures/growth-curve/summary.toml");
    let text = fs::read_to_string(&summary).unwrap();
    assert!(
        text.contains(&format!("\nblessed_by = \"{version}\"\n")),
        "{text}"
    );
    // The workspace's fixture has none, and verifies.
    let old = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/growth-curve/summary.toml");
    let old_text = fs::read_to_string(old).unwrap();
    assert!(!old_text.contains("blessed_by"));
    let stream = fs::read(tmp.path().join("fixtures/growth-curve/stream.bin")).unwrap();
    let workspace_stream =
        fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/growth-curve/stream.bin"))
            .unwrap();
    assert_eq!(stream, workspace_stream);
    fs::write(&summary, old_text).unwrap();
    let o = morphogen(&["verify"], tmp.path(), None);
    assert_eq!(o.status.code(), Some(0), "{}", both(&o));
}
