//! `lens.load` and the `Prescription` class: a validated prescription at
//! one wavelength, its first-order report, its findings, and new
//! prescriptions from it (another f-number, another wavelength).

use crate::convert::to_py;
use crate::errors::{OrPyErr, PrescriptionError};
use lens::paraxial::ObjectDistance;
use pyo3::prelude::*;

/// A lens prescription (lengths in mm), validated, at one wavelength.
#[pyclass(module = "lens._lens", frozen)]
pub struct Prescription {
    pub(crate) inner: lens::Prescription,
    /// The file it came from, for messages and `repr`.
    pub(crate) file: Option<String>,
}

impl Prescription {
    /// `inner` as a Python object, its glasses' warnings given.
    pub(crate) fn wrap(inner: lens::Prescription, file: Option<String>) -> Self {
        Prescription { inner, file }
    }

    /// The prescription at `wavelength_nm` (itself where `None`): checked
    /// as the CLI's `--wavelength-nm` is, a glass outside its data a
    /// `RuntimeWarning`.
    pub(crate) fn at(&self, py: Python<'_>, wavelength_nm: Option<f64>) -> PyResult<lens::Prescription> {
        let Some(w) = wavelength_nm else { return Ok(self.inner.clone()) };
        if !(w.is_finite() && w > 0.0) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "wavelength_nm={}: give a positive wavelength in nm",
                lens::error::exact(w)
            )));
        }
        warn_range(py, &self.inner, &[w])?;
        self.inner.at_wavelength(w).py()
    }
}

/// A `RuntimeWarning` for each glass of `p` used outside its data at
/// `wavelengths_nm` (the CLI prints the same on standard error).
pub(crate) fn warn_range(py: Python<'_>, p: &lens::Prescription, wavelengths_nm: &[f64]) -> PyResult<()> {
    for w in p.glass_range(wavelengths_nm, lens::glass::GlassRange::Extrapolate).py()? {
        crate::errors::warn_glass_range(py, &w)?;
    }
    Ok(())
}

#[pymethods]
impl Prescription {
    /// The prescription's name (empty if it has none).
    #[getter]
    fn name(&self) -> &str {
        self.inner.name()
    }

    /// The wavelength it is at, nm.
    #[getter]
    fn wavelength_nm(&self) -> f64 {
        self.inner.wavelength_nm()
    }

    /// Its wavelengths, nm (the primary among them).
    #[getter]
    fn wavelengths_nm(&self) -> Vec<f64> {
        self.inner.wavelengths_nm().to_vec()
    }

    /// Its primary wavelength, nm.
    #[getter]
    fn primary_wavelength_nm(&self) -> f64 {
        self.inner.primary_wavelength_nm()
    }

    /// Its design fields, degrees.
    #[getter]
    fn fields_deg(&self) -> Vec<f64> {
        self.inner.fields_deg().to_vec()
    }

    /// Number of surfaces (the image surface not counted).
    #[getter]
    fn surface_count(&self) -> usize {
        self.inner.surfaces().len()
    }

    /// Film distance: the last thickness, mm behind the last vertex.
    #[getter]
    fn film_distance_mm(&self) -> f64 {
        self.inner.film_distance()
    }

    /// First-order properties, the keys of `lens info --json`: efl, bfl,
    /// ffd, principal planes (z from the first vertex), entrance and exit
    /// pupil (z, diameter), f_number, working_f_number, image_distance,
    /// magnification, total_track; mm. At `wavelength_nm` (default: the
    /// prescription's) for an object `object_distance_mm` in front of the
    /// first vertex (default: the prescription's, else infinity).
    #[pyo3(signature = (wavelength_nm=None, object_distance_mm=None))]
    fn info<'py>(
        &self,
        py: Python<'py>,
        wavelength_nm: Option<f64>,
        object_distance_mm: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let p = self.at(py, wavelength_nm)?;
        let d = object_distance_mm.or(self.inner.object_distance_mm()).unwrap_or(f64::INFINITY);
        let object = ObjectDistance::from_mm(d).py()?;
        to_py(py, &lens::report::info(&p, object).py()?)
    }

    /// Every finding of the validation (all warnings: a prescription with
    /// errors does not load), as dicts with the keys of `lens validate
    /// --json`'s findings.
    fn validate<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let findings = lens::model::validate::validate(&self.inner.to_spec());
        to_py(py, &serde_json::to_value(&findings).map_err(|e| PrescriptionError::new_err(e.to_string()))?)
    }

    /// The same lens with its stop resized to f-number `f_number` (paraxial,
    /// object at infinity), as the CLI's `--f-number`.
    fn with_f_number(&self, f_number: f64) -> PyResult<Prescription> {
        let p = lens::analysis::aperture::with_f_number(&self.inner, f_number).py()?;
        Ok(Prescription::wrap(p, self.file.clone()))
    }

    /// The same lens at `wavelength_nm` (its glasses' indices there).
    fn at_wavelength(&self, py: Python<'_>, wavelength_nm: f64) -> PyResult<Prescription> {
        Ok(Prescription::wrap(self.at(py, Some(wavelength_nm))?, self.file.clone()))
    }

    /// The prescription as the JSON format's text.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.inner.to_spec()).map_err(|e| PrescriptionError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        let name = if self.inner.name().is_empty() { self.file.as_deref().unwrap_or("") } else { self.inner.name() };
        format!(
            "<lens.Prescription {name:?}: {} surfaces at {} nm>",
            self.inner.surfaces().len(),
            self.inner.wavelength_nm()
        )
    }
}

/// Loads a prescription: `.json` (the project's format), `.dat` (pbrt), or
/// `.zmx` (Zemax); the glasses from the catalogues the file names and the
/// shipped ones. Warnings (a retired glass name replaced) become Python
/// `UserWarning`s.
#[pyfunction]
pub fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Prescription> {
    let p = lens::Prescription::load(&path).py()?;
    for w in p.warnings() {
        crate::errors::warn_user(py, w)?;
    }
    Ok(Prescription::wrap(p, Some(path.display().to_string())))
}

/// `lens validate --json` of one file, as a dict: "file", "valid",
/// "error" (why it did not load, or None), "findings".
#[pyfunction]
pub fn validate_file<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let (valid, findings, error) = match lens::load_spec(&path) {
        Ok(spec) => {
            let f = lens::model::validate::validate(&spec);
            (!lens::model::has_errors(&f), f, None)
        }
        Err(e) => (false, Vec::new(), Some(e.to_string())),
    };
    to_py(py, &lens::report::validation(&path.display().to_string(), valid, error, &findings))
}
