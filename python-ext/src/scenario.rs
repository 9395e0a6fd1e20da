//! A scenario from Python: a preset's name or a scenario file, with
//! `KEY=VALUE` settings applied as `morphogen run --set` applies them, so a
//! bad value is the command line's message (as a `ValueError`).

use morphogen_cli::exec;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A checked scenario: a model with every one of its parameters, a name
/// and a seed.
#[pyclass(module = "morphogen", frozen)]
#[derive(Debug)]
pub struct Scenario {
    pub(crate) inner: morphogen_scenario::Scenario,
}

#[pymethods]
impl Scenario {
    /// The preset or scenario file `target` with `sets` (`KEY=VALUE`, the
    /// keys of `--set`) applied in order.
    #[new]
    #[pyo3(signature = (target, sets = Vec::new()))]
    fn new(target: &str, sets: Vec<String>) -> PyResult<Scenario> {
        let found = exec::parse_sets(&sets).and_then(|sets| exec::find(target, &sets));
        found.map(|inner| Scenario { inner }).map_err(value_error)
    }

    /// The scenario from `text`, a self-contained scenario file (as
    /// [`Scenario::text`] gives it); `origin` names it in errors.
    #[staticmethod]
    fn from_text(origin: &str, text: &str) -> PyResult<Scenario> {
        morphogen_scenario::Scenario::from_text(origin, text)
            .map(|inner| Scenario { inner })
            .map_err(|e| value_error(e.into()))
    }

    /// Pickling, for an executor whose workers are other processes (a
    /// process pool, a Dask or Ray cluster): the scenario as one
    /// self-contained file, read back by [`Scenario::from_text`].
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String, String))> {
        let from_text = py.get_type::<Scenario>().getattr("from_text")?;
        let origin = self.inner.name().to_string();
        Ok((from_text, (origin, self.inner.self_contained())))
    }

    /// This scenario with more `sets` applied after its own.
    fn with_sets(&self, sets: Vec<String>) -> PyResult<Scenario> {
        let sets = exec::parse_sets(&sets).map_err(value_error)?;
        let inner = self
            .inner
            .clone_with_sets(&sets)
            .map_err(|e| value_error(e.into()))?;
        Ok(Scenario { inner })
    }

    /// Its name (the stream header's).
    #[getter]
    fn name(&self) -> &str {
        self.inner.name()
    }

    /// Its one-line summary.
    #[getter]
    fn summary(&self) -> &str {
        self.inner.summary()
    }

    /// Its default seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed()
    }

    /// Whether its stream depends on the seed beyond the header.
    #[getter]
    fn uses_seed(&self) -> bool {
        self.inner.uses_seed()
    }

    /// The scenario as one self-contained TOML file, as `morphogen show`
    /// prints it (settings applied, named files inline).
    #[getter]
    fn text(&self) -> String {
        self.inner.self_contained()
    }

    fn __repr__(&self) -> String {
        format!(
            "<Scenario {} (seed {})>",
            self.inner.name(),
            self.inner.seed()
        )
    }
}

/// A command-line error as a `ValueError`, with the message the CLI prints.
pub(crate) fn value_error(e: anyhow::Error) -> PyErr {
    PyValueError::new_err(format!("{e:#}"))
}
