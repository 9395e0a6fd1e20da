//! The `morphogen` binary end to end: outputs, exit codes, fixtures.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use morphogen::stream::{Decoder, Record};
use morphogen_cli::outputs::mosaic;
use morphogen_cli::{exec, fixture};
use morphogen_stream_text::verify;
use tiny_skia::{ColorU8, Pixmap};

/// `morphogen ARGS`, outside CI (whose variables change what `verify`
/// writes and prints).
fn morphogen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(args)
        .env_remove("CI")
        .env_remove("GITHUB_ACTIONS")
        .output()
        .expect("run morphogen")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn workspace_fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// A private copy of the growth-curve fixture.
fn fixture_copy(tmp: &Path) -> PathBuf {
    fixture_copy_of(tmp, "growth-curve")
}

/// A fixtures folder in `tmp` that holds a copy of `name`'s fixture alone.
fn fixture_copy_of(tmp: &Path, name: &str) -> PathBuf {
    let dir = tmp.join("fixtures").join(name);
    fs::create_dir_all(&dir).unwrap();
    for f in [fixture::STREAM_FILE, fixture::SUMMARY_FILE] {
        fs::copy(workspace_fixtures().join(name).join(f), dir.join(f)).unwrap();
    }
    tmp.join("fixtures")
}

#[test]
fn list_names_every_preset() {
    let o = morphogen(&["list"]);
    assert!(o.status.success());
    for p in morphogen_scenario::builtins() {
        assert!(
            text(&o).contains(p.name()),
            "{} missing from list",
            p.name()
        );
    }
    // The big mosaics are host presets, marked as such; croton-mcu is not.
    let line = |name: &str| {
        text(&o)
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("{name} missing from list"))
            .to_string()
    };
    assert!(line("sansevieria").contains("(host only: "));
    assert!(!line("croton-mcu").contains("(host only: "));
}

