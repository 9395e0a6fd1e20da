//! Built-in scenarios through `morphogen::sent`: what a device reads is
//! the preset the host runs.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use morphogen::sent::{MAX_SENT, SentModel, SentReader, SentScenario};

/// `sent` framed and read back as the firmware reads it.
fn through_the_wire(sent: &SentScenario) -> SentScenario {
    let mut frame = [0u8; MAX_SENT + 3];
    let len = sent.encode(&mut frame).unwrap();
    let mut buffer = [0u8; MAX_SENT];
    let mut reader = SentReader::new(&mut buffer);
    let mut read: Vec<_> = frame[..len]
        .iter()
        .filter_map(|&b| reader.push(b))
        .collect();
    assert_eq!(read.len(), 1);
    read.pop().unwrap().unwrap()
}

#[test]
fn every_sendable_built_in_arrives_as_it_was() {
    let mut sent = 0;
    for scenario in morphogen_scenario::builtins() {
        // What `morphogen send` sends: grammars without their comments.
        let Ok(message) = morphogen_scenario::firmware::sent(&scenario, 1) else {
            continue;
        };
        let back = through_the_wire(&message);
        assert_eq!(back, message, "{}", scenario.name());
        assert_eq!(
            back.params,
            scenario.with_preset(|p| p.model.params_digest())
        );
        // The preset it lends is the one it was made from.
        if !matches!(back.model, SentModel::LSystem(_) | SentModel::Bones { .. }) {
            let model = back.with_preset(|p| format!("{:?}", p.model));
            assert_eq!(model, scenario.with_preset(|p| format!("{:?}", p.model)));
        }
        sent += 1;
    }
    // The growth curve, two horns, six L-systems, four bones (not
    // `bone-ossification`: its context-sensitive grammar the device cannot
    // derive, `a_bone_needing_buffered_derivation_is_refused`).
    assert_eq!(sent, 13);
}

#[test]
fn a_mosaic_is_refused_with_its_reason() {
    let croton = morphogen_scenario::builtin("croton-mcu").unwrap();
    let e = croton
        .with_preset(|p| SentScenario::new(p, 1, 0))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "a mosaic cannot be sent to a device: the parameters it lends a run take 288 B of \
         stack, which the firmware (its RAM 99 % used) does not have; build it into the \
         firmware with MORPHOGEN_SCENARIOS"
    );
}

#[test]
fn a_bone_needing_buffered_derivation_is_refused() {
    let bone = morphogen_scenario::builtin("bone-ossification").unwrap();
    let e = morphogen_scenario::firmware::sent(&bone, 0).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "a bone grammar that needs buffered derivation cannot be sent to a device: its \
             skeleton grammar is context-sensitive"
        ),
        "{e}"
    );
}
