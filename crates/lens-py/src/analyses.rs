//! The analyses at one field, each the dict of its CLI command's `--json`
//! (`lens::report`), computed by the same library calls in the same order
//! so that the numbers agree to the bit: `fan`, `spot`, `wavefront`,
//! `mtf`, `psf`, `coc`, `chromatic`.
//! Arguments follow the flags: `field_deg`, `field_x_deg` (the x
//! component, for lenses with decentred or tilted surfaces; the last
//! keyword of `fan`, `spot`, `wavefront`, `mtf` and `psf`; reports gain
//! `field_x_deg` where it is not 0), `wavelength_nm` (None: the
//! prescription's, or for `spot` every wavelength with its weight), `aim`
//! ("auto", "paraxial", "real"), `film` ("image": the prescription's
//! image surface; "paraxial"; or a distance in mm behind the last vertex),
//! `threads` (None: every core; the GIL is released while they work).

use crate::convert::to_py;
use crate::errors::{OpticsError, OrPyErr};
use crate::prescription::{warn_range, Prescription};
use lens::analysis::fan::ImagePlane;
use lens::analysis::{Aim, Field, Launcher};
use lens::paraxial::FirstOrder;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The aiming named `aim`.
fn aim_of(aim: &str) -> PyResult<Aim> {
    match aim.to_ascii_lowercase().as_str() {
        "auto" => Ok(Aim::Auto),
        "paraxial" => Ok(Aim::Paraxial),
        "real" => Ok(Aim::Real),
        _ => Err(PyValueError::new_err(format!("aim={aim:?}: give \"auto\", \"paraxial\" or \"real\""))),
    }
}

/// The image plane `film` names (as the CLI's `--film`).
fn plane_of(film: Option<&Bound<'_, PyAny>>) -> PyResult<ImagePlane> {
    let Some(film) = film else { return Ok(ImagePlane::ImageSurface) };
    if let Ok(d) = film.extract::<f64>() {
        return match d {
            d if d.is_finite() && d > 0.0 => Ok(ImagePlane::Film(d)),
            _ => Err(PyValueError::new_err(format!(
                "film={}: give a distance behind the last vertex (> 0 mm), \"image\" or \"paraxial\"",
                lens::error::exact(d)
            ))),
        };
    }
    match film.extract::<String>()?.trim().to_ascii_lowercase().as_str() {
        "image" | "image-surface" => Ok(ImagePlane::ImageSurface),
        "paraxial" => Ok(ImagePlane::Paraxial),
        other => Err(PyValueError::new_err(format!(
            "film={other:?}: give \"image\" (the prescription's image surface), \"paraxial\", or a distance in mm behind the last vertex"
        ))),
    }
}

/// `f` on `threads` threads (None: every core), the GIL released.
fn off_gil<T: Send>(py: Python<'_>, threads: Option<usize>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let pool = crate::trace::pool(threads)?;
    Ok(py.detach(|| pool.install(f)))
}

/// Refuses a field angle that is not one (`name` its argument).
fn check_field(name: &str, deg: f64) -> PyResult<()> {
    if deg.is_finite() && deg.abs() < 90.0 {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "{name}={}: give an angle above -90 and below 90 degrees",
            lens::error::exact(deg)
        )))
    }
}

/// What every analysis starts from: the prescription at its wavelength
/// and at the one traced, the first order, the launcher of the field.
struct Setup {
    p: lens::Prescription,
    traced: lens::Prescription,
    launcher: Launcher,
    /// The aiming asked for (before the field resolves "auto").
    aim: Aim,
}

