//! Scenario files end to end: every preset's `show` output runs to its
//! fixture's bytes, every documented parameter reaches the digest, a user's
//! scenario is blessed and verified, and sweeps do not depend on the thread
//! count or on sharding.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use morphogen_scenario::Scenario;

fn morphogen(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run morphogen")
}

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// Every numeric or boolean leaf of a TOML value, as dotted keys with
/// indices, with its value.
fn leaves(prefix: &str, v: &toml::Value, out: &mut Vec<(String, toml::Value)>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                leaves(&key, v, out);
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                leaves(&format!("{prefix}[{i}]"), v, out);
            }
        }
        toml::Value::Integer(_) | toml::Value::Float(_) | toml::Value::Boolean(_) => {
            out.push((prefix.to_string(), v.clone()));
        }
        _ => {}
    }
}

/// Candidate changes of one value, tried in order until one is valid.
fn changes(v: &toml::Value) -> Vec<String> {
    match v {
        toml::Value::Integer(i) => vec![
            (i + 1).to_string(),
            (i - 1).to_string(),
            (i + 4).to_string(),
        ],
        toml::Value::Float(f) => vec![
            format!("{:?}", f * 1.0625 + 0.0625),
            format!("{:?}", f * 0.9375),
            format!("{:?}", f - 0.0625),
        ],
        toml::Value::Boolean(b) => vec![(!b).to_string()],
        _ => vec![],
    }
}

#[test]
fn every_documented_parameter_changes_the_digest() {
    let mut checked = 0;
    for s in morphogen_scenario::builtins() {
        let digest = |s: &Scenario| s.with_preset(|p| p.model.params_digest());
        let base = digest(&s);
        let table: toml::Value = toml::from_str(&s.self_contained()).unwrap();
        let mut all = Vec::new();
        leaves("", &table, &mut all);
        for (key, value) in all.iter().filter(|(k, _)| k != "seed") {
            let Some(changed) = changes(value)
                .into_iter()
                .find_map(|v| s.clone_with_sets(&[(key.clone(), v)]).ok())
            else {
                continue; // no valid neighbour (e.g. a lone odd count)
            };
            assert_ne!(
                digest(&changed),
                base,
                "{}: changing {key} keeps the digest",
                s.name()
            );
            checked += 1;
        }
    }
    assert!(checked > 400, "only {checked} parameters were changed");
}

#[test]
fn built_in_scenario_files_are_named_after_their_presets() {
    for s in morphogen_scenario::builtins() {
        assert_eq!(s.origin(), format!("built-in {}", s.name()));
        // `builtin` reads that one file alone, and finds the same preset.
        let alone = morphogen_scenario::builtin(s.name()).expect("found by name");
        let digest = |s: &Scenario| s.with_preset(|p| p.model.params_digest());
        assert_eq!((alone.origin(), digest(&alone)), (s.origin(), digest(&s)));
        assert!(
            fixtures().join(s.name()).join("stream.bin").is_file(),
            "{}",
            s.name()
        );
    }
}

