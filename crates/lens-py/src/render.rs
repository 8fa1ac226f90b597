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
/// a pixel `(column, row)` from the top left, as `--focus-on`); `flare`
/// ("off", "ghosts", "ghosts+glare", as `--flare`), `diffraction` ("off"
/// or "on", or a bool, as `--diffraction`), `coating` (every surface of a
/// real lens: "none", "MgF2", or a list of layers from the object side,
/// each a dict `{"index": n, "thickness_nm": t}` or a tuple `(n, t)`, as
/// the scene's `camera.coating`). Scene warnings become `UserWarning`s.
#[pyfunction]
#[pyo3(signature = (scene, width=None, height=None, spp=None, seed=1, camera=None, f_number=None, aperture=None,
    focal_length_mm=None, focus_distance=None, focus_shift=None, aperture_shape=None, prescription=None, threads=None, focus_on=None,
    flare=None, diffraction=None, coating=None))]
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
    flare: Option<&str>,
    diffraction: Option<Bound<'py, PyAny>>,
    coating: Option<Bound<'py, PyAny>>,
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
    let flare = match flare {
        Some(f) => Some(f.parse().map_err(|e: String| PyValueError::new_err(format!("flare={f:?}: {e}")))?),
        None => None,
    };
    let diffraction = match diffraction {
        None => None,
        Some(v) => Some(match v.extract::<bool>() {
            Ok(true) => ::render::scene::format::DiffractionSpec::On,
            Ok(false) => ::render::scene::format::DiffractionSpec::Off,
            Err(_) => {
                let s = v
                    .extract::<String>()
                    .map_err(|_| PyValueError::new_err("diffraction: give \"off\", \"on\" or a bool"))?;
                s.parse().map_err(|e: String| PyValueError::new_err(format!("diffraction={s:?}: {e}")))?
            }
        }),
    };
    let coating = match coating {
        None => None,
        Some(v) => Some(coating_spec(&v)?),
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
        flare,
        coating,
        diffraction,
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

/// A coating given from Python: a name, or layers as dicts
/// `{"index", "thickness_nm"}` or `(index, thickness_nm)` tuples; checked
/// as the scene file's.
fn coating_spec(v: &Bound<'_, PyAny>) -> PyResult<lens::model::CoatingSpec> {
    use lens::model::{CoatingSpec, LayerSpec};
    const HELP: &str =
        "coating: give \"none\", \"MgF2\" or a list of layers, each {\"index\": n, \"thickness_nm\": t} or (n, t)";
    let spec = if let Ok(name) = v.extract::<String>() {
        CoatingSpec::Name(name)
    } else {
        let items: Vec<Bound<'_, PyAny>> = v.extract().map_err(|_| PyValueError::new_err(HELP))?;
        let mut layers = Vec::with_capacity(items.len());
        for (k, item) in items.iter().enumerate() {
            let (index, thickness_nm) = if let Ok(t) = item.extract::<(f64, f64)>() {
                t
            } else if let Ok(d) = item.cast::<pyo3::types::PyDict>() {
                if d.len() != 2 {
                    return Err(PyValueError::new_err(format!(
                        "coating layer {}: give exactly index and thickness_nm",
                        k + 1
                    )));
                }
                let get = |key: &str| -> PyResult<f64> {
                    d.get_item(key)?
                        .ok_or_else(|| PyValueError::new_err(format!("coating layer {}: missing {key}", k + 1)))?
                        .extract::<f64>()
                        .map_err(|_| PyValueError::new_err(format!("coating layer {}: {key} must be a number", k + 1)))
                };
                (get("index")?, get("thickness_nm")?)
            } else {
                return Err(PyValueError::new_err(HELP));
            };
            layers.push(LayerSpec { index, thickness_nm });
        }
        CoatingSpec::Layers(layers)
    };
    spec.coating().map_err(|e| PyValueError::new_err(format!("coating: {e}")))?;
    Ok(spec)
}
