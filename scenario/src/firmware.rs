//! What a firmware's build script needs: the presets it runs, as `static`
//! Rust generated from scenario files by [`codegen`], and their parameter
//! digests, with what the device never reads (summaries, grammar comments)
//! left out to save flash. `firmware-example` and `firmware-rp2040` both
//! call [`write_presets`] from their `build.rs`.
//!
//! - By default: every built-in scenario (`scenarios/*.toml`) that fits
//!   the MCU ([`morphogen::preset::Model::fits_mcu`]), in `morphogen list`
//!   order; mosaics on a surface only for a firmware whose runner runs
//!   them (the core's feature `surface-runner`); no body on its own mesh
//!   ([`on_own_mesh`]: its vertices and triangles would be in flash).
//! - With `MORPHOGEN_SCENARIOS=a.toml,b.toml`: exactly those files, in that
//!   order. Relative paths are taken from the directory `cargo` was started
//!   in (the shell's `$PWD`; a build script runs in its package directory).
//!   A file that does not load or does not fit the MCU fails the build with
//!   its message.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

use morphogen::bones::BonesParams;
use morphogen::preset::{Model, Preset};
use morphogen::sent::{SentError, SentScenario};

use crate::schema::Include;
use crate::{Scenario, codegen};

/// The variable naming the scenario files to build in.
pub const VAR: &str = "MORPHOGEN_SCENARIOS";

/// Writes `OUT_DIR/presets.rs` (`PRESETS` and `PARAMS_DIGESTS`) and prints
/// the `cargo:rerun-if-…` lines for the scenario files it read. Call it
/// from a build script; `surfaces` says whether the firmware's runner runs
/// mosaics on a surface (the core's feature `surface-runner`).
///
/// # Errors
/// A message for the build to fail with: no `OUT_DIR`, a scenario that does
/// not load or does not fit the MCU (or is a surface mosaic the runner
/// cannot run), no preset at all, a failed write.
pub fn write_presets(surfaces: bool) -> Result<(), String> {
    let out = PathBuf::from(
        env::var_os("OUT_DIR").ok_or("OUT_DIR is not set: call this from a build script")?,
    );
    let repository = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    println!("cargo:rerun-if-env-changed={VAR}");
    println!(
        "cargo:rerun-if-changed={}",
        repository.join("scenarios").display()
    );
    println!(
        "cargo:rerun-if-changed={}",
        repository.join("grammars").display()
    );

    let scenarios = match env::var_os(VAR) {
        None => builtin_presets(surfaces),
        Some(list) => user_scenarios(
            list.to_str().ok_or(format!("{VAR} is not UTF-8"))?,
            surfaces,
        )?,
    };
    if scenarios.is_empty() {
        return Err("no preset fits the MCU".into());
    }
    let mut source =
        codegen::presets(&scenarios).map_err(|e| format!("generating presets.rs: {e}"))?;
    strip_for_flash(&mut source, &scenarios);
    source.push_str(&params_digests(&scenarios));
    fs::write(out.join("presets.rs"), source).map_err(|e| format!("writing presets.rs: {e}"))
}

/// `PARAMS_DIGESTS`: the stream header's parameter digest of each preset,
/// in the order of `PRESETS`, computed here by the same core code the
/// device would run (`Model::params_digest`), so that the firmware needs no
/// serializer for the parameters of every model.
fn params_digests(scenarios: &[Scenario]) -> String {
    let digests: Vec<String> = scenarios
        .iter()
        .map(|s| format!("{:#018x}", s.with_preset(|p| p.model.params_digest())))
        .collect();
    format!(
        "\n/// The parameter digest of each of `PRESETS`, in order (computed by `build.rs`).\n\
         pub static PARAMS_DIGESTS: [u64; {}] = [{}];\n",
        digests.len(),
        digests.join(", ")
    )
}

