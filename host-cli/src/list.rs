//! `morphogen list` and `morphogen show`: the built-in presets, with
//! where each runs, and one preset's scenario file to start from.

use anyhow::Result;
use morphogen::preset::Model;

use crate::{Outcome, exec, say};

/// Prints every built-in preset: name, seed, summary, and why one runs
/// on the host only or takes flash of its own on an MCU.
///
/// # Errors
/// When standard output cannot be written.
pub fn list() -> Result<Outcome> {
    let all = morphogen_scenario::builtins();
    let width = all.iter().map(|s| s.name().len()).max().unwrap_or(0);
    for s in &all {
        let note = s.with_preset(|p| match p.model {
            Model::Mosaic(m) if !p.model.fits_mcu() => mcu_note(m),
            Model::Bones(_) if !p.model.fits_mcu() => {
                "  (host only: its skeleton grammar needs buffered derivation; the MCU streams)"
                    .to_owned()
            }
            Model::GrowthCurve(_)
            | Model::Horn(_)
            | Model::LSystem(_)
            | Model::Mosaic(_)
            | Model::Body(_)
            | Model::Bones(_) => match morphogen_scenario::firmware::on_own_mesh(s) {
                Some(bytes) => format!(
                    "  (on the MCU only when named by MORPHOGEN_SCENARIOS: its own mesh takes {} KB of flash)",
                    bytes.div_ceil(1000)
                ),
                None => String::new(),
            },
        });
        say!(
            "{:width$}  seed {:<4} {}{note}",
            s.name(),
            s.seed(),
            s.summary()
        )?;
    }
    Ok(Outcome::Ok)
}

/// Prints `preset`'s scenario file, self-contained.
///
/// # Errors
/// When it names no preset or scenario file, or standard output cannot
/// be written.
pub fn show(preset: &str) -> Result<Outcome> {
    let scenario = exec::find(preset, &[])?;
    crate::stdout::text(&scenario.self_contained())?;
    Ok(Outcome::Ok)
}

/// Why the mosaic `m` is host only (it does not fit the MCU's stores).
fn mcu_note(m: &morphogen::mosaic::Params<'_>) -> String {
    use morphogen::mosaic::{McuMeshStore, McuSurfaceStore};
    let peak = morphogen::mosaic::expected_peak_cells(m);
    let capacity = match m.surface {
        Some(_) => McuSurfaceStore::CAPACITY,
        None => morphogen::mosaic::McuStore::CAPACITY,
    };
    let surface = m.surface.map(|s| s.counts());
    if peak > capacity as u64 {
        format!(
            "  (host only: up to ~{peak} cells at the fastest type's doubling, an MCU store holds {capacity})"
        )
    } else if m.momentum != morphogen::fx::Fx::ZERO {
        "  (host only: momentum needs a velocity per cell, an MCU store keeps none)".to_owned()
    } else if m.anisotropy.is_some() && surface.is_some() {
        "  (host only: the MCU's mesh store keeps no anisotropy field)".to_owned()
    } else if let Some((vertices, faces)) = surface {
        format!(
            "  (host only: a mesh of {vertices} vertices and {faces} triangles, the MCU's mesh store holds {} and {})",
            McuMeshStore::VERTICES,
            McuMeshStore::FACES
        )
    } else {
        String::new()
    }
}
