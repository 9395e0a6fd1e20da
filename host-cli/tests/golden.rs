//! The golden-file workflow: `verify` checks everything and sums up,
//! leaves a mismatch's new stream pending, `bless --accept` takes it,
//! `bless --all` re-blesses; the fixtures folder is found from
//! `--fixtures`, `MORPHOGEN_FIXTURES` or the nearest `fixtures/`.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

fn morphogen(args: &[&str], dir: &Path, env: Option<&Path>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_morphogen"));
    c.args(args)
        .current_dir(dir)
        .env_remove("MORPHOGEN_FIXTURES");
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