#[test]
fn show_then_run_gives_the_fixture_for_small_presets() {
    // The big mosaics are checked the same way by scripts/check.sh with the
    // release build (`morphogen verify` runs the embedded scenario files).
    let tmp = tempfile::tempdir().unwrap();
    for name in [
        "growth-curve",
        "abop-2d-plant",
        "croton-mcu",
        "long-bone",
        "cow-growth",
    ] {
        let shown = morphogen(&["show", name], tmp.path());
        assert!(shown.status.success());
        let file = tmp.path().join(format!("{name}.toml"));
        std::fs::write(&file, &shown.stdout).unwrap();
        let o = morphogen(&["run", file.to_str().unwrap(), "--out", "o"], tmp.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let ours = std::fs::read(tmp.path().join("o/stream.bin")).unwrap();
        let golden = std::fs::read(fixtures().join(name).join("stream.bin")).unwrap();
        assert!(
            ours == golden,
            "{name}: show | run differs from the fixture"
        );
    }
}

#[test]
fn a_user_scenario_is_blessed_verified_and_guarded() {
    let tmp = tempfile::tempdir().unwrap();
    let shown = morphogen(&["show", "growth-curve"], tmp.path());
    let text = String::from_utf8(shown.stdout)
        .unwrap()
        .replace("name = \"growth-curve\"", "name = \"my-curve\"")
        .replace("width = 22", "width = 30");
    std::fs::write(tmp.path().join("my.toml"), &text).unwrap();
    let fx = tmp.path().join("fx");
    let fxs = fx.to_str().unwrap();
    let o = morphogen(&["bless", "my.toml", "--fixtures", fxs], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(fx.join("my-curve/scenario.toml").is_file());
    // verify by file, and verify --fixtures re-runs every fixture there
    // from its own scenario.toml.
    for args in [
        vec!["verify", "my.toml", "--fixtures", fxs],
        vec!["verify", "--fixtures", fxs],
    ] {
        let o = morphogen(&args, tmp.path());
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stdout)
        );
    }
    // A changed parameter is a mismatch (exit 1).
    let o = morphogen(&["verify", "--fixtures", fxs], tmp.path());
    assert!(String::from_utf8_lossy(&o.stdout).contains("ok        my-curve"));
    let changed = text.replace("width = 30", "width = 31");
    std::fs::write(tmp.path().join("my.toml"), &changed).unwrap();
    let o = morphogen(&["verify", "my.toml", "--fixtures", fxs], tmp.path());
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    // A flipped byte in the fixture is a corrupt fixture (exit 2).
    let stream = fx.join("my-curve/stream.bin");
    let mut bytes = std::fs::read(&stream).unwrap();
    bytes[40] ^= 1;
    std::fs::write(&stream, &bytes).unwrap();
    let o = morphogen(&["verify", "--fixtures", fxs], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("fixture corrupt"));
    // A bad value exits 2 naming the file, the line and the key.
    let bad = text.replace("days = 365", "days = -4");
    std::fs::write(tmp.path().join("bad.toml"), &bad).unwrap();
    let line = bad
        .lines()
        .position(|l| l.starts_with("days = -4"))
        .unwrap()
        + 1;
    let o = morphogen(&["run", "bad.toml"], tmp.path());
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        format!("error: bad.toml:{line}: curve.days: -4 is out of range (allowed: 1 to 32767)")
    );
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples")
}

/// Runs `morphogen` in `dir` and asserts that it succeeds, naming the
/// arguments and what it said.
fn runs(args: &[&str], dir: &Path) {
    let o = morphogen(args, dir);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Runs `morphogen` in `dir`, asserts that it refuses (exit 2) and returns
/// what it said, trimmed.
fn refused(args: &[&str], dir: &Path) -> String {
    let o = morphogen(args, dir);
    assert_eq!(o.status.code(), Some(2), "{args:?}");
    String::from_utf8_lossy(&o.stderr).trim().to_string()
}

/// The stream a run in `dir` wrote to its `--out` folder `out`.
fn stream_in(dir: &Path, out: &str) -> Vec<u8> {
    std::fs::read(dir.join(out).join("stream.bin")).unwrap()
}

/// A folder holding the example user body: `wagging-tail.toml` and the
/// mesh and cylinders it names.
fn folder_with_the_tail() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    for file in ["wagging-tail.toml", "tail.obj", "tail.cylinders"] {
        std::fs::copy(examples().join(file), tmp.path().join(file)).unwrap();
    }
    tmp
}

