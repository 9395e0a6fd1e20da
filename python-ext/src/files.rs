//! A run's files from Python, written by the command line's own writers:
//! `stream.bin`, `records.jsonl` and the model's pictures, meshes and
//! tables, as `morphogen run --out DIR --only KINDS` writes them; and the
//! model's main picture, for a notebook.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use morphogen::preset::Model;
use morphogen_cli::atomic::{OutputFile, write_atomic};
use morphogen_cli::exec;
use morphogen_cli::folder_lock::FolderLock;
use morphogen_cli::outputs::{self, Kinds, Product};
use morphogen_cli::records::StreamFile;
use morphogen_stream_text::jsonl;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;

use crate::scenario::{Scenario, value_error};

/// Writes the run of `scenario` whose stream is `stream` into `dir`
/// (created if missing): `stream.bin`, then the kinds of file `only`
/// names (a comma list as `--only` takes: png, obj, glb, anim, svg, csv,
/// jsonl; default all). Returns the paths written, `stream.bin` first.
#[pyfunction]
#[pyo3(signature = (scenario, stream, dir, only = None))]
pub fn write(
    py: Python<'_>,
    scenario: &Scenario,
    stream: &[u8],
    dir: PathBuf,
    only: Option<&str>,
) -> PyResult<Vec<PathBuf>> {
    let kinds = match only {
        Some(list) => Kinds::parse(list).map_err(value_error)?,
        None => Kinds::DEFAULT,
    };
    py.detach(|| write_run(&scenario.inner, stream, &dir, kinds))
        .map_err(|e| PyOSError::new_err(format!("{e:#}")))
}

/// The model's main picture of the run of `scenario` whose stream is
/// `stream`, as PNG bytes: the growth chart, the horn, the plant, the
/// body's ages, the bones or the mosaic.
#[pyfunction]
pub fn picture(py: Python<'_>, scenario: &Scenario, stream: &[u8]) -> PyResult<Vec<u8>> {
    let scenario = &scenario.inner;
    py.detach(|| {
        let dir = tempfile::tempdir().context("cannot make a temporary folder")?;
        write_run(scenario, stream, dir.path(), Kinds::parse("png")?)?;
        let path = dir.path().join(main_picture(scenario));
        std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))
    })
    .map_err(|e| PyOSError::new_err(format!("{e:#}")))
}

/// The file name of the main picture of `scenario`'s model.
fn main_picture(scenario: &morphogen_scenario::Scenario) -> &'static str {
    scenario.with_preset(|preset| match preset.model {
        Model::GrowthCurve(_) => "growth.png",
        Model::Horn(_) => "horn.png",
        Model::LSystem(_) => "plant.png",
        Model::Body(_) => "ages.png",
        Model::Bones(_) => "bones.png",
        Model::Mosaic(_) => "mosaic.png",
    })
}

/// `stream` into `dir` as its stream file, then the files of `kinds`
/// drawn from it; an earlier run's numbered files that this one did not
/// write again are removed, as `morphogen run` removes them.
fn write_run(
    scenario: &morphogen_scenario::Scenario,
    stream: &[u8],
    dir: &Path,
    kinds: Kinds,
) -> Result<Vec<PathBuf>> {
    let _lock = FolderLock::take(dir)?;
    let path = dir.join(exec::STREAM_FILE);
    write_atomic(&path, stream)?;
    let mut written = vec![path.clone()];
    if kinds.wants(Product::Records) {
        let lines = dir.join(exec::JSONL_FILE);
        let mut file = OutputFile::create(&lines)?;
        jsonl::write_stream(stream, &mut file)
            .with_context(|| format!("cannot write {}", lines.display()))?;
        file.finish()?;
        written.push(lines);
    }
    written.extend(outputs::write(
        scenario,
        &StreamFile::new(&path),
        dir,
        kinds,
    )?);
    let stale = outputs::numbered::stale(dir, &written)?;
    outputs::numbered::remove(&stale)?;
    Ok(written)
}