/// Drops from the generated `source` what the firmware never reads, to
/// save flash: each preset's summary (for `morphogen list`), and the
/// comments of its grammar text (the parser skips them; the digest of the
/// whole text is in `PARAMS_DIGESTS`). Both are found as the `{:?}`
/// literals `codegen` writes; a literal not found stays as it is.
fn strip_for_flash(source: &mut String, scenarios: &[Scenario]) {
    for scenario in scenarios {
        let (summary, grammar) = scenario.with_preset(|p| {
            let grammar = match p.model {
                Model::LSystem(text) => Some(text.to_owned()),
                Model::Bones(b) => Some(b.grammar.to_owned()),
                Model::GrowthCurve(_) | Model::Horn(_) | Model::Mosaic(_) | Model::Body(_) => None,
            };
            (p.summary.to_owned(), grammar)
        });
        *source = source.replace(&format!("summary: {summary:?}"), "summary: \"\"");
        if let Some(text) = grammar {
            *source = source.replace(
                &format!("{text:?}"),
                &format!("{:?}", without_comments(&text)),
            );
        }
    }
}

/// The message `morphogen send` writes to a device for `scenario` run with
/// `seed` ([`SentScenario`]): the header's parameter digest is the whole
/// scenario's, as the host's run has it, and a grammar goes without its
/// comments, as built-in presets do.
///
/// # Errors
/// A model that cannot be sent, or a part bigger than the message holds.
pub fn sent(scenario: &Scenario, seed: u64) -> Result<SentScenario, SentError> {
    scenario.with_preset(|p| {
        let params = p.model.params_digest();
        match p.model {
            Model::LSystem(text) => {
                let text = without_comments(text);
                let preset = Preset {
                    model: Model::LSystem(&text),
                    ..*p
                };
                SentScenario::new(&preset, seed, params)
            }
            Model::Bones(_) if !p.model.fits_mcu() => Err(SentError::NotSendable {
                what: "a bone grammar that needs buffered derivation",
                why: NEEDS_BUFFER,
            }),
            Model::Bones(bones) => {
                let text = without_comments(bones.grammar);
                let bones = BonesParams {
                    grammar: &text,
                    ..*bones
                };
                let preset = Preset {
                    model: Model::Bones(&bones),
                    ..*p
                };
                SentScenario::new(&preset, seed, params)
            }
            Model::GrowthCurve(_) | Model::Horn(_) | Model::Mosaic(_) | Model::Body(_) => {
                SentScenario::new(p, seed, params)
            }
        }
    })
}

/// Why a bone scenario that does not fit the MCU does not: its grammar.
const NEEDS_BUFFER: &str = "its skeleton grammar is context-sensitive, has decomposition rules or \
     n > 32 (the device's `Streaming<STEPS>`), which only buffered derivation handles, and the device derives \
     streaming; run it on the host with `morphogen run`";

/// `text` without its comments: each line up to its first `#`, as the
/// grammar parser reads it (`docs/lsystems.md`), without the blanks before
/// it; the lines stay, so that a parse error names the same line.
fn without_comments(text: &str) -> String {
    let lines: Vec<&str> = text
        .split('\n')
        .map(|line| match line.find('#') {
            Some(k) => line[..k].trim_end_matches([' ', '\t']),
            None => line,
        })
        .collect();
    lines.join("\n")
}

/// The built-in presets a firmware runs unless [`VAR`] names others, in
/// `morphogen list` order: each that fits the MCU, without mosaics on a
/// surface unless the runner runs them (`surfaces`: the core's feature
/// `surface-runner`) and without bodies on their own mesh
/// ([`on_own_mesh`]). Its length is the number of streams the firmware
/// sends back to back.
#[must_use]
pub fn builtin_presets(surfaces: bool) -> Vec<Scenario> {
    crate::builtins()
        .into_iter()
        .filter(|s| {
            s.with_preset(|p| p.model.fits_mcu())
                && (surfaces || !on_surface(s))
                && on_own_mesh(s).is_none()
        })
        .collect()
}

