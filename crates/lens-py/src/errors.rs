//! The package's exceptions, each carrying the library's own message:
//! `LensError` and, under it, `PrescriptionError` (a file that does not
//! load or validate), `GlassError` (an unknown glass, a wavelength outside
//! its data), `OpticsError` (a computation the lens cannot do: a lost chief
//! ray, a fully vignetted pupil, a bad argument) and `RenderError`.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(_lens, LensError, PyException, "Every error of the lens package: the message says what to change.");
create_exception!(_lens, PrescriptionError, LensError, "A prescription that does not load or is not valid.");
create_exception!(_lens, GlassError, LensError, "An unknown glass, or a wavelength outside a glass's data.");
create_exception!(_lens, OpticsError, LensError, "A computation the lens cannot do, or an argument out of range.");
create_exception!(_lens, RenderError, LensError, "A scene that does not load or render.");

/// Adds the exceptions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("LensError", py.get_type::<LensError>())?;
    m.add("PrescriptionError", py.get_type::<PrescriptionError>())?;
    m.add("GlassError", py.get_type::<GlassError>())?;
    m.add("OpticsError", py.get_type::<OpticsError>())?;
    m.add("RenderError", py.get_type::<RenderError>())?;
    Ok(())
}

/// A library error as the package's exception.
pub trait IntoPyErr {
    /// The exception.
    fn py_err(self) -> PyErr;
}

impl IntoPyErr for lens::OpticsError {
    fn py_err(self) -> PyErr {
        match self {
            lens::OpticsError::Glass(g) => g.py_err(),
            e => OpticsError::new_err(e.to_string()),
        }
    }
}

impl IntoPyErr for lens::LoadError {
    fn py_err(self) -> PyErr {
        PrescriptionError::new_err(self.to_string())
    }
}

impl IntoPyErr for lens::glass::GlassError {
    fn py_err(self) -> PyErr {
        GlassError::new_err(self.to_string())
    }
}

/// `Result<T, E>` to `PyResult<T>` with the package's exception.
pub trait OrPyErr<T> {
    /// The result, its error as the package's exception.
    fn py(self) -> PyResult<T>;
}

impl<T, E: IntoPyErr> OrPyErr<T> for Result<T, E> {
    fn py(self) -> PyResult<T> {
        self.map_err(IntoPyErr::py_err)
    }
}

/// A Python `UserWarning` saying `text` (a prescription's or a scene's
/// warning: a retired glass name replaced, ...).
pub fn warn_user(py: Python<'_>, text: &str) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    PyErr::warn(py, &category, &std::ffi::CString::new(text.replace('\0', " "))?, 1)
}

/// A Python `RuntimeWarning` for a glass used outside its data (the CLI
/// prints the same on standard error).
pub fn warn_glass_range(py: Python<'_>, w: &lens::glass::RangeWarning) -> PyResult<()> {
    let text = format!("glass outside its data: {}", serde_json::to_string(w).unwrap_or_default());
    let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
    PyErr::warn(py, &category, &std::ffi::CString::new(text)?, 1)
}