/// A user's body runs from its mesh and cylinders, every vertex in a
/// cylinder; `show` inlines both files, so the shown scenario runs anywhere,
/// alike.
#[test]
fn a_user_body_runs_from_its_files() {
    let tmp = folder_with_the_tail();
    let o = morphogen(&["run", "wagging-tail.toml", "--out", "a"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(tmp.path().join("a/summary.txt")).unwrap();
    assert!(
        summary.contains("vertices 16, triangles 28")
            && summary.contains("vertices in no cylinder (following the nearest): 0"),
        "{summary}"
    );
    let shown = morphogen(&["show", "wagging-tail.toml"], tmp.path());
    std::fs::create_dir(tmp.path().join("elsewhere")).unwrap();
    std::fs::write(tmp.path().join("elsewhere/tail.toml"), &shown.stdout).unwrap();
    let o = morphogen(
        &["run", "tail.toml", "--out", "b"],
        &tmp.path().join("elsewhere"),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(tmp.path().join("a/stream.bin")).unwrap(),
        std::fs::read(tmp.path().join("elsewhere/b/stream.bin")).unwrap()
    );
}

/// Golden files guard a user's body like any scenario.
#[test]
fn a_user_body_is_blessed_and_verified() {
    let tmp = folder_with_the_tail();
    let o = morphogen(
        &["bless", "wagging-tail.toml", "--fixtures", "fx"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = morphogen(&["verify", "--fixtures", "fx"], tmp.path());
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// A mistake in a file a user's scenario names is located in that file,
/// under the scenario's key; a built-in body beside a user's is refused at
/// its key.
#[test]
fn a_mistake_in_a_user_bodys_file_is_named_in_that_file() {
    let tmp = folder_with_the_tail();
    let error = |cylinders: &str, toml: &str| {
        std::fs::write(tmp.path().join("bad.cylinders"), cylinders).unwrap();
        std::fs::write(tmp.path().join("bad.toml"), toml).unwrap();
        refused(&["run", "bad.toml"], tmp.path())
    };
    let cylinders = std::fs::read_to_string(tmp.path().join("tail.cylinders")).unwrap();
    let toml = std::fs::read_to_string(tmp.path().join("wagging-tail.toml")).unwrap();
    let bad_toml = toml.replace("\"tail.cylinders\"", "\"bad.cylinders\"");
    assert_eq!(
        error(&cylinders.replace("parent base", "parent hip"), &bad_toml),
        "error: bad.toml:7: body.cylinders: bad.cylinders:6: parent 'hip' must be declared before 'tip'"
    );
    assert_eq!(
        error(
            &cylinders.replace("measured girth", "measured waist"),
            &bad_toml
        ),
        "error: bad.toml:7: body.cylinders: bad.cylinders:5: the growth table has no column 'waist' (it has length, girth)"
    );
    assert_eq!(
        error(
            &cylinders,
            &toml.replace("[body]\n", "[body]\nmodel = \"horse\"\n")
        ),
        "error: bad.toml:6: body.model: a built-in body or your own mesh and cylinders, not both (remove model, or mesh and cylinders)"
    );
}

/// The command line's `--mesh`/`--cylinders` go through the same readers
/// and checks as a scenario file's: the preset's growth table has no column
/// the user's cylinders measure.
#[test]
fn a_body_given_on_the_command_line_is_checked_alike() {
    let tmp = folder_with_the_tail();
    assert_eq!(
        refused(
            &[
                "run",
                "horse-growth",
                "--mesh",
                "tail.obj",
                "--cylinders",
                "tail.cylinders",
            ],
            tmp.path(),
        ),
        "error: tail.cylinders:4: the growth table has no column 'length' (it has elbow-to-ground, cannon-diameter, hind-leg, head-width)"
    );
}

/// Lengths the cylinders' features cannot have are refused naming the
/// cylinder and the age of the frame that meets them.
#[test]
fn lengths_a_cylinder_cannot_have_are_named_with_its_age() {
    let tmp = tempfile::tempdir().unwrap();
    assert_eq!(
        refused(
            &[
                "run",
                "cow-trot",
                "--set",
                "body.table.columns[0].values[3]=30000",
            ],
            tmp.path(),
        ),
        "error: cow-trot: body: cylinder 'torso' at age 3.00 months: the measured lengths give a \
         negative L² or R²"
    );
}

/// A folder holding the example skeleton, `wishbone.lsys`.
fn folder_with_the_wishbone() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(
        examples().join("wishbone.lsys"),
        tmp.path().join("wishbone.lsys"),
    )
    .unwrap();
    tmp
}

/// long-bone's fixture stream.
fn long_bone_fixture() -> Vec<u8> {
    std::fs::read(fixtures().join("long-bone/stream.bin")).unwrap()
}

/// A user's skeleton: `--grammar` with a bone preset wraps it with the
/// preset's shrinkwrap, as `--set bones.grammar=` (a file relative to the
/// current folder, even on a built-in), a scenario file naming it, and a
/// sweep over skeletons do.
#[test]
fn a_user_skeleton_is_wrapped_by_a_bone_preset() {
    let tmp = folder_with_the_wishbone();
    let dir = tmp.path();
    runs(
        &[
            "run",
            "long-bone",
            "--grammar",
            "wishbone.lsys",
            "--out",
            "a",
            "-q",
        ],
        dir,
    );
    runs(
        &[
            "run",
            "long-bone",
            "--set",
            "bones.grammar=wishbone.lsys",
            "--out",
            "b",
            "-q",
        ],
        dir,
    );
    let scenario = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios/long-bone.toml"),
    )
    .unwrap()
    .replace("\"../grammars/long-bone.lsys\"", "\"wishbone.lsys\"");
    std::fs::write(dir.join("wishbone.toml"), scenario).unwrap();
    runs(&["run", "wishbone.toml", "--out", "c", "-q"], dir);
    assert_eq!(stream_in(dir, "a"), stream_in(dir, "b"));
    assert_eq!(stream_in(dir, "a"), stream_in(dir, "c"));
    check_the_wishbones_skeleton(dir, "a");
    check_a_sweep_over_skeletons(dir, &stream_in(dir, "a"));
}

/// The run in `out` is not long-bone's, and its skeleton is the
/// wishbone's: 8 steps, and 15 elements (two arms of 6 segments, the keel
/// and two knobs).
fn check_the_wishbones_skeleton(dir: &Path, out: &str) {
    assert_ne!(stream_in(dir, out), long_bone_fixture());
    let summary = std::fs::read_to_string(dir.join(out).join("summary.txt")).unwrap();
    assert!(
        summary
            .lines()
            .any(|l| l.split_whitespace().take(3).eq(["0", "8", "15"])),
        "{summary}"
    );
}

/// A sweep over skeletons reads each as a run does (the wishbone's run
/// gave `wishbone`); its table keeps their names.
fn check_a_sweep_over_skeletons(dir: &Path, wishbone: &[u8]) {
    std::fs::copy(
        grammars().join("long-bone.lsys"),
        dir.join("long-bone.lsys"),
    )
    .unwrap();
    runs(
        &[
            "sweep",
            "long-bone",
            "--set",
            "bones.grammar=wishbone.lsys,long-bone.lsys",
            "--out",
            "sweep",
        ],
        dir,
    );
    let table = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    assert!(
        table.contains("\n0,wishbone.lsys,") && table.contains("\n1,long-bone.lsys,"),
        "{table}"
    );
    assert_eq!(stream_in(dir, "sweep/run-00000"), wishbone);
    assert_eq!(stream_in(dir, "sweep/run-00001"), long_bone_fixture());
}

/// An absolute path on a built-in reads that file: long-bone's own grammar
/// gives long-bone's fixture, by `--set` and by `--grammar`.
#[test]
fn an_absolute_grammar_path_on_a_built_in_reads_that_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let own = grammars().join("long-bone.lsys");
    runs(
        &[
            "run",
            "long-bone",
            "--set",
            &format!("bones.grammar={}", own.display()),
            "--out",
            "d",
            "-q",
        ],
        dir,
    );
    assert_eq!(stream_in(dir, "d"), long_bone_fixture());
    runs(
        &[
            "run",
            "long-bone",
            "--grammar",
            own.to_str().unwrap(),
            "--out",
            "e",
            "-q",
        ],
        dir,
    );
    assert_eq!(stream_in(dir, "e"), long_bone_fixture());
}

/// A skeleton's mistakes name the grammar file, its line and column, under
/// the flag or key that gave it; a grammar on a preset that takes none, and
/// a file that is not there, are named too.
#[test]
fn a_skeletons_mistakes_are_named_by_its_grammar_file() {
    let tmp = tempfile::tempdir().unwrap();
    let error = |text: &str, args: &[&str]| {
        std::fs::write(tmp.path().join("bad.lsys"), text).unwrap();
        refused(args, tmp.path())
    };
    let unclosed = "n = 3\naxiom: F(1)\nF(l) -> F(l * 1.1\n";
    assert_eq!(
        error(unclosed, &["run", "long-bone", "--grammar", "bad.lsys"]),
        "error: long-bone with --grammar: bad.lsys:3:18: expected `,` or `)`"
    );
    assert_eq!(
        error(
            unclosed,
            &["run", "long-bone", "--set", "bones.grammar=bad.lsys"]
        ),
        "error: --set bones.grammar=bad.lsys: bones.grammar: bad.lsys:3:18: expected `,` or `)`"
    );
    assert_eq!(
        error(
            "n = 1\naxiom: F(1)\ninterpretation:\nF(l) -> F(l) O(0.2)\n",
            &["run", "long-bone", "--grammar", "bad.lsys"]
        ),
        "error: long-bone with --grammar: bad.lsys: `interpretation:` rules change only a plant's \
         drawing; a skeleton is the derived string itself, so a bone grammar cannot have them"
    );
    assert_eq!(
        error(unclosed, &["run", "ram-horn", "--grammar", "bad.lsys"]),
        "error: --grammar with a preset needs an L-system or a bone preset, and 'ram-horn' is \
         neither (or give no preset to run the grammar on its own)"
    );
    assert_eq!(
        error(
            unclosed,
            &["run", "long-bone", "--set", "bones.grammar=missing.lsys"]
        ),
        "error: --set bones.grammar=missing.lsys: cannot read missing.lsys: No such file or directory (os error 2)"
    );
}

/// Frames past the grammar's n, and a first sphere the mesh cannot hold,
/// are refused before the run, with what is allowed.
#[test]
fn frames_and_spheres_a_bone_preset_cannot_have_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let set = |kv: &str| refused(&["run", "bone-growth", "--set", kv], tmp.path());
    assert_eq!(
        set("bones.frames.every_step_from=13"),
        "error: --set bones.frames.every_step_from=13: bones.frames.every_step_from: 13 is out of \
         range (allowed: 0 to 12)"
    );
    assert_eq!(
        set("bones.wrap.parallels=51"),
        "error: --set bones.wrap.parallels=51: bones.wrap.parallels: 51 parallels of 24 meridians \
         make a sphere of 1226 vertices, more than the shrinkwrap mesh holds (MCU_VERTICES = \
         1200; allowed with 24 meridians: 1 to 49)"
    );
}

/// An L-system preset takes a user's grammar the same way, with its
/// settings, and draws it.
#[test]
fn an_lsystem_preset_takes_a_user_grammar() {
    let tmp = folder_with_the_wishbone();
    runs(
        &[
            "run",
            "abop-shrub",
            "--grammar",
            "wishbone.lsys",
            "--out",
            "f",
            "-q",
        ],
        tmp.path(),
    );
    assert!(tmp.path().join("f/plant.png").exists());
}

#[test]
fn sweeps_do_not_depend_on_threads_or_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "growth-curve",
            "--set",
            "curve.days=100,200",
            "--set",
            "curve.growth.width=10,22",
            "--set",
            "seed=1..2",
        ];
        args.extend_from_slice(extra);
        let o = morphogen(&args, tmp.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    sweep(&["--out", "one", "--jobs", "1"]);
    sweep(&["--out", "two", "--jobs", "2"]);
    sweep(&["--out", "a", "--shard", "1/2"]);
    sweep(&["--out", "b", "--shard", "2/2"]);
    let o = morphogen(
        &["sweep", "--merge", "a", "b", "--out", "merged"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = |d: &str| std::fs::read_to_string(tmp.path().join(d).join("sweep.csv")).unwrap();
    let one = read("one");
    assert_eq!(one.lines().count(), 9, "{one}");
    assert_eq!(one, read("two"));
    assert_eq!(one, read("merged"));
    assert_ne!(read("a"), one);
}

#[test]
fn a_smaller_sweep_into_the_same_folder_removes_the_earlier_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = |seeds: &str| {
        let o = morphogen(
            &["sweep", "growth-curve", "--set", seeds, "--out", "s"],
            tmp.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    sweep("seed=1..4");
    let said = sweep("seed=1..2");
    assert!(
        said.contains(
            "removed an earlier sweep's run-00002 … run-00003 (2 folders), not in sweep.csv"
        ),
        "{said}"
    );
    let mut names: Vec<String> = std::fs::read_dir(tmp.path().join("s"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            ".morphogen.lock",
            "run-00000",
            "run-00001",
            "sweep.csv",
            "sweep.toml"
        ]
    );
    // A folder of the user's that no table listed stays.
    std::fs::create_dir(tmp.path().join("s/run-00005")).unwrap();
    sweep("seed=1..3");
    sweep("seed=1..2");
    assert!(tmp.path().join("s/run-00005").is_dir());
    assert!(!tmp.path().join("s/run-00002").exists());
}

#[test]
fn only_shards_of_one_sweep_merge_and_every_row_is_checked() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let o = morphogen(args, tmp.path());
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        (o.status.code(), text)
    };
    let shard = |days: &str, i: &str, out: &str| {
        let (code, text) = run(&[
            "sweep",
            "growth-curve",
            "--set",
            days,
            "--set",
            "seed=1..2",
            "--shard",
            i,
            "--out",
            out,
        ]);
        assert_eq!(code, Some(0), "{text}");
    };
    shard("curve.days=100,200", "1/2", "a");
    shard("curve.days=100,200", "2/2", "b");
    shard("curve.days=100,300", "2/2", "c");
    let (code, text) = run(&["sweep", "--merge", "a", "c", "--out", "m"]);
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("is a shard of another sweep"), "{text}");
    // An edited digest is found against the run's stream.
    let table = tmp.path().join("b/sweep.csv");
    let clean = std::fs::read_to_string(&table).unwrap();
    let row = clean.lines().nth(1).unwrap();
    let digest = row.split(',').nth(5).unwrap();
    std::fs::write(&table, clean.replacen(digest, "0123456789abcdef", 1)).unwrap();
    let (code, text) = run(&["sweep", "--merge", "a", "b", "--out", "m"]);
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("row is not what its stream"), "{text}");
    std::fs::write(&table, &clean).unwrap();
    // Merged into one of the shards: it holds every run its table lists.
    let (code, text) = run(&["sweep", "--merge", "a", "b", "--out", "a"]);
    assert_eq!(code, Some(0), "{text}");
    let merged = std::fs::read_to_string(tmp.path().join("a/sweep.csv")).unwrap();
    assert_eq!(merged.lines().count(), 5, "{merged}");
    for k in 0..4 {
        assert!(
            tmp.path()
                .join(format!("a/run-0000{k}/stream.bin"))
                .is_file()
        );
    }
    // A key set twice is refused, not half-used.
    let (code, text) = run(&[
        "sweep",
        "growth-curve",
        "--set",
        "curve.days=10,20",
        "--set",
        "curve.days=30",
        "--out",
        "d",
    ]);
    assert_eq!(code, Some(2), "{text}");
    assert!(text.contains("--set curve.days is given twice"), "{text}");
}