#[test]
fn run_writes_stream_jsonl_and_model_files_and_decode_reproduces_jsonl() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("gc");
    let o = morphogen(&["run", "growth-curve", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    for f in ["stream.bin", "records.jsonl", "growth.csv", "growth.png"] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    let decoded = morphogen(&["decode", out.join("stream.bin").to_str().unwrap()]);
    assert!(decoded.status.success());
    assert_eq!(decoded.stdout, fs::read(out.join("records.jsonl")).unwrap());
    let csv = fs::read_to_string(out.join("growth.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 366);
}

#[test]
fn verify_passes_on_the_workspace_fixtures() {
    // One preset per model, unoptimised; scripts/check.sh verifies all of
    // them with a release build.
    let probes = [
        "growth-curve",
        "ram-horn",
        "abop-shrub",
        "horse-growth",
        "croton-mcu",
        "philodendron",
    ];
    let mut args = vec!["verify"];
    args.extend(probes);
    let o = morphogen(&args);
    assert!(o.status.success(), "{}", text(&o));
    for p in probes {
        assert!(
            text(&o).contains(&format!("ok        {p} ")),
            "{p}: {}",
            text(&o)
        );
    }
}

#[test]
fn flipping_any_byte_of_a_fixture_is_a_mismatch_naming_the_record() {
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = fixture_copy_of(tmp.path(), "lsys-flower");
    let stream_path = fixtures.join("lsys-flower/stream.bin");
    let clean = fs::read(&stream_path).unwrap();
    let preset = exec::find("lsys-flower", &[]).unwrap();
    let run = exec::run(&preset, 0, false).unwrap();
    assert_eq!(run.stream, clean);
    // Every byte, in process: the comparison names a record at or before it
    // (a small fixture of every kind of record a plant has: each
    // comparison decodes up to its byte).
    for i in 0..clean.len() {
        let mut flipped = clean.clone();
        flipped[i] ^= 0x01;
        let diff = verify::compare(&flipped, &run.stream)
            .unwrap_or_else(|| panic!("flip at {i} unnoticed"));
        assert!(
            diff.offset <= i,
            "flip at byte {i} reported at byte {}",
            diff.offset
        );
    }
    // A sample through the binary: exit 1 and the record named. The
    // fixture's summary is made to match the flipped stream (a fixture of
    // other code); a stream that does not match its own summary is a
    // corrupt fixture instead (exit 2).
    let summary_path = fixtures.join("lsys-flower/summary.toml");
    let summary = fs::read_to_string(&summary_path).unwrap();
    for i in [0, 1, 17, clean.len() / 2, clean.len() - 2, clean.len() - 1] {
        let mut flipped = clean.clone();
        flipped[i] ^= 0x80;
        fs::write(&stream_path, &flipped).unwrap();
        fs::write(&summary_path, &summary).unwrap();
        let corrupt = morphogen(&[
            "verify",
            "lsys-flower",
            "--fixtures",
            fixtures.to_str().unwrap(),
        ]);
        assert_eq!(
            corrupt.status.code(),
            Some(2),
            "flip at {i}: {}",
            text(&corrupt)
        );
        assert!(
            text(&corrupt).contains("fixture corrupt"),
            "{}",
            text(&corrupt)
        );
        let digest = format!("{:016x}", morphogen::stream::StreamDigest::of(&flipped));
        let old = summary
            .lines()
            .find(|l| l.starts_with("stream_digest"))
            .unwrap();
        fs::write(
            &summary_path,
            summary.replace(old, &format!("stream_digest = \"{digest}\"")),
        )
        .unwrap();
        let o = morphogen(&[
            "verify",
            "lsys-flower",
            "--fixtures",
            fixtures.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1), "flip at {i}: {}", text(&o));
        assert!(
            text(&o).contains("MISMATCH  lsys-flower: first difference"),
            "{}",
            text(&o)
        );
        assert!(text(&o).contains("expected:") && text(&o).contains("actual:"));
    }
}

#[test]
fn a_capture_with_a_flipped_bit_names_the_preset_and_frame() {
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = fixture_copy(tmp.path());
    let clean = fs::read(fixtures.join("growth-curve/stream.bin")).unwrap();
    let mut capture = clean.clone();
    capture.extend_from_slice(&clean); // two streams back to back
    let path = tmp.path().join("capture.bin");
    fs::write(&path, &capture).unwrap();
    let o = morphogen(&[
        "verify",
        "--stream",
        path.to_str().unwrap(),
        "--fixtures",
        fixtures.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("2 stream(s)"));
    capture[clean.len() + clean.len() / 2] ^= 0x04;
    fs::write(&path, &capture).unwrap();
    let o = morphogen(&[
        "verify",
        "--stream",
        path.to_str().unwrap(),
        "--fixtures",
        fixtures.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("MISMATCH  growth-curve"), "{}", text(&o));
    assert!(
        text(&o).contains("first difference in frame 0"),
        "{}",
        text(&o)
    );
}

#[test]
fn bad_input_exits_2_with_a_message_and_no_backtrace() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let file = t.join("file");
    fs::write(&file, b"not a folder").unwrap();
    let junk = t.join("junk.bin");
    fs::write(&junk, [1u8, 2, 3, 0, 9, 9]).unwrap();
    let broken = fixture_copy(t);
    fs::write(broken.join("growth-curve/summary.toml"), "preset = ").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["run".into(), "no-such-preset".into()],
            "unknown preset 'no-such-preset'",
        ),
        (
            vec![
                "verify".into(),
                "--fixtures".into(),
                t.join("absent").display().to_string(),
            ],
            "cannot read the fixtures folder",
        ),
        (
            vec![
                "verify".into(),
                "growth-curve".into(),
                "--fixtures".into(),
                broken.display().to_string(),
            ],
            "summary.toml is not a valid fixture summary",
        ),
        (
            vec![
                "run".into(),
                "growth-curve".into(),
                "--out".into(),
                file.join("sub").display().to_string(),
            ],
            "cannot create output folder",
        ),
        (
            vec!["decode".into(), t.join("absent.bin").display().to_string()],
            "cannot read",
        ),
        (
            vec!["decode".into(), junk.display().to_string()],
            "corrupt or truncated frame",
        ),
        (
            vec![
                "verify".into(),
                "--stream".into(),
                t.join("absent.bin").display().to_string(),
            ],
            "cannot read capture",
        ),
        (
            vec![
                "verify".into(),
                "growth-curve".into(),
                "--jobs".into(),
                "100000".into(),
            ],
            "100000 is not in 1..=256",
        ),
        (vec!["frobnicate".into()], "unrecognized subcommand"),
    ];
    for (args, message) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = morphogen(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains(message), "{args:?}: {}", text(&o));
        assert!(!text(&o).contains("panicked"), "{args:?}: {}", text(&o));
    }
}

#[test]
fn bless_writes_what_verify_accepts() {
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = tmp.path().join("fx");
    let o = morphogen(&[
        "bless",
        "growth-curve",
        "--fixtures",
        fixtures.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        fs::read(fixtures.join("growth-curve/stream.bin")).unwrap(),
        fs::read(workspace_fixtures().join("growth-curve/stream.bin")).unwrap()
    );
    let leftovers: Vec<_> = fs::read_dir(fixtures.join("growth-curve"))
        .unwrap()
        .collect();
    assert_eq!(leftovers.len(), 2, "temporary files left behind");
}

/// The records of a stream.
fn records(stream: &[u8]) -> Vec<Record> {
    Decoder::new(stream).filter_map(|d| d.result.ok()).collect()
}

/// F (type 1) cells on the last day of a mosaic stream.
fn last_day_f_cells(stream: &[u8]) -> usize {
    let days = mosaic::days(&records(stream));
    let last = days.last().expect("a mosaic streams days");
    last.cells.iter().filter(|c| c.1 == 1).count()
}

#[test]
fn an_all_black_mask_starts_no_f_cells() {
    let tmp = tempfile::tempdir().unwrap();
    let black = tmp.path().join("black.pbm");
    fs::write(&black, "P1\n3 2\n1 1 1\n1 1 1\n").unwrap();
    let out = tmp.path().join("out");
    let o = morphogen(&[
        "run",
        "croton-mcu",
        "--mask",
        black.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let csv = fs::read_to_string(out.join("cells_day35.csv")).unwrap();
    let kinds: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    assert!(kinds.len() > 1000, "{} cells", kinds.len());
    assert!(
        kinds.iter().all(|k| *k == "0"),
        "F cells under a black mask"
    );
    assert_eq!(
        fs::read_to_string(out.join("mask.pbm")).unwrap(),
        "P1\n# morphogen mosaic mask: white (0) allows foreground cells\n3 2\n1 1 1\n1 1 1\n"
    );
    let builtin = exec::run(&exec::find("croton-mcu", &[]).unwrap(), 1, false).unwrap();
    assert!(last_day_f_cells(&builtin.stream) > 100);
}

#[test]
fn a_png_mask_runs_like_the_same_pbm_mask() {
    let tmp = tempfile::tempdir().unwrap();
    // 5 × 4: white where 3 divides x + 2y; in the PNG, white and black
    // each in two colours either side of the 50 % thresholds.
    let white = |x: u32, y: u32| (x + 2 * y).is_multiple_of(3);
    let mut pbm = String::from("P1\n5 4\n");
    let mut png = Pixmap::new(5, 4).unwrap();
    for y in 0..4 {
        for x in 0..5 {
            pbm.push_str(if white(x, y) { "0 " } else { "1 " });
            let [r, g, b, a] = match (white(x, y), x % 2) {
                (true, 0) => [0, 255, 0, 255],
                (true, _) => [200, 200, 200, 200],
                (false, 0) => [255, 0, 0, 255],
                (false, _) => [255, 255, 255, 100],
            };
            png.pixels_mut()[(y * 5 + x) as usize] = ColorU8::from_rgba(r, g, b, a).premultiply();
        }
    }
    let (pbm_path, png_path) = (tmp.path().join("m.pbm"), tmp.path().join("m.png"));
    fs::write(&pbm_path, pbm).unwrap();
    png.save_png(&png_path).unwrap();
    let croton = exec::find("croton-mcu", &[]).unwrap();
    let run = |path: &Path| exec::run(&exec::with_mask(&croton, path).unwrap(), 1, false).unwrap();
    let (from_pbm, from_png) = (run(&pbm_path), run(&png_path));
    assert_eq!(from_pbm.stream, from_png.stream);
    // The mask takes effect, and the header's digest is of the new params.
    let builtin = exec::run(&croton, 1, false).unwrap();
    assert!(last_day_f_cells(&from_png.stream) < last_day_f_cells(&builtin.stream) / 2);
    let masked = exec::with_mask(&croton, &png_path).unwrap();
    let digest = |s: &morphogen_scenario::Scenario| s.with_preset(|p| p.model.params_digest());
    let Some(Record::Header(h)) = records(&from_png.stream).first().cloned() else {
        panic!("no header");
    };
    assert_eq!(
        (h.preset.as_str(), h.params),
        ("croton-mcu", digest(&masked))
    );
    assert_ne!(h.params, digest(&croton));
    // Another mosaic takes a mask too, its other parameters kept.
    let mosaic = |s: &morphogen_scenario::Scenario| match s.checked() {
        morphogen_scenario::Checked::Mosaic { params, mask, .. } => (params.domain, mask.clone()),
        _ => panic!("not a mosaic"),
    };
    let watermelon = exec::find("watermelon", &[]).unwrap();
    let with = exec::with_mask(&watermelon, &png_path).unwrap();
    assert_eq!(with.name(), "watermelon");
    assert_eq!(mosaic(&with).1, mosaic(&masked).1);
    assert_eq!(mosaic(&with).0, mosaic(&watermelon).0);
}

#[test]
fn mask_errors_exit_2_naming_the_problem() {
    let tmp = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let path = tmp.path().join(name);
        fs::write(&path, bytes).unwrap();
        path.display().to_string()
    };
    let good = file("good.pbm", b"P1\n1 1\n0\n");
    let wide_png = tmp.path().join("wide.png");
    Pixmap::new(70_000, 1).unwrap().save_png(&wide_png).unwrap();
    let cases = [
        (
            "growth-curve",
            good.clone(),
            "--mask needs a mosaic preset, and 'growth-curve' is not one",
        ),
        (
            "croton-mcu",
            tmp.path().join("absent.pbm").display().to_string(),
            "cannot read mask",
        ),
        (
            "croton-mcu",
            file("bad.pbm", b"P1\n2 2\n0 1 2 0"),
            "PBM: pixel 2 (byte 11): 2 is not 0 or 1",
        ),
        (
            "croton-mcu",
            file("short.pbm", b"P4\n9 2\n\x00"),
            "raster needs 4 bytes",
        ),
        (
            "croton-mcu",
            file("bad.png", b"\x89PNG\r\n\x1a\ngarbage"),
            "PNG: cannot decode",
        ),
        (
            "croton-mcu",
            file("huge.pbm", b"P1\n70000 1\n"),
            "70000×1 pixels (allowed: sides of 1 to at most 65535)",
        ),
        (
            "croton-mcu",
            wide_png.display().to_string(),
            "70000×1 pixels (allowed: sides of 1 to at most 65535)",
        ),
    ];
    for (preset, mask, message) in cases {
        let o = morphogen(&[
            "run",
            preset,
            "--mask",
            &mask,
            "--out",
            tmp.path().to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{mask}: {}", text(&o));
        assert!(text(&o).contains(message), "{mask}: {}", text(&o));
        assert!(!text(&o).contains("panicked"), "{mask}: {}", text(&o));
    }
    let o = morphogen(&["run", "--grammar", &good, "--mask", &good]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("cannot be used with"), "{}", text(&o));
}

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_exit_2() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let shrub = workspace_fixtures().join("abop-shrub/stream.bin");
    for args in [
        vec!["decode", shrub.to_str().unwrap()],
        vec!["list"],
        vec!["show", "ram-horn"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_morphogen"))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(!first.is_empty());
        // The reader is gone: the rest of the output meets a closed pipe.
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", text(&o));
        assert!(!text(&o).contains("panicked"), "{args:?}: {}", text(&o));
    }
    if Path::new("/dev/full").exists() {
        for args in [vec!["list"], vec!["decode", shrub.to_str().unwrap()]] {
            let o = Command::new(env!("CARGO_BIN_EXE_morphogen"))
                .args(&args)
                .stdout(fs::File::create("/dev/full").unwrap())
                .output()
                .unwrap();
            assert_eq!(o.status.code(), Some(2), "{args:?}");
            assert!(
                text(&o).contains("cannot write to standard output"),
                "{args:?}: {}",
                text(&o)
            );
        }
    }
}

#[test]
fn bless_replaces_a_fixture_whole_and_cleans_what_a_kill_left() {
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = tmp.path().join("fx");
    let fx = fixtures.to_str().unwrap();
    // What a bless killed mid-way leaves: a hidden staging folder with a
    // half fixture in it, untouched for a while.
    let stale = fixtures.join(".morphogen-bless-killed");
    fs::create_dir_all(&stale).unwrap();
    fs::write(stale.join("stream.bin"), b"half").unwrap();
    let old = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    fs::File::open(&stale).unwrap().set_modified(old).unwrap();
    // Never read as a fixture.
    let o = morphogen(&["verify", "--fixtures", fx]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("no fixtures in"), "{}", text(&o));
    for seed in ["3", "4"] {
        let o = morphogen(&["bless", "growth-curve", "--seed", seed, "--fixtures", fx]);
        assert!(o.status.success(), "{}", text(&o));
    }
    let mut entries: Vec<String> = fs::read_dir(&fixtures)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    entries.sort();
    assert_eq!(entries, ["growth-curve"], "leftovers beside the fixture");
    let summary = fs::read_to_string(fixtures.join("growth-curve/summary.toml")).unwrap();
    assert!(summary.contains("seed = 4"), "{summary}");
    let o = morphogen(&["verify", "--fixtures", fx]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

#[test]
fn decode_follows_the_stream_format_spec() {
    use morphogen::stream::{Encoder, Header, Sink};
    let tmp = tempfile::tempdir().unwrap();
    let header = |version| {
        Record::Header(Header {
            version,
            preset: "growth-curve".try_into().unwrap(),
            seed: 0,
            params: 1,
        })
    };
    let encode = |records: &[Record]| {
        let mut enc = Encoder::new(Vec::new());
        for r in records {
            enc.record(r).unwrap();
        }
        enc.into_writer()
    };
    // A newer writer's record kind (tag 13) between known ones: skipped.
    let record = [13u8, 5];
    let mut raw = record.to_vec();
    raw.extend_from_slice(
        &crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC)
            .checksum(&record)
            .to_le_bytes(),
    );
    let mut newer = encode(&[header(1)]);
    newer.extend(cobs::encode_vec(&raw));
    newer.push(0);
    newer.extend(encode(&[Record::FrameEnd { frame: 0 }]));
    let path = tmp.path().join("newer.bin");
    fs::write(&path, &newer).unwrap();
    let o = morphogen(&["decode", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        text(&o).contains(r#""kind":"unknown""#) && text(&o).contains(r#""tag":13"#),
        "{}",
        text(&o)
    );
    // Another format version, and an empty file: exit 2, as verify --stream.
    let v2 = tmp.path().join("v2.bin");
    fs::write(&v2, encode(&[header(2)])).unwrap();
    let empty = tmp.path().join("empty.bin");
    fs::write(&empty, b"").unwrap();
    for (file, message) in [(&v2, "format version 2"), (&empty, "holds no frames")] {
        let o = morphogen(&["decode", file.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(message), "{}", text(&o));
        let o = morphogen(&["verify", "--stream", file.to_str().unwrap()]);
        assert_ne!(o.status.code(), Some(0), "{}", text(&o));
    }
}

#[test]
fn runaway_and_unreadable_grammars_stop_with_the_limit_named() {
    let tmp = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let path = tmp.path().join(name);
        fs::write(&path, bytes).unwrap();
        path.display().to_string()
    };
    let runaway = file("runaway.lsys", b"n = 20\naxiom: A\nA -> [F]AA\n");
    let o = morphogen(&[
        "run",
        "--grammar",
        &runaway,
        "--max-stream-mb",
        "4",
        "--out",
        tmp.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("passed 4 MiB") && text(&o).contains("--max-stream-mb"),
        "{}",
        text(&o)
    );
    let o = morphogen(&["run", "growth-curve", "--max-stream-mb", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("'0' for '--max-stream-mb <MB>'"),
        "a cap of 0 MiB stops every run: refused before it starts: {}",
        text(&o)
    );
    let mut big = b"n = 1\naxiom: F\n# ".to_vec();
    big.resize(17 << 20, b'x');
    let big = file("big.lsys", &big);
    let not_utf8 = file("latin1.lsys", b"n = 2\naxiom: F\nF -> F\xe9\n");
    for (grammar, message) in [
        (big.as_str(), "more than 16777216 bytes"),
        (
            not_utf8.as_str(),
            "latin1.lsys:3:7: not UTF-8 text (byte 0xe9)",
        ),
    ] {
        let o = morphogen(&[
            "run",
            "--grammar",
            grammar,
            "--out",
            tmp.path().to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(message), "{}", text(&o));
    }
}

#[test]
fn a_capture_cannot_choose_its_fixture_by_a_path_in_its_name() {
    use morphogen::stream::{Encoder, Header, Sink};
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = fixture_copy(tmp.path());
    for name in ["../fixtures/growth-curve", "/tmp/x", ".hidden", "a/b"] {
        let mut enc = Encoder::new(Vec::new());
        enc.record(&Record::Header(Header {
            version: 1,
            preset: name.try_into().unwrap(),
            seed: 0,
            params: 0,
        }))
        .unwrap();
        enc.record(&Record::FrameEnd { frame: 0 }).unwrap();
        let capture = tmp.path().join("capture.bin");
        fs::write(&capture, enc.into_writer()).unwrap();
        let o = morphogen(&[
            "verify",
            "--stream",
            capture.to_str().unwrap(),
            "--fixtures",
            fixtures.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", text(&o));
        assert!(
            text(&o).contains("is not a fixture name"),
            "{name}: {}",
            text(&o)
        );
    }
}

/// The `.morphogen-*` temporary files in `dir`.
fn temporary(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .map(|entries| {
            entries
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with(".morphogen-"))
                .collect()
        })
        .unwrap_or_default()
}

/// A run into `out` that would last hours (amanita-df20 with 10,000
/// relaxations a day), once its stream's temporary file is there: it is
/// still running then however fast the machine is. The stream is opened
/// as the run starts, so a minute without it is a run that never opens it.
#[cfg(unix)]
fn a_long_run_writing(out: &Path) -> std::process::Child {
    let mut child = Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .args(["run", "amanita-df20", "--quiet", "--out"])
        .arg(out)
        .args(["--set", "mosaic.initial_relaxations=10000"])
        .args(["--set", "mosaic.daily_relaxations=10000"])
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while temporary(out).is_empty() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before its stream was written");
        }
        assert!(started.elapsed().as_secs() < 60, "no stream after 60 s");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child
}

#[cfg(unix)]
#[test]
fn a_run_stopped_by_a_signal_leaves_no_temporary_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let mut child = a_long_run_writing(&out);
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(temporary(&out), Vec::<String>::new());
}

#[test]
fn verifying_a_file_whose_seed_is_not_its_fixtures_says_which_ran() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("mine.toml");
    let fixtures = tmp.path().join("fixtures");
    let (file_arg, fixtures_arg) = (file.to_str().unwrap(), fixtures.to_str().unwrap());
    let shown = morphogen(&["show", "growth-curve"]);
    let shown = String::from_utf8(shown.stdout)
        .unwrap()
        .replace("name = \"growth-curve\"", "name = \"my-curve\"");
    fs::write(&file, &shown).unwrap();
    let o = morphogen(&["bless", file_arg, "--fixtures", fixtures_arg]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    fs::write(&file, shown.replace("\nseed = 0\n", "\nseed = 7\n")).unwrap();
    let o = morphogen(&["verify", file_arg, "--fixtures", fixtures_arg]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let note = format!("note: run with the fixture's seed 0; {file_arg} says seed = 7");
    assert!(text(&o).contains(&note), "{}", text(&o));
    // Verifying the fixtures themselves says nothing of it.
    let o = morphogen(&["verify", "--fixtures", fixtures_arg]);
    assert!(!text(&o).contains("note:"), "{}", text(&o));
}

#[cfg(unix)]
#[test]
fn writers_follow_symlinks_and_write_into_devices_never_replacing_them() {
    let tmp = tempfile::tempdir().unwrap();
    let stream = workspace_fixtures().join("growth-curve/stream.bin");
    let stream = stream.to_str().unwrap();
    // A device is written to, not replaced by a file.
    let o = morphogen(&["decode", stream, "--out", "/dev/null"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let null = fs::symlink_metadata("/dev/null").unwrap();
    assert!(!null.file_type().is_file() && !null.file_type().is_symlink());
    // A symlink to a full device: the write fails, the link stays.
    let full = tmp.path().join("full");
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let o = morphogen(&["decode", stream, "--out", full.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("cannot write"), "{}", text(&o));
    assert!(
        fs::symlink_metadata(&full)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    // A symlink to a file is written through.
    let real = tmp.path().join("real.jsonl");
    fs::write(&real, "old").unwrap();
    let link = tmp.path().join("link.jsonl");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let o = morphogen(&["decode", stream, "--out", link.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(
        fs::read_to_string(&real)
            .unwrap()
            .starts_with("{\"kind\":\"header\",")
    );
    // A folder is refused by name.
    let o = morphogen(&["decode", stream, "--out", tmp.path().to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("it is a folder, not a file"),
        "{}",
        text(&o)
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_device_as_an_input_file_is_refused_by_its_type() {
    let tmp = tempfile::tempdir().unwrap();
    let fifo = tmp.path().join("fifo");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let fifo = fifo.to_str().unwrap();
    let fixtures = workspace_fixtures();
    for args in [
        &["run", fifo][..],
        &["run", "--grammar", fifo],
        &["run", "croton-mcu", "--mask", fifo],
        &["decode", fifo],
        &[
            "verify",
            "--stream",
            fifo,
            "--fixtures",
            fixtures.to_str().unwrap(),
        ],
        &["decode", "/dev/zero"],
        &[
            "verify",
            "--stream",
            "/dev/zero",
            "--fixtures",
            fixtures.to_str().unwrap(),
        ],
    ] {
        // Opening a FIFO without a writer would block: these return.
        let o = morphogen(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(
            text(&o).contains("not a regular file but a FIFO")
                || text(&o).contains("not a regular file but a device"),
            "{args:?}: {}",
            text(&o)
        );
    }
}

#[cfg(unix)]
#[test]
fn one_run_writes_a_folder_at_a_time_and_the_next_removes_what_a_killed_one_left() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let out_arg = out.to_str().unwrap();
    let mut child = a_long_run_writing(&out);
    let o = morphogen(&["run", "growth-curve", "--out", out_arg]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("another morphogen is writing into"),
        "{}",
        text(&o)
    );
    // Killed outright, it leaves its temporary files; the next run into
    // the folder removes them.
    child.kill().unwrap();
    child.wait().unwrap();
    let left = temporary(&out).len();
    assert!(left > 0);
    let o = morphogen(&["run", "growth-curve", "--out", out_arg]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        text(&o).contains(&format!("removed {left} temporary file(s)")),
        "{}",
        text(&o)
    );
    assert_eq!(temporary(&out), Vec::<String>::new());
}

#[test]
fn errors_quote_little_of_the_input_and_name_the_users_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let out = out.to_str().unwrap();
    // A megabyte key is a line, not a megabyte.
    let key = format!("{}=1", "k".repeat(100_000));
    let o = morphogen(&["run", "growth-curve", "--set", &key, "--out", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).len() < 1000, "{} bytes", text(&o).len());
    assert!(text(&o).contains("more characters)"), "{}", text(&o));
    let file = tmp.path().join("long.toml");
    let shown = String::from_utf8(morphogen(&["show", "growth-curve"]).stdout).unwrap();
    let long = shown.replace(
        "[curve]\n",
        &format!("[curve]\n{} = 1\n", "k".repeat(1 << 20)),
    );
    fs::write(&file, long).unwrap();
    let o = morphogen(&["run", file.to_str().unwrap(), "--out", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).len() < 1000, "{} bytes", text(&o).len());
    // A list of lists takes two indices.
    let o = morphogen(&[
        "run",
        "croton-mcu",
        "--set",
        "mosaic.adhesion[0][0]=2",
        "--out",
        out,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("mosaic.adhesion[0][0]: 2 is out of range (allowed: 0 to 1)"),
        "{}",
        text(&o)
    );
    // A damaged PNG mask in words, not the decoder's debug output.
    let png = tmp.path().join("bad.png");
    let mut bytes = b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x10\0\0\0\x10\x08\0\0\0\0".to_vec();
    bytes.extend(0xdead_beef_u32.to_be_bytes());
    fs::write(&png, bytes).unwrap();
    let o = morphogen(&[
        "run",
        "croton-mcu",
        "--mask",
        png.to_str().unwrap(),
        "--out",
        out,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("PNG: damaged or cut short"),
        "{}",
        text(&o)
    );
    assert!(!text(&o).contains("ChunkType"), "{}", text(&o));
    // A grammar's run-time error names the grammar's file.
    let grammar = tmp.path().join("boom.lsys");
    fs::write(&grammar, "n = 30\naxiom: F\nF -> F F\n").unwrap();
    let grammar = grammar.to_str().unwrap();
    let o = morphogen(&["run", "abop-shrub", "--grammar", grammar, "--out", out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains(&format!("abop-shrub with the grammar {grammar}: ")),
        "{}",
        text(&o)
    );
}

#[test]
fn a_mismatch_is_a_mismatch_where_its_new_stream_cannot_be_left() {
    // The fixture of other code (a byte changed, its summary agreeing)
    // in a folder where the pending stream cannot be written.
    let tmp = tempfile::tempdir().unwrap();
    let fixtures = fixture_copy(tmp.path());
    let dir = fixtures.join("growth-curve");
    let mut stream = fs::read(dir.join(fixture::STREAM_FILE)).unwrap();
    let middle = stream.len() / 2;
    stream[middle] ^= 0x80;
    fs::write(dir.join(fixture::STREAM_FILE), &stream).unwrap();
    let summary = fs::read_to_string(dir.join(fixture::SUMMARY_FILE)).unwrap();
    let old = summary
        .lines()
        .find(|l| l.starts_with("stream_digest"))
        .unwrap();
    let digest = format!("{:016x}", morphogen::stream::StreamDigest::of(&stream));
    fs::write(
        dir.join(fixture::SUMMARY_FILE),
        summary.replace(old, &format!("stream_digest = \"{digest}\"")),
    )
    .unwrap();
    fs::create_dir(dir.join(fixture::PENDING_FILE)).unwrap();
    let o = morphogen(&["verify", "--fixtures", fixtures.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("MISMATCH  growth-curve")
            && text(&o).contains("the new stream could not be left beside it"),
        "{}",
        text(&o)
    );
}

/// The grammar that docs/lsystems.md shows to explain the format runs as
/// written, saved as a file of its own.
#[test]
fn the_grammar_format_example_runs_as_written() {
    let doc = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/lsystems.md"))
        .unwrap();
    let start = doc.find("# ABOP Fig. 2.6a\n").expect("the format example");
    let end = start + doc[start..].find("```").unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("format.lsys");
    fs::write(&file, &doc[start..end]).unwrap();
    let out = tmp.path().join("out");
    let o = morphogen(&[
        "run",
        "--grammar",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--only",
        "png",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("plant.png").is_file());
}