impl Setup {
    /// The setup at the field of component angles `field` (x, y degrees).
    fn new(
        py: Python<'_>,
        pr: &Prescription,
        field: (f64, f64),
        wavelength_nm: Option<f64>,
        aim: &str,
    ) -> PyResult<Self> {
        let (field_x_deg, field_deg) = field;
        check_field("field_deg", field_deg)?;
        check_field("field_x_deg", field_x_deg)?;
        let aim = aim_of(aim)?;
        let traced = pr.at(py, wavelength_nm)?;
        let p = pr.inner.clone();
        let first = FirstOrder::of(&p).py()?;
        let launcher =
            Launcher::with_first(&p, &first, Field::at_angles(&p, &first, field_x_deg, field_deg), aim).py()?;
        Ok(Setup { p, traced, launcher, aim })
    }
}

/// Tangential and sagittal ray fans at `field_deg`, `points` pupil points
/// each (the keys of `lens fan --json`).
#[pyfunction]
#[pyo3(signature = (prescription, field_deg=0.0, points=21, wavelength_nm=None, aim="auto", film=None, threads=None, field_x_deg=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn fan<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    field_deg: f64,
    points: usize,
    wavelength_nm: Option<f64>,
    aim: &str,
    film: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    field_x_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    if points < 2 {
        return Err(PyValueError::new_err(format!("points={points}: a fan needs at least 2 points")));
    }
    let plane = plane_of(film)?;
    let s = Setup::new(py, prescription, (field_x_deg, field_deg), wavelength_nm, aim)?;
    let fan =
        off_gil(py, threads, || lens::analysis::fan::fan_traced(&s.p, &s.traced, &s.launcher, points, plane))?.py()?;
    to_py(py, &serde_json::to_value(&fan).map_err(|e| OpticsError::new_err(e.to_string()))?)
}

/// The spot diagram at `field_deg` (the keys of `lens spot --json`):
/// `pattern` "gauss" (n rings), "square", "hexapolar" or "random"; at
/// `wavelength_nm`, or every wavelength of the prescription with its
/// weight where None.
#[pyfunction]
#[pyo3(signature = (prescription, field_deg=0.0, pattern="gauss", n=12, wavelength_nm=None, aim="auto", film=None, threads=None, field_x_deg=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn spot<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    field_deg: f64,
    pattern: &str,
    n: usize,
    wavelength_nm: Option<f64>,
    aim: &str,
    film: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    field_x_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    use lens::analysis::pattern::Pattern;
    let pattern = match pattern.to_ascii_lowercase().as_str() {
        "gauss" => Pattern::Gauss,
        "square" => Pattern::Square,
        "hexapolar" => Pattern::Hexapolar,
        "random" => Pattern::Random,
        other => {
            return Err(PyValueError::new_err(format!(
                "pattern={other:?}: give \"gauss\", \"square\", \"hexapolar\" or \"random\""
            )))
        }
    };
    let plane = plane_of(film)?;
    let s = Setup::new(py, prescription, (field_x_deg, field_deg), wavelength_nm, aim)?;
    let waves: Vec<(f64, f64)> = s.p.wavelengths_nm().iter().copied().zip(s.p.wavelength_weights()).collect();
    if wavelength_nm.is_none() {
        warn_range(py, &s.p, s.p.wavelengths_nm())?;
    }
    let spot = off_gil(py, threads, || match wavelength_nm {
        Some(_) => lens::analysis::spot::spot_traced(&s.p, &s.traced, &s.launcher, pattern, n, plane),
        None => lens::analysis::spot::spot_polychromatic(&s.p, &s.launcher, pattern, n, plane, &waves),
    })?
    .py()?;
    to_py(py, &lens::report::with_field_x(lens::report::spot(field_deg, &spot), field_x_deg))
}

