//! `lens._lens`: the Python package's native module. Bindings only: every
//! number comes from the `lens` and `render` crates, and every dict is the
//! JSON report the CLI prints (`lens::report`), with its numeric lists as
//! numpy arrays. Long calls release the GIL and take `threads=`.
//!
//! The Python side (`python/lens/__init__.py`) re-exports these names; the
//! stubs are `python/lens/_lens.pyi`.

mod analyses;
mod convert;
mod errors;
mod glass;
mod prescription;
mod render;
mod tolerance;
mod trace;

use pyo3::prelude::*;

/// The native module.
#[pymodule]
fn _lens(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<prescription::Prescription>()?;
    m.add_class::<glass::Glass>()?;
    m.add_function(wrap_pyfunction!(prescription::load, m)?)?;
    m.add_function(wrap_pyfunction!(prescription::validate_file, m)?)?;
    m.add_function(wrap_pyfunction!(trace::trace, m)?)?;
    m.add_function(wrap_pyfunction!(glass::glass, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::fan, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::spot, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::wavefront, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::mtf, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::psf, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::coc, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::chromatic, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(tolerance::tolerance_share, m)?)?;
    m.add_function(wrap_pyfunction!(tolerance::tolerance_summary, m)?)?;
    m.add("STATUS_NAMES", trace::STATUS_NAMES.to_vec())?;
    Ok(())
}
