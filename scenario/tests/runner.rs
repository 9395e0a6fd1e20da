//! The firmware's `Runner` and the mosaics on a surface: with the core's
//! feature `surface-runner` (the firmware's `surface`), it holds the cells
//! and the mesh inline and streams `watermelon-mcu` as the host does;
//! without it, it refuses such a mosaic, naming the feature.
//!
//! `cargo test -p morphogen-scenario --test runner` checks the refusal,
//! `cargo test -p morphogen-scenario --features surface-runner --test runner`
//! the stream.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]

use morphogen::preset::Runner;

/// The firmware's [`Runner`], its surface mosaic's cells and mesh inline,
/// streams `watermelon-mcu` byte for byte as its fixture (the host's run,
/// with its heap mesh, inward normals and edge sort).
#[cfg(feature = "surface-runner")]
#[test]
fn the_runner_grows_watermelon_mcu_on_its_inline_mesh_as_the_host_does() {
    use morphogen::preset;
    use morphogen::stream::Encoder;
    let fixture = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/watermelon-mcu/stream.bin"
    ))
    .unwrap();
    let scenario = morphogen_scenario::builtin("watermelon-mcu").unwrap();
    scenario.with_preset(|p| {
        assert!(p.model.fits_mcu());
        let mut runner = Box::new(Runner::new());
        let mut sink = Encoder::new(Vec::new());
        preset::run(p, p.default_seed, &mut runner, &mut sink, &mut |_| {}).unwrap();
        assert!(sink.into_writer() == fixture, "the Runner's stream differs");
    });
}

/// Built without the feature `surface-runner`, the Runner refuses a surface
/// mosaic, naming the feature.
#[cfg(not(feature = "surface-runner"))]
#[test]
fn without_its_feature_the_runner_refuses_a_surface_mosaic_naming_it() {
    use morphogen::Error;
    use morphogen::preset::{Model, SURFACE_MOSAICS};
    let scenario = morphogen_scenario::builtin("watermelon-mcu").unwrap();
    scenario.with_preset(|p| {
        assert!(matches!(p.model, Model::Mosaic(_)));
        let mut runner = Box::new(Runner::new());
        let refused = runner.start(&p.model, 1);
        assert!(matches!(
            refused,
            Err(Error::Capacity {
                limit: SURFACE_MOSAICS,
                capacity: 0
            })
        ));
    });
}