/// A combination that cannot run stops the sweep before any runs, named.
#[test]
fn a_sweep_names_the_combination_that_cannot_run() {
    let tmp = tempfile::tempdir().unwrap();
    let o = morphogen(
        &[
            "sweep",
            "croton",
            "--set",
            "mosaic.days=40,1",
            "--set",
            "seed=1,2",
            "--out",
            "s",
        ],
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with("error: the combination mosaic.days=1 seed=1: ")
            && err.contains("day 10 is past the run's last day, mosaic.days = 1"),
        "{err}"
    );
    assert!(!tmp.path().join("s").exists(), "nothing ran");
}

#[test]
fn every_example_in_the_scenario_docs_runs() {
    let docs =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scenarios.md"))
            .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    // The bones example names its grammar relative to docs/.
    std::fs::create_dir_all(tmp.path().join("docs")).unwrap();
    std::fs::create_dir_all(tmp.path().join("grammars")).unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammars/long-bone.lsys"),
        tmp.path().join("grammars/long-bone.lsys"),
    )
    .unwrap();
    // The user-body example names its mesh and cylinders beside it.
    for file in ["tail.obj", "tail.cylinders"] {
        std::fs::copy(examples().join(file), tmp.path().join("docs").join(file)).unwrap();
    }
    let blocks: Vec<&str> = docs
        .split("```toml\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap())
        .collect();
    let mut models = std::collections::BTreeSet::new();
    for (i, block) in blocks.iter().enumerate() {
        let file = tmp.path().join(format!("docs/example-{i}.toml"));
        std::fs::write(&file, block).unwrap();
        let s = Scenario::load(&file, &[]).unwrap_or_else(|e| panic!("example {i}: {e}"));
        models.insert(format!("{:?}", std::mem::discriminant(s.checked())));
        let o = morphogen(
            &["run", file.to_str().unwrap(), "--out", &format!("o{i}")],
            tmp.path(),
        );
        assert!(
            o.status.success(),
            "example {i}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    assert_eq!(models.len(), 6, "one example per model");
    let tail = std::fs::read_to_string(examples().join("wagging-tail.toml")).unwrap();
    assert!(
        blocks.contains(&tail.as_str()),
        "docs/scenarios.md shows examples/wagging-tail.toml as it is"
    );
}

#[test]
fn a_seed_that_changes_nothing_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let o = morphogen(&["run", "growth-curve", "--seed", "4"], tmp.path());
    assert!(o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .contains("warning: --seed has no effect on growth-curve"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = morphogen(&["run", "abop-stochastic", "--seed", "4"], tmp.path());
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
}

/// The repository's `grammars/` folder.
fn grammars() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammars")
}

/// A grammar constant set from outside (`--set lsystem.delta=30`) changes
/// the run, as the same constant in a scenario file, and in the grammar
/// itself, would.
#[test]
fn a_grammar_constant_set_from_outside_changes_the_run_as_the_grammar_would() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    runs(&["run", "abop-shrub", "--out", "preset"], dir);
    runs(
        &[
            "run",
            "abop-shrub",
            "--set",
            "lsystem.delta=30",
            "--out",
            "set",
        ],
        dir,
    );
    let grammar = grammars().join("abop-shrub.lsys");
    std::fs::write(
        dir.join("shrub-30.toml"),
        format!(
            "name = \"abop-shrub\"\n[lsystem]\ngrammar = {:?}\ndelta = 30\n",
            grammar.to_str().unwrap()
        ),
    )
    .unwrap();
    runs(&["run", "shrub-30.toml", "--out", "file"], dir);
    let edited = std::fs::read_to_string(&grammar)
        .unwrap()
        .replace("delta = 22.5", "delta = 30");
    std::fs::write(dir.join("shrub-30.lsys"), edited).unwrap();
    runs(
        &[
            "run",
            "abop-shrub",
            "--grammar",
            "shrub-30.lsys",
            "--out",
            "edited",
        ],
        dir,
    );
    assert_ne!(stream_in(dir, "set"), stream_in(dir, "preset"));
    assert_eq!(stream_in(dir, "set"), stream_in(dir, "file"));
    assert_eq!(stream_in(dir, "set"), stream_in(dir, "edited"));
}

/// A sweep over a grammar constant: one run per value, each its own
/// digest, each row naming the Morphogen that ran it.
#[test]
fn a_sweep_over_a_grammar_constant_runs_each_value() {
    let tmp = tempfile::tempdir().unwrap();
    runs(
        &[
            "sweep",
            "abop-2d-plant",
            "--set",
            "lsystem.delta=20,25,30",
            "--set",
            "lsystem.n=2",
            "--out",
            "sweep",
        ],
        tmp.path(),
    );
    let table = std::fs::read_to_string(tmp.path().join("sweep/sweep.csv")).unwrap();
    check_one_digest_per_value(&table);
    let version = String::from_utf8(morphogen(&["--version"], tmp.path()).stdout).unwrap();
    check_each_row_names_its_morphogen(&table, version.trim());
}

/// The sweep table of three values holds three different stream digests.
fn check_one_digest_per_value(table: &str) {
    let column = table
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "stream_digest")
        .unwrap();
    let digests: std::collections::BTreeSet<&str> = table
        .lines()
        .skip(1)
        .map(|row| row.split(',').nth(column).unwrap())
        .collect();
    assert_eq!(digests.len(), 3, "{table}");
}

