//! `Scenario::uses_seed` says the truth: with two seeds, a built-in's
//! stream differs beyond the header exactly when it says it uses the seed.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use morphogen::preset::Model;
use morphogen::stream::Encoder;
use rayon::prelude::*;

/// The stream of `name` with `seed`, without its header record.
fn body(scenario: &morphogen_scenario::Scenario, seed: u64) -> Vec<u8> {
    let mut encoder = Encoder::new(Vec::new());
    scenario
        .with_preset(|p| morphogen_scenario::run::run(p, seed, &mut encoder, &mut |_| {}))
        .expect("runs");
    let bytes = encoder.into_writer();
    let header = morphogen::stream::Decoder::new(&bytes)
        .next()
        .expect("a header");
    bytes[header.offset + header.len..].to_vec()
}

#[test]
fn the_seed_changes_a_stream_exactly_when_the_scenario_says_so() {
    // Mosaics are slow in a debug build: the MCU-sized croton stands for
    // them (a mosaic always draws its cells' positions). The built-ins run
    // on every core.
    morphogen_scenario::builtins()
        .par_iter()
        .for_each(|scenario| {
            let name = scenario.name();
            let mosaic = scenario.with_preset(|p| matches!(p.model, Model::Mosaic(_)));
            if mosaic && name != "croton-mcu" {
                assert!(scenario.uses_seed(), "{name}");
                return;
            }
            let (three, four) = rayon::join(|| body(scenario, 3), || body(scenario, 4));
            let differs = three != four;
            assert_eq!(scenario.uses_seed(), differs, "{name}");
        });
}
