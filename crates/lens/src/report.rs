//! The JSON reports of the analyses: what `lens CMD --json` prints and
//! what the Python package returns as dicts, built in one place from the
//! library's results so that both carry the same keys and the same numbers
//! to the bit. Lengths in mm, z from the first vertex, wavelengths in nm,
//! wavefront figures in waves at the wavelength analysed.

use crate::analysis::fan::ImagePlane;
use crate::analysis::spot::SpotDiagram;
use crate::analysis::wave::zernike::ZernikeFit;
use crate::analysis::wave::{Wavefront, WavefrontStats};
use crate::error::OpticsError;
use crate::model::{Finding, Prescription};
use crate::paraxial::{imaging, FirstOrder, ObjectDistance};
use serde_json::{json, Value};

/// `lens info --json`: first-order properties of `p` (at its wavelength)
/// for an object at `object`.
pub fn info(p: &Prescription, object: ObjectDistance) -> Result<Value, OpticsError> {
    let f = FirstOrder::of(p)?;
    let img = imaging(p, &f, object)?;
    let pupil = |z: Option<f64>, d: Option<f64>| json!({"z": z, "diameter": d});
    Ok(json!({
        "name": p.name(),
        "efl": f.efl,
        "bfl": f.bfl,
        "ffd": f.ffd,
        "front_principal_plane": f.front_principal_plane,
        "back_principal_plane": f.back_principal_plane,
        "entrance_pupil": pupil(Some(f.entrance_pupil.z), Some(f.entrance_pupil.diameter)),
        "exit_pupil": pupil(f.exit_pupil.map(|x| x.z), f.exit_pupil.map(|x| x.diameter)),
        "f_number": f.f_number,
        "working_f_number": img.working_f_number,
        "image_distance": img.image_distance,
        "magnification": img.magnification,
        "total_track": f.total_track,
        // decentred or tilted surfaces: the numbers above are the co-axial
        // system's
        "tilted": p.is_tilted(),
    }))
}

/// `lens validate --json` of one file: whether it is valid, the error
/// that kept it from loading (`None` if it loaded), its findings.
pub fn validation(file: &str, valid: bool, error: Option<String>, findings: &[Finding]) -> Value {
    json!({
        "file": file,
        "valid": valid,
        "error": error,
        "findings": findings,
    })
}

/// A field report `v` with `field_x_deg` added when the field has an x
/// component (`x_deg` not 0; a y field's report is unchanged): how the
/// reports of fans, spots, wavefronts, MTFs and PSFs name an x field.
pub fn with_field_x(mut v: Value, x_deg: f64) -> Value {
    if x_deg != 0.0 {
        if let Some(o) = v.as_object_mut() {
            o.insert("field_x_deg".into(), x_deg.into());
        }
    }
    v
}

/// `lens spot --json` of a spot diagram at `field_deg`.
pub fn spot(field_deg: f64, s: &SpotDiagram) -> Value {
    json!({
        "field_deg": field_deg,
        "image_plane": s.image_plane,
        "image_z": s.image_z,
        "wavelengths_nm": s.wavelengths_nm,
        "wavelength_weights": s.wavelength_weights,
        "rays": s.rays,
        "vignetted": s.vignetted,
        "aim_failures": s.aim_failures,
        "centroid": s.centroid,
        "rms_radius": s.rms_radius,
        "rms_radius_chief": s.rms_radius_chief,
        "geo_radius": s.geo_radius,
        "geo_radius_chief": s.geo_radius_chief,
        "chief": s.chief,
        "airy_radius": s.airy_radius,
        "best_focus_shift": s.best_focus_shift,
        "rms_radius_best_focus": s.rms_radius_best_focus,
    })
}

/// The Zernike fits of a wavefront report, Fringe then Standard (`None`
/// where too few rays pass to fit).
pub struct Fits<'a> {
    /// The Fringe fit.
    pub fringe: Option<&'a ZernikeFit>,
    /// The Standard (Noll) fit.
    pub standard: Option<&'a ZernikeFit>,
}

/// `lens wavefront --json`: the wavefront `w` at `field_deg` on `plane`,
/// its statistics `s` and Zernike fits; with `samples`, every cell of the
/// map (`px`, `py` normalised pupil, `weight` its area share, `opd_waves`
/// null where vignetted).
pub fn wavefront(
    field_deg: f64,
    plane: ImagePlane,
    w: &Wavefront,
    s: &WavefrontStats,
    fits: Fits,
    samples: bool,
) -> Value {
    let samples = samples.then(|| {
        let cells = &w.grid.cells;
        json!({
            "px": cells.iter().map(|c| c.centre.0).collect::<Vec<_>>(),
            "py": cells.iter().map(|c| c.centre.1).collect::<Vec<_>>(),
            "weight": cells.iter().map(|c| c.area).collect::<Vec<_>>(),
            "opd_waves": &w.opd_waves,
        })
    });
    let exit = w.exit_pupil;
    let (fringe, standard) = (fits.fringe, fits.standard);
    json!({
        "field_deg": field_deg,
        "wavelength_nm": w.wavelength_nm,
        "image_plane": plane.name(),
        "image_z": w.image_z,
        "pupil_samples": w.grid.n,
        "rays": w.opd_waves.len(),
        "vignetted": w.vignetted,
        "rms_waves": s.rms_to_chief,
        "pv_waves": s.pv_to_chief,
        "rms_centroid_waves": s.rms_to_centroid,
        "pv_centroid_waves": s.pv_to_centroid,
        "strehl": s.strehl,
        "zernike_fringe": fringe.map(|f| &f.coefficients),
        "zernike_fringe_order": "Fringe (University of Arizona) order, 1-based, not normalised, waves",
        "zernike_standard": standard.map(|f| &f.coefficients),
        "zernike_standard_order": "Standard (Noll) order, 1-based, RMS-normalised, waves",
        "zernike_fringe_rms_residual_waves": fringe.map(|f| f.rms_residual),
        "zernike_standard_rms_residual_waves": standard.map(|f| f.rms_residual),
        "exit_pupil_mm": exit.map(|e| e.diameter),
        "exit_pupil_z": exit.map(|e| e.z),
        "reference_radius_mm": w.reference_radius,
        "chief_image": [w.chief_image.x, w.chief_image.y, w.chief_image.z],
        "samples": samples,
    })
}