/// The wavefront error at `field_deg` (the keys of `lens wavefront
/// --json`): RMS and P-V to the chief ray and to the centroid, Strehl,
/// both 37-term Zernike fits; on a `grid` x `grid` pupil grid (None: the
/// default, finer where the wavefront needs it); with `samples`, the map.
#[pyfunction]
#[pyo3(signature = (prescription, field_deg=0.0, wavelength_nm=None, aim="auto", film=None, grid=None, samples=false, threads=None, field_x_deg=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn wavefront<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    field_deg: f64,
    wavelength_nm: Option<f64>,
    aim: &str,
    film: Option<&Bound<'py, PyAny>>,
    grid: Option<usize>,
    samples: bool,
    threads: Option<usize>,
    field_x_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    use lens::analysis::wave::zernike::{fit, ZernikeKind, TERMS};
    let plane = plane_of(film)?;
    let s = Setup::new(py, prescription, (field_x_deg, field_deg), wavelength_nm, aim)?;
    let report = off_gil(py, threads, || -> Result<serde_json::Value, lens::OpticsError> {
        let w = match grid {
            Some(n) => lens::analysis::wave::wavefront(&s.p, &s.traced, &s.launcher, n, plane)?,
            None => lens::analysis::wave::wavefront_auto(&s.p, &s.traced, &s.launcher, plane)?,
        };
        let st = lens::analysis::wave::stats(&w);
        let fringe = fit(&w, ZernikeKind::Fringe, TERMS);
        let standard = fit(&w, ZernikeKind::Standard, TERMS);
        let fits = lens::report::Fits { fringe: fringe.as_ref(), standard: standard.as_ref() };
        Ok(lens::report::with_field_x(lens::report::wavefront(field_deg, plane, &w, &st, fits, samples), field_x_deg))
    })?
    .py()?;
    to_py(py, &report)
}

/// The diffraction MTF at `field_deg` and `frequencies` (cycles/mm; the
/// keys of `lens mtf --json`), monochromatic at `wavelength_nm` or, with
/// `polychromatic`, over the prescription's wavelengths and weights.
#[pyfunction]
#[pyo3(signature = (prescription, frequencies, field_deg=0.0, wavelength_nm=None, polychromatic=false, aim="auto", film=None, threads=None, field_x_deg=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn mtf<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    frequencies: Vec<f64>,
    field_deg: f64,
    wavelength_nm: Option<f64>,
    polychromatic: bool,
    aim: &str,
    film: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    field_x_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    use lens::analysis::wave::mtf::{cutoffs, mtf, polychromatic_mtf};
    if frequencies.is_empty() {
        return Err(PyValueError::new_err("frequencies: give at least one frequency in cycles/mm"));
    }
    let plane = plane_of(film)?;
    let s = Setup::new(py, prescription, (field_x_deg, field_deg), wavelength_nm, aim)?;
    let waves: Option<Vec<(f64, f64)>> =
        polychromatic.then(|| s.p.wavelengths_nm().iter().copied().zip(s.p.wavelength_weights()).collect());
    if polychromatic {
        warn_range(py, &s.p, s.p.wavelengths_nm())?;
    }
    let report = off_gil(py, threads, || -> Result<serde_json::Value, lens::OpticsError> {
        let first = FirstOrder::of(&s.p)?;
        let axis = Launcher::with_first(&s.p, &first, Field::at_angle(&s.p, &first, 0.0), s.aim)?;
        let axis_cutoff = cutoffs(&s.p, &s.traced, &axis, plane.z(&s.p, &axis)?)?.0;
        let m = match &waves {
            Some(w) => polychromatic_mtf(&s.p, &s.launcher, plane, &frequencies, w)?,
            None => mtf(&s.p, &s.traced, &s.launcher, plane, &frequencies)?,
        };
        Ok(lens::report::with_field_x(
            lens::report::mtf(field_deg, plane, &m, waves.as_deref(), axis_cutoff, None),
            field_x_deg,
        ))
    })?
    .py()?;
    to_py(py, &report)
}

