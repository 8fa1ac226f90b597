//! `lens.glass` and the `Glass` class: a catalogue glass's index over
//! numpy arrays of wavelengths.

use crate::errors::OrPyErr;
use crate::trace::float_array;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// A catalogue glass (the shipped catalogues: Schott, Ohara, Hoya, ...).
#[pyclass(module = "lens._lens", frozen)]
pub struct Glass {
    inner: lens::glass::Glass,
}

#[pymethods]
impl Glass {
    /// `VENDOR:NAME`, as the vendor writes it.
    #[getter]
    fn name(&self) -> String {
        self.inner.full_name()
    }

    /// Index at the d line (587.5618 nm).
    #[getter]
    fn nd(&self) -> PyResult<f64> {
        self.inner.nd().py()
    }

    /// Abbe number at the d line.
    #[getter]
    fn vd(&self) -> PyResult<f64> {
        self.inner.vd().py()
    }

    /// The wavelengths its data covers, nm (low, high).
    #[getter]
    fn range_nm(&self) -> (f64, f64) {
        (self.inner.range_nm[0], self.inner.range_nm[1])
    }

    /// The refractive index at each wavelength (nm): a number for a
    /// number, a float64 array for an array. With `strict`, a wavelength
    /// outside the glass's data is an error (else the formula is
    /// extrapolated, as Zemax and optiland do).
    #[pyo3(signature = (wavelength_nm, strict=false))]
    fn index<'py>(
        &self,
        py: Python<'py>,
        wavelength_nm: &Bound<'py, PyAny>,
        strict: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let range = if strict { lens::glass::GlassRange::Strict } else { lens::glass::GlassRange::Extrapolate };
        let one = |nm: f64| -> PyResult<f64> {
            if !(nm.is_finite() && nm > 0.0) {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "wavelength_nm {nm}: give positive wavelengths in nm"
                )));
            }
            self.inner.index_with(nm, range).py()
        };
        if let Ok(nm) = wavelength_nm.extract::<f64>() {
            return Ok(one(nm)?.into_pyobject(py)?.into_any());
        }
        let a = float_array::<numpy::IxDyn>(wavelength_nm, "wavelength_nm", "any")?;
        let ro = a.readonly();
        let values = ro.as_array().iter().map(|nm| one(*nm)).collect::<PyResult<Vec<f64>>>()?;
        let out = PyArray1::from_vec(py, values);
        Ok(out.reshape(ro.shape())?.into_any())
    }

    fn __repr__(&self) -> String {
        format!("<lens.Glass {}>", self.inner.full_name())
    }
}

/// The glass `name` (`VENDOR:NAME`, or a name one catalogue alone has;
/// a retired name gives its successor with a `UserWarning`).
#[pyfunction]
pub fn glass(py: Python<'_>, name: &str) -> PyResult<Glass> {
    let (g, note) = lens::glass::Catalogs::shipped().resolve(name).py()?;
    if let Some(note) = note {
        crate::errors::warn_user(py, &note)?;
    }
    Ok(Glass { inner: g.clone() })
}
