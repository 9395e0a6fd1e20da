//! Embedding the core without the scenario crate (`docs/embedding.md`):
//! the ram horn's parameters written in Rust, as the firmware examples
//! include them (`firmware-example/examples/shared/ram_horn.rs`), are the
//! built-in scenario's bit for bit, so a device driving the horn directly
//! streams the bytes of the golden fixture.
#![allow(clippy::unwrap_used, clippy::panic)]

#[path = "../../firmware-example/examples/shared/ram_horn.rs"]
mod ram_horn;

use morphogen::horn::Horn;
use morphogen::preset::{self, Model, Preset, Runner};
use morphogen::sim::Start;
use morphogen::stream::Encoder;

/// A value of `fixtures/<preset>/summary.toml` (`key = "hex"`).
fn fixture_hex(preset: &str, key: &str) -> u64 {
    let path = format!(
        "{}/../fixtures/{preset}/summary.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with(&format!("{key} = ")))
        .unwrap_or_else(|| panic!("{path}: no {key}"));
    let hex = line.split('"').nth(1).unwrap();
    u64::from_str_radix(hex, 16).unwrap()
}

#[test]
fn hand_written_params_are_the_scenario_readers() {
    let scenario = morphogen_scenario::builtin(ram_horn::NAME).unwrap();
    scenario.with_preset(|p| {
        let Model::Horn(read) = p.model else {
            panic!("ram-horn is not a horn")
        };
        assert_eq!(read.modules, &ram_horn::MODULES[..]);
        assert_eq!(read.outline, &ram_horn::OUTLINE[..]);
        assert_eq!(*read, ram_horn::PARAMS);
    });
}

#[test]
fn hand_written_params_digest_is_the_fixtures() {
    let digest = Model::Horn(&ram_horn::PARAMS).params_digest();
    assert_eq!(digest, fixture_hex("ram-horn", "params_digest"));
    assert_eq!(digest, ram_horn::PARAMS_DIGEST);
}

#[test]
fn driven_directly_the_stream_is_the_fixtures() {
    let mut horn = Horn::IDLE;
    horn.start(&ram_horn::PARAMS, 0).unwrap();
    let header = preset::header(ram_horn::NAME, 0, ram_horn::PARAMS_DIGEST);
    let mut encoder = Encoder::new(Vec::new());
    preset::drive(&mut horn, &header, &mut encoder, &mut |_| {}).unwrap();
    assert_eq!(encoder.digest(), fixture_hex("ram-horn", "stream_digest"));
    assert_eq!(encoder.digest(), ram_horn::STREAM_DIGEST);
}

#[test]
fn through_the_runner_the_stream_is_the_same() {
    let preset = Preset {
        name: ram_horn::NAME,
        summary: "",
        default_seed: 0,
        model: Model::Horn(&ram_horn::PARAMS),
    };
    let mut runner = Runner::new();
    let mut encoder = Encoder::new(Vec::new());
    preset::run(&preset, 0, &mut runner, &mut encoder, &mut |_| {}).unwrap();
    assert_eq!(encoder.digest(), ram_horn::STREAM_DIGEST);
}