/// For a body grown on its own mesh (a built-in preset such as
/// `horse-with-cow-growth`, or a user's), the flash its mesh takes in a
/// firmware, in bytes (12 a vertex, 12 a triangle); such a preset is built
/// in only when named by [`VAR`].
#[must_use]
pub fn on_own_mesh(scenario: &Scenario) -> Option<usize> {
    scenario.with_preset(|p| match p.model {
        Model::Body(b) => match b.model.mesh {
            morphogen::body::Mesh::Indexed {
                vertices,
                triangles,
            } => Some(size_of_val(vertices) + size_of_val(triangles)),
            morphogen::body::Mesh::Tubes(_) => None,
        },
        Model::GrowthCurve(_)
        | Model::Horn(_)
        | Model::LSystem(_)
        | Model::Mosaic(_)
        | Model::Bones(_) => None,
    })
}

/// Whether `scenario` is a mosaic on a surface.
fn on_surface(scenario: &Scenario) -> bool {
    scenario.with_preset(|p| matches!(p.model, Model::Mosaic(m) if m.surface.is_some()))
}

/// The scenario files of the comma-separated `list`, loaded and checked
/// (mosaics on a surface only if the runner runs them: `surfaces`).
fn user_scenarios(list: &str, surfaces: bool) -> Result<Vec<Scenario>, String> {
    let paths: Vec<&str> = list
        .split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect();
    if paths.is_empty() {
        return Err(format!("{VAR} is set but names no scenario file"));
    }
    if paths.iter().any(|p| Path::new(p).is_relative()) {
        // The same relative paths from another directory are other files.
        println!("cargo:rerun-if-env-changed=PWD");
    }
    let mut scenarios: Vec<Scenario> = Vec::new();
    for given in paths {
        let path = resolve(given)?;
        println!("cargo:rerun-if-changed={}", path.display());
        let scenario = Scenario::load(&path, &[]).map_err(|e| format!("{VAR}: {e}"))?;
        // The files it names, relative to its folder.
        let file = scenario.file();
        let folder = path.parent().unwrap_or(Path::new("."));
        let includes = [
            file.lsystem.as_ref().map(|l| &l.grammar),
            file.bones.as_ref().map(|b| &b.grammar),
            file.mosaic.as_ref().and_then(|m| m.mask.as_ref()),
            file.body.as_ref().and_then(|b| b.mesh.as_ref()),
            file.body.as_ref().and_then(|b| b.cylinders.as_ref()),
        ];
        for include in includes.into_iter().flatten() {
            if let Include::Path(named) = include {
                println!("cargo:rerun-if-changed={}", folder.join(named).display());
            }
        }
        if !scenario.with_preset(|p| p.model.fits_mcu()) {
            let why = scenario.with_preset(|p| match p.model {
                Model::Bones(_) => NEEDS_BUFFER,
                Model::GrowthCurve(_)
                | Model::Horn(_)
                | Model::LSystem(_)
                | Model::Mosaic(_)
                | Model::Body(_) => "too big for the runner's fixed capacity; run it on the host with `morphogen run`",
            });
            return Err(format!(
                "{VAR}: {}: {} does not fit the MCU ({why})",
                path.display(),
                scenario.name()
            ));
        }
        if !surfaces && on_surface(&scenario) {
            return Err(format!(
                "{VAR}: {}: {} is a mosaic on a surface: build the firmware with its feature \
                 `surface` (the core's `surface-runner`)",
                path.display(),
                scenario.name()
            ));
        }
        if let Some(twin) = scenarios.iter().find(|s| s.name() == scenario.name()) {
            return Err(format!(
                "{VAR}: {}: name {:?} is also the name of {}",
                path.display(),
                scenario.name(),
                twin.origin()
            ));
        }
        scenarios.push(scenario);
    }
    Ok(scenarios)
}

/// `given` as an absolute path: relative ones from the directory `cargo`
/// was started in (`$PWD`).
fn resolve(given: &str) -> Result<PathBuf, String> {
    let path = Path::new(given);
    if path.is_absolute() {
        return Ok(path.to_path_buf());
    }
    match env::var_os("PWD").map(PathBuf::from) {
        Some(dir) if dir.is_absolute() => Ok(dir.join(path)),
        _ => Err(format!(
            "{VAR}: {given} is relative but $PWD (where cargo was started) is not set; \
             give an absolute path"
        )),
    }
}
