//! Tolerancing from Python: a share of the Monte Carlo trials of a
//! tolerance file as JSON text (what a `concurrent.futures` executor's
//! workers return: plain, picklable), and the summary of shares (the dict
//! `lens tolerance --json` prints). `lens.tolerance` (python/lens) maps
//! shares over an executor or runs one in-process.

use crate::convert::to_py;
use crate::errors::OpticsError;
use lens::tolerance::{Share, Tolerancing};
use pyo3::prelude::*;
use std::path::Path;

fn load(spec: &str) -> PyResult<Tolerancing> {
    Tolerancing::load(Path::new(spec), Vec::new()).map_err(|e| OpticsError::new_err(e.to_string()))
}

/// Share `shard` of `shards` (1-based) of `trials` trials of `seed` for the
/// tolerance file `spec`, on `threads` threads (None: every core), the
/// GIL released; the share as JSON text.
#[pyfunction]
#[pyo3(name = "_tolerance_share", signature = (spec, seed, trials, shard, shards, threads=None))]
pub fn tolerance_share(
    py: Python<'_>,
    spec: &str,
    seed: u64,
    trials: u64,
    shard: u64,
    shards: u64,
    threads: Option<usize>,
) -> PyResult<String> {
    let tol = load(spec)?;
    let pool = crate::trace::pool(threads)?;
    let share = py.detach(|| pool.install(|| tol.run(seed, trials, [shard, shards]))).map_err(OpticsError::new_err)?;
    serde_json::to_string(&share).map_err(|e| OpticsError::new_err(e.to_string()))
}

/// The summary (`lens tolerance --json`'s dict) of `shares` (JSON texts of
/// [`tolerance_share`]) of the tolerance file `spec`; `seconds` the run's
/// wall time.
#[pyfunction]
#[pyo3(name = "_tolerance_summary")]
pub fn tolerance_summary<'py>(
    py: Python<'py>,
    spec: &str,
    shares: Vec<String>,
    seconds: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let tol = load(spec)?;
    let shares = shares
        .iter()
        .map(|s| serde_json::from_str::<Share>(s).map_err(|e| OpticsError::new_err(format!("not a share: {e}"))))
        .collect::<PyResult<Vec<_>>>()?;
    let merged = lens::tolerance::merge(&shares).map_err(OpticsError::new_err)?;
    if merged.digest != tol.digest {
        return Err(OpticsError::new_err(format!(
            "the shares are of another analysis than {spec}: summarise them with the tolerance file that made them"
        )));
    }
    let stats = tol.statistics(std::slice::from_ref(&merged)).map_err(OpticsError::new_err)?;
    to_py(py, &lens::report::tolerance(&tol, &merged, &stats, seconds))
}
