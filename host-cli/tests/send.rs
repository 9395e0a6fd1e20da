//! `morphogen send`: the message a device reads, and the scenarios it
//! refuses.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use std::process::{Command, Output};

use morphogen::sent::{MAX_SENT, SentModel, SentReader, SentScenario};
use morphogen::stream::{Decoder, Record};

fn send(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_morphogen"))
        .arg("send")
        .args(args)
        .output()
        .unwrap()
}

/// The scenarios in `bytes`, read as the firmware reads them.
fn read(bytes: &[u8]) -> Vec<SentScenario> {
    let mut buffer = [0u8; MAX_SENT];
    let mut reader = SentReader::new(&mut buffer);
    bytes
        .iter()
        .filter_map(|&b| reader.push(b))
        .map(Result::unwrap)
        .collect()
}

/// The parameter digest in the header of a preset's fixture.
fn fixture_params(name: &str) -> u64 {
    let path = format!(
        "{}/../fixtures/{name}/stream.bin",
        env!("CARGO_MANIFEST_DIR")
    );
    let bytes = std::fs::read(path).unwrap();
    match Decoder::new(&bytes).next().unwrap().result.unwrap() {
        Record::Header(h) => h.params,
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_sent_scenario_carries_the_fixture_header() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["ram-horn", "abop-shrub", "long-bone-random", "growth-curve"] {
        let file = dir.path().join(format!("{name}.sent"));
        let o = send(&[name, file.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{o:?}");
        let sent = read(&std::fs::read(&file).unwrap());
        assert_eq!(sent.len(), 1, "{name}");
        assert_eq!(sent[0].name.as_str(), name);
        assert_eq!(sent[0].params, fixture_params(name), "{name}");
    }
}

#[test]
fn a_changed_scenario_is_sent_as_changed_and_to_standard_output() {
    let o = send(&["ram-horn", "-", "--set", "horn.years=3", "--seed", "9"]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let sent = read(&o.stdout);
    assert_eq!(sent[0].seed, 9);
    let SentModel::Horn(horn) = &sent[0].model else {
        panic!("{:?}", sent[0].model)
    };
    assert_eq!(horn.years, 3);
    assert_ne!(sent[0].params, fixture_params("ram-horn"));
    // A grammar goes without its comments.
    let o = send(&["abop-shrub", "-"]);
    let SentModel::LSystem(grammar) = &read(&o.stdout)[0].model else {
        panic!("not an L-system")
    };
    assert!(
        grammar.contains("n = 7") && !grammar.contains('#'),
        "{grammar}"
    );
}

#[test]
fn what_does_not_fit_a_message_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("x.sent");
    for (name, why) in [
        (
            "horse-trot",
            "a body cannot be sent to a device: its mesh and tables do not fit a message; \
             build it into the firmware with MORPHOGEN_SCENARIOS",
        ),
        (
            "croton-mcu",
            "a mosaic cannot be sent to a device: the parameters it lends a run take 288 B of \
             stack, which the firmware (its RAM 99 % used) does not have; build it into the \
             firmware with MORPHOGEN_SCENARIOS",
        ),
    ] {
        let o = send(&[name, file.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2));
        assert_eq!(
            String::from_utf8_lossy(&o.stderr),
            format!("error: {name}: {why}\n")
        );
    }
    assert!(!file.exists());
}

#[test]
fn a_missing_port_is_named_not_created() {
    // A mistyped or unplugged port under /dev/ is an error, where any
    // other missing path is a file to write.
    let port = "/dev/morphogen-no-such-port";
    let o = send(&["ram-horn", port]);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with(&format!("error: no serial port {port}: ")),
        "{stderr}"
    );
    assert!(
        stderr.ends_with(" (DEST is a serial port, a file, or - for standard output)\n"),
        "{stderr}"
    );
    assert!(!std::path::Path::new(port).exists());
}

#[cfg(unix)]
#[test]
fn a_write_that_fails_leaves_no_file_behind() {
    // A file size limit of 0 blocks: the first write fails as on a full
    // disk (SIGXFSZ, then EFBIG), and the destination is never created.
    let tmp = tempfile::tempdir().unwrap();
    let dest = tmp.path().join("message.bin");
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f 0; exec {} send growth-curve {}",
            env!("CARGO_BIN_EXE_morphogen"),
            dest.display()
        ))
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!dest.exists(), "send left {}", dest.display());
}
