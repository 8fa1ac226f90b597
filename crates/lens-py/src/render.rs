//! `lens.render`: a scene file rendered into a numpy array, with the CLI's
//! overrides (`lens render`'s flags of the same names).

use crate::errors::RenderError;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The most samples per pixel (as the CLI).
const MAX_SPP: u32 = 1 << 20;

/// Renders the scene file `scene` and returns its image as an (H, W, 3)
/// float32 array of linear RGB (exposure not applied, as the EXR the CLI
/// writes). Overrides as `lens render`'s flags: `width`, `height` (one
/// alone keeps the scene's aspect), `spp`,
/// `seed`, `camera` ("pinhole", "thin-lens", "lens"), `f_number`,
/// `aperture` (m), `focal_length_mm`, `focus_distance` (m), `focus_shift`
/// (mm), `aperture_shape`, `prescription` (a lens file for the camera);
/// `threads` (None: every core); `focus_on` (autofocus: a shape's name, or
/// a pixel `(column, row)` from the top left, as `--focus-on`). Scene
/// warnings become `UserWarning`s.
#[pyfunction]
#[pyo3(signature = (scene, width=None, height=None, spp=None, seed=1, camera=None, f_number=None, aperture=None,
    focal_length_mm=None, focus_distance=None, focus_shift=None, aperture_shape=None, prescription=None, threads=None, focus_on=None))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    scene: std::path::PathBuf,
    width: Option<u32>,
    height: Option<u32>,
    spp: Option<u32>,
    seed: u64,
    camera: Option<&str>,
    f_number: Option<f64>,
    aperture: Option<f64>,
    focal_length_mm: Option<f64>,
    focus_distance: Option<f64>,
    focus_shift: Option<f64>,
    aperture_shape: Option<&str>,
    prescription: Option<std::path::PathBuf>,
    threads: Option<usize>,
    focus_on: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    use ::render::scene::{CameraKind, Overrides};
    let camera = match camera.map(str::to_ascii_lowercase).as_deref() {
        None => None,
        Some("pinhole") => Some(CameraKind::Pinhole),
        Some("thin-lens") | Some("thin_lens") => Some(CameraKind::ThinLens),
        Some("lens") => Some(CameraKind::Lens),
        Some(other) => {
            return Err(PyValueError::new_err(format!("camera={other:?}: give \"pinhole\", \"thin-lens\" or \"lens\"")))
        }
    };
    let aperture_shape = match aperture_shape {
        Some(s) => Some(Overrides::parse_shape(s).map_err(|e| PyValueError::new_err(format!("aperture_shape: {e}")))?),
        None => None,
    };
    let focus_on = match focus_on {
        None => None,
        Some(v) => Some(match v.extract::<String>() {
            Ok(name) => ::render::scene::format::FocusOn::Shape(name),
            Err(_) => {
                let (x, y) = v.extract::<(f64, f64)>().map_err(|_| {
                    PyValueError::new_err("focus_on: give a shape's name (str) or a pixel (column, row)")
                })?;
                ::render::scene::format::FocusOn::Pixel([x, y])
            }
        }),
    };
    if focus_on.is_some() && focus_distance.is_some() {
        return Err(PyValueError::new_err("give focus_distance or focus_on, not both"));
    }
    let overrides = Overrides {
        width,
        height,
        spp: None,
        camera,
        aperture,
        f_number,
        focal_length_mm,
        focus_distance,
        focus_on,
        focus_shift,
        aperture_shape,
        prescription,
        strict_glass_range: false,
        flare: None,
        coating: None,
        diffraction: None,
    };
    let s = ::render::Scene::load_with(&scene, &overrides).map_err(|e| RenderError::new_err(e.to_string()))?;
    for w in &s.glass_warnings {
        crate::errors::warn_glass_range(py, w)?;
    }
    for w in &s.warnings {
        crate::errors::warn_user(py, w)?;
    }
    let spp = spp.unwrap_or(s.film.spp);
    if spp == 0 || spp > MAX_SPP {
        return Err(PyValueError::new_err(format!("spp={spp}: give 1 to {MAX_SPP} samples per pixel")));
    }
    let pool = crate::trace::pool(threads)?;
    let image = py.detach(|| pool.install(|| ::render::render(&s, ::render::Options { spp, seed }, &|_| {}).0));
    let data: Vec<f32> = image.pixels.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect();
    let a = Array3::from_shape_vec((image.height, image.width, 3), data)
        .map_err(|e| RenderError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}
