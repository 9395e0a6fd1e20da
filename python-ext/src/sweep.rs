//! A sweep from Python: `morphogen sweep`'s combinations and table
//! (`host-cli`'s sweep plan), the runs left to the caller's executor.

use morphogen_cli::sweep::Plan;
use pyo3::prelude::*;

use crate::scenario::{Scenario, value_error};

/// The combinations of values over a scenario: each run's scenario and
/// seed, the table's header and each run's line, as `sweep.csv` holds them.
#[pyclass(module = "morphogen", frozen)]
#[derive(Debug)]
pub struct Sweep {
    plan: Plan,
}

#[pymethods]
impl Sweep {
    /// `scenario` swept over `sets` (`KEY=V1,V2,…`, as `morphogen sweep
    /// --set` takes them).
    #[new]
    fn new(scenario: &Scenario, sets: Vec<String>) -> PyResult<Sweep> {
        let plan = Plan::new(scenario.inner.clone(), &sets).map_err(value_error)?;
        Ok(Sweep { plan })
    }

    /// The number of runs.
    #[getter]
    fn runs(&self) -> usize {
        self.plan.runs()
    }

    /// The table's first line.
    #[getter]
    fn header(&self) -> String {
        self.plan.header()
    }

    /// Run `k`'s scenario and seed.
    fn scenario(&self, k: usize) -> PyResult<(Scenario, u64)> {
        let (inner, seed) = self.plan.scenario(k).map_err(value_error)?;
        Ok((Scenario { inner }, seed))
    }

    /// Run `k`'s line of the table, its stream `stream`.
    fn line(&self, k: usize, stream: &[u8]) -> String {
        self.plan.line(k, stream)
    }
}