/// Real circles of confusion for objects at `distances` (mm; `inf` for
/// infinity) with the lens focused at `focus_mm`, beside the thin-lens
/// formula (the keys of `lens coc --json`).
#[pyfunction]
#[pyo3(signature = (prescription, focus_mm, distances, wavelength_nm=None, threads=None))]
pub fn coc<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    focus_mm: f64,
    distances: Vec<f64>,
    wavelength_nm: Option<f64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    if distances.is_empty() {
        return Err(PyValueError::new_err("distances: give at least one object distance in mm (inf for infinity)"));
    }
    let p = prescription.at(py, wavelength_nm)?;
    let t = off_gil(py, threads, || lens::analysis::coc::circle_of_confusion(&p, focus_mm, &distances))?.py()?;
    to_py(py, &serde_json::to_value(&t).map_err(|e| OpticsError::new_err(e.to_string()))?)
}

/// Colour (the keys of `lens chromatic --json`): focal shift against
/// wavelength, lateral colour from the axis to `max_field_deg` (None: the
/// design's largest field, else a 36 x 24 mm frame's corner), the
/// polychromatic spot and each wavelength's fans at `field_deg`.
#[pyfunction]
#[pyo3(signature = (prescription, field_deg=0.0, max_field_deg=None, aim="auto", threads=None))]
pub fn chromatic<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    field_deg: f64,
    max_field_deg: Option<f64>,
    aim: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let aim = aim_of(aim)?;
    let p = &prescription.inner;
    warn_range(py, p, p.wavelengths_nm())?;
    let c = off_gil(py, threads, || {
        let max = match max_field_deg {
            Some(m) => m,
            None => lens::analysis::chromatic::default_max_field_deg(p, aim)?,
        };
        lens::analysis::chromatic::chromatic(p, field_deg, max, aim)
    })?
    .py()?;
    to_py(py, &serde_json::to_value(&c).map_err(|e| OpticsError::new_err(e.to_string()))?)
}

/// The point spread function at `field_deg` (the keys of `lens psf
/// --json`, and "intensity": the image, rows from -y to +y, normalised so
/// the same pupil without aberration peaks at 1): `method` "fft" or
/// "huygens", `pad` samples per lambda N_w, `pixels` across (Huygens),
/// `polychromatic` the prescription's wavelengths summed (FFT).
#[pyfunction]
#[pyo3(signature = (prescription, field_deg=0.0, wavelength_nm=None, method="fft", pad=4, pixels=64, grid=None,
    polychromatic=false, aim="auto", film=None, threads=None, field_x_deg=0.0))]
#[allow(clippy::too_many_arguments)]
pub fn psf<'py>(
    py: Python<'py>,
    prescription: &Prescription,
    field_deg: f64,
    wavelength_nm: Option<f64>,
    method: &str,
    pad: usize,
    pixels: usize,
    grid: Option<usize>,
    polychromatic: bool,
    aim: &str,
    film: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    field_x_deg: f64,
) -> PyResult<Bound<'py, PyAny>> {
    use lens::analysis::wave::field_psf::{field_psf, PsfOptions};
    use lens::analysis::wave::psf::PsfMethod;
    let method = match method.to_ascii_lowercase().as_str() {
        "fft" => PsfMethod::Fft,
        "huygens" => PsfMethod::Huygens,
        other => return Err(PyValueError::new_err(format!("method={other:?}: give \"fft\" or \"huygens\""))),
    };
    let plane = plane_of(film)?;
    let s = Setup::new(py, prescription, (field_x_deg, field_deg), wavelength_nm, aim)?;
    if polychromatic {
        warn_range(py, &s.p, s.p.wavelengths_nm())?;
    }
    let options = PsfOptions { method, pad, pixels, grid, polychromatic };
    let f = off_gil(py, threads, || field_psf(&s.p, &s.traced, &s.launcher, plane, &options))?.py()?;
    let report = to_py(py, &lens::report::with_field_x(lens::report::psf(field_deg, plane, &f), field_x_deg))?;
    let n = f.psf.size;
    let image = numpy::ndarray::Array2::from_shape_vec((n, n), f.psf.intensity)
        .map_err(|e| OpticsError::new_err(e.to_string()))?;
    report.set_item("intensity", numpy::IntoPyArray::into_pyarray(image, py))?;
    Ok(report)
}
