//! Morphogen in Python: the extension module `morphogen._native` behind the
//! `morphogen` package (`python-ext/morphogen/`). It finds scenarios as the
//! command line does (`scenario`), runs them with the interpreter free
//! and Ctrl-C heard (`run`), writes a run's files with the CLI's own
//! writers (`files`) and plans sweeps (`sweep`); the package turns its
//! results into Python values.

mod files;
mod run;
mod scenario;
mod sweep;

use pyo3::prelude::*;

/// The built-in presets' names, in `morphogen list` order.
#[pyfunction]
fn presets() -> Vec<String> {
    morphogen_scenario::builtins()
        .iter()
        .map(|s| s.name().to_string())
        .collect()
}

/// The module: its functions, the scenario type and the version.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<sweep::Sweep>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(files::write, m)?)?;
    m.add_function(wrap_pyfunction!(files::picture, m)?)?;
    m.add("VERSION", morphogen_cli::provenance::version())?;
    m.add(
        "DEFAULT_MAX_STREAM_MB",
        morphogen_cli::exec::DEFAULT_MAX_STREAM_MB,
    )?;
    Ok(())
}