/// The sweep table's last column is `morphogen`, and every row holds the
/// version that `morphogen --version` prints.
fn check_each_row_names_its_morphogen(table: &str, version: &str) {
    assert!(table.starts_with("run,") && table.lines().next().unwrap().ends_with(",morphogen"));
    assert!(
        table
            .lines()
            .skip(1)
            .all(|row| row.ends_with(&format!(",{version}"))),
        "{table}"
    );
}

/// An unknown grammar constant is refused, with the closest name.
#[test]
fn an_unknown_grammar_constant_is_refused_with_the_closest_name() {
    let tmp = tempfile::tempdir().unwrap();
    let o = morphogen(
        &["run", "abop-shrub", "--set", "lsystem.detla=30"],
        tmp.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains(
            "--set lsystem.detla=30: lsystem.detla: unknown setting or constant (did you mean `delta`?)"
        ),
        "{stderr}"
    );
}

#[test]
fn input_that_would_do_nothing_is_refused_naming_it() {
    let tmp = tempfile::tempdir().unwrap();
    let refused = |args: &[&str]| {
        let o = morphogen(args, tmp.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    // A misspelt setting in a grammar file.
    std::fs::write(
        tmp.path().join("detla.lsys"),
        "n = 3\ndetla = 30\naxiom: F\nF -> F[+F]F\n",
    )
    .unwrap();
    let stderr = refused(&["run", "--grammar", "detla.lsys"]);
    assert!(
        stderr.contains("detla.lsys:2:1: unknown setting `detla`: did you mean `delta`?"),
        "{stderr}"
    );
    // Plant settings in a skeleton.
    std::fs::write(
        tmp.path().join("plants.lsys"),
        "n = 3\nplants = 3\naxiom: F\nF -> FF\n",
    )
    .unwrap();
    let stderr = refused(&["run", "long-bone", "--grammar", "plants.lsys"]);
    assert!(
        stderr.contains("plants.lsys:2: `plants` applies only to L-system plant presets"),
        "{stderr}"
    );
    // Initial probabilities past 1, and a mutation row past 1.
    let stderr = refused(&[
        "run",
        "croton-mcu",
        "--set",
        "mosaic.types[0].initial_probability=0.9",
    ]);
    assert!(
        stderr.contains("the initial probabilities sum to"),
        "{stderr}"
    );
    let stderr = refused(&[
        "run",
        "croton-mcu",
        "--set",
        "mosaic.mutation=[[0, 0.9], [0, 0]]",
        "--set",
        "mosaic.mutation[1][1]=0.5",
    ]);
    assert!(
        stderr.contains("mosaic.mutation[1][1]: 0.5 on the diagonal: the diagonal is the probability of not mutating"),
        "{stderr}"
    );
}