/// The geometric MTF beside a diffraction MTF report: tangential and
/// sagittal at the same frequencies, and whether they were scaled by the
/// diffraction limit.
pub struct GeometricMtf<'a> {
    /// Tangential values.
    pub tangential: &'a [f64],
    /// Sagittal values.
    pub sagittal: &'a [f64],
    /// Whether each was multiplied by the diffraction limit.
    pub scaled_by_diffraction_limit: bool,
}

/// `lens mtf --json` at one field: the MTF `m` at `field_deg` on `plane`,
/// `waves` the (nm, weight) pairs of a polychromatic MTF (`None`:
/// monochromatic), `axis_cutoff` the on-axis cutoff 1 / (lambda N_w)
/// (cycles/mm), `geometric` the geometric MTF where asked.
pub fn mtf(
    field_deg: f64,
    plane: ImagePlane,
    m: &crate::analysis::wave::mtf::Mtf,
    waves: Option<&[(f64, f64)]>,
    axis_cutoff: f64,
    geometric: Option<GeometricMtf>,
) -> Value {
    json!({
        "field_deg": field_deg,
        "wavelength_nm": m.wavelength_nm,
        "wavelengths_nm": waves.map(|w| w.iter().map(|x| x.0).collect::<Vec<_>>()),
        "wavelength_weights": waves.map(|w| w.iter().map(|x| x.1).collect::<Vec<_>>()),
        "image_plane": plane.name(),
        "image_z": m.image_z,
        "frequencies_per_mm": m.frequencies_per_mm,
        "tangential": m.tangential,
        "sagittal": m.sagittal,
        "cutoff_per_mm": axis_cutoff,
        "cutoff_tangential_per_mm": m.cutoff_tangential_per_mm,
        "cutoff_sagittal_per_mm": m.cutoff_sagittal_per_mm,
        "diffraction_limit": {"tangential": m.diffraction_limit_tangential, "sagittal": m.diffraction_limit_sagittal},
        "quadrature_nodes": m.nodes,
        "geometric": geometric.map(|g| json!({
            "tangential": g.tangential,
            "sagittal": g.sagittal,
            "scaled_by_diffraction_limit": g.scaled_by_diffraction_limit,
        })),
    })
}

/// `lens psf --json` of a field's PSF at `field_deg` on `plane`.
pub fn psf(field_deg: f64, plane: ImagePlane, f: &crate::analysis::wave::field_psf::FieldPsf) -> Value {
    let (w, psf, radii) = (&f.wavefront, &f.psf, &f.radii_mm);
    let waves = f.wavelengths.as_ref();
    json!({
        "method": psf.method.name(),
        "field_deg": field_deg,
        "wavelength_nm": w.wavelength_nm,
        "wavelengths_nm": waves.map(|w| w.iter().map(|x| x.0).collect::<Vec<_>>()),
        "wavelength_weights": waves.map(|w| w.iter().map(|x| x.1).collect::<Vec<_>>()),
        "image_plane": plane.name(),
        "image_z": w.image_z,
        "pupil_samples": w.grid.n,
        "size": psf.size,
        "pixel_x_mm": psf.pixel_mm.0,
        "pixel_y_mm": psf.pixel_mm.1,
        "strehl": f.stats.strehl,
        "strehl_wavelength_nm": w.wavelength_nm,
        "peak": psf.peak(),
        "centroid_mm": [f.centroid.0, f.centroid.1],
        "chief_image": [w.chief_image.x, w.chief_image.y, w.chief_image.z],
        "encircled_energy": {"radius_mm": radii, "fraction": f.encircled},
        "geometric_encircled_energy": {"radius_mm": radii, "fraction": f.geometric_encircled},
        "ensquared_energy": {"half_width_mm": radii, "fraction": f.ensquared},
    })
}

/// `lens tolerance --json`: the sensitivity table and Monte Carlo
/// statistics of a whole run (`share` holds every trial), `seconds` its
/// wall time.
pub fn tolerance(
    tol: &crate::tolerance::Tolerancing,
    share: &crate::tolerance::Share,
    stats: &crate::tolerance::Statistics,
    seconds: f64,
) -> Value {
    let x = &tol.criterion.fields_x_deg;
    let mut v = json!({
        "digest": share.digest,
        "seed": share.seed,
        "criterion": tol.criterion.kind,
        "fields_deg": tol.criterion.fields_deg,
        "nominal": share.nominal,
        "sensitivity": share.sensitivity,
        "monte_carlo": stats,
        "tolerances": tol.tolerances.iter().map(|t| t.label()).collect::<Vec<_>>(),
        "seconds": seconds,
        "seconds_per_trial": seconds / share.trials.max(1) as f64,
    });
    // fields with x components: each field's x, in the order of fields_deg
    if x.iter().any(|&x| x != 0.0) {
        v["fields_x_deg"] = json!(x);
    }
    v
}
