//! Checks a prescription as written and reports every finding, not the first.

use super::finding::{Finding, Severity};
use super::motion_check::{check_elements, check_motion, check_moved_edge, placements, rigid_pair};
use super::spec::{PrescriptionSpec, SurfaceSpec};
use crate::error::num;

pub(super) struct Findings(Vec<Finding>);

impl Findings {
    pub(super) fn push(
        &mut self,
        severity: Severity,
        surface: Option<usize>,
        field: Option<&'static str>,
        message: String,
    ) {
        self.0.push(Finding { severity, surface, field, message });
    }
    pub(super) fn error(&mut self, surface: usize, field: &'static str, message: String) {
        self.push(Severity::Error, Some(surface), Some(field), message);
    }
}

/// Number of heights sampled across the common aperture when looking for
/// surfaces that cross (negative edge thickness).
const EDGE_SAMPLES: usize = 256;

/// Validates a prescription as written. Returns every finding, errors and
/// warnings, in surface order; an empty list means the prescription is clean.
///
/// Errors: units other than mm; no surfaces; non-finite numbers; radius 0;
/// thickness < 0; semi-diameter <= 0 or larger than |radius|; ior < 1; no stop
/// or several stops; a stop without a semi-diameter; consecutive surfaces that
/// cross inside their common aperture; last thickness <= 0.
/// Warnings: surfaces without a semi-diameter (they do not clip rays).
///
/// ```
/// use lens::{PrescriptionSpec, model::validate::validate};
/// let spec = PrescriptionSpec::from_json_str(r#"{"surfaces": [
///   {"radius": 12, "thickness": 2, "ior": 1.5, "semi_diameter": 14, "stop": true},
///   {"thickness": 20}]}"#, "<doc>").unwrap();
/// let findings = validate(&spec);
/// assert!(findings[0].to_string().contains("surface 1: semi_diameter 14 mm exceeds |radius| 12 mm"));
/// ```
pub fn validate(spec: &PrescriptionSpec) -> Vec<Finding> {
    let mut out = Findings(Vec::new());
    if let Some(units) = &spec.units {
        if units != "mm" {
            out.push(
                Severity::Error,
                None,
                Some("units"),
                format!("units \"{units}\" are not supported: write lengths in millimetres and set \"units\": \"mm\""),
            );
        }
    }
    let good_nm = |w: &f64| w.is_finite() && *w > 0.0;
    if let Some(w) = &spec.wavelengths_nm {
        if w.is_empty() || !w.iter().all(good_nm) {
            out.push(
                Severity::Error,
                None,
                Some("wavelengths_nm"),
                "wavelengths_nm must list at least one positive wavelength in nm".into(),
            );
        }
    }
    if let Some(weights) = &spec.wavelength_weights {
        let count = spec.wavelengths_nm.as_ref().map_or(3, Vec::len);
        if weights.len() != count {
            out.push(
                Severity::Error,
                None,
                Some("wavelength_weights"),
                format!(
                    "{} wavelength_weights for {count} wavelengths: give one weight per wavelength of wavelengths_nm (F, d, C when it is not given), in its order",
                    weights.len()
                ),
            );
        } else if !weights.iter().all(|w| w.is_finite() && *w >= 0.0) || !weights.iter().any(|w| *w > 0.0) {
            out.push(
                Severity::Error,
                None,
                Some("wavelength_weights"),
                "wavelength_weights must be finite numbers >= 0, at least one above 0".into(),
            );
        }
    }
    if let Some(w) = spec.primary_wavelength_nm {
        if !good_nm(&w) {
            out.push(
                Severity::Error,
                None,
                Some("primary_wavelength_nm"),
                format!("primary_wavelength_nm = {}: give a positive wavelength in nm", crate::error::exact(w)),
            );
        }
    }
    if let Some(v) = &spec.vignetting_factors {
        let fields = spec.fields_deg.as_ref().map_or(0, Vec::len);
        if v.len() != fields {
            out.push(
                Severity::Error,
                None,
                Some("vignetting_factors"),
                format!(
                    "{} vignetting_factors for {fields} fields_deg: give one set per field, in the order of fields_deg",
                    v.len()
                ),
            );
        }
        for (k, f) in v.iter().enumerate() {
            let all = [f.decenter_x, f.decenter_y, f.compress_x, f.compress_y];
            if !all.iter().all(|x| x.is_finite()) || f.compress_x >= 1.0 || f.compress_y >= 1.0 {
                out.push(
                    Severity::Error,
                    None,
                    Some("vignetting_factors"),
                    format!(
                        "vignetting_factors of field {} ({all:?}): give finite numbers, compress_x and compress_y \
                         below 1 (1 would close the pupil)",
                        k + 1
                    ),
                );
            }
        }
    }
    if spec.surfaces.is_empty() {
        out.push(Severity::Error, None, Some("surfaces"), "no surfaces: list at least one surface".into());
        return out.0;
    }
    if spec.surfaces.len() > MAX_SURFACES {
        out.push(
            Severity::Error,
            None,
            Some("surfaces"),
            format!(
                "{} surfaces: at most {MAX_SURFACES} (camera lenses have a few dozen); is this the right file?",
                spec.surfaces.len()
            ),
        );
        return out.0;
    }
    for (i, s) in spec.surfaces.iter().enumerate() {
        check_surface(&mut out, i + 1, s);
        check_paraxial(&mut out, spec, i);
        check_motion(&mut out, Some(i + 1), "", s.decenter_mm, s.tilt_deg);
    }
    let elements_fine = check_elements(&mut out, spec);
    if let Some([a, b]) = spec.focus_group {
        let n = spec.surfaces.len();
        let air = |k: usize| spec.surfaces.get(k).is_some_and(|s| s.glass.is_none() && s.ior.is_none_or(|n| n == 1.0));
        if a >= 2 && a <= b && b < n && !(air(a - 2) && air(b - 1)) {
            out.push(
                Severity::Error,
                None,
                Some("focus_group"),
                format!(
                    "focus_group [{a}, {b}]: the gaps before and after the group (after surfaces {} and {b}) must be air, or \
                     moving it would change a glass's thickness; name the surfaces of whole elements",
                    a - 1
                ),
            );
        }
        if !(a >= 2 && a <= b && b < n) {
            out.push(
                Severity::Error,
                None,
                Some("focus_group"),
                format!(
                    "focus_group [{a}, {b}]: give the group's first and last surfaces, numbered from 1, with a surface before it \
                     and one after it (2 <= first <= last <= {})",
                    n - 1
                ),
            );
        }
    }
    let stops: Vec<usize> = spec.surfaces.iter().enumerate().filter(|(_, s)| s.stop).map(|(i, _)| i + 1).collect();
    match stops.len() {
        0 => out.push(
            Severity::Error,
            None,
            Some("stop"),
            "no aperture stop: mark exactly one surface with \"stop\": true".into(),
        ),
        1 => {
            let s = &spec.surfaces[stops[0] - 1];
            if s.semi_diameter.is_none() {
                out.error(
                    stops[0],
                    "semi_diameter",
                    "the aperture stop has no semi_diameter: give the stop's clear radius in mm".into(),
                );
            }
        }
        _ => out.push(
            Severity::Error,
            None,
            Some("stop"),
            format!(
                "{} surfaces are marked as the stop (surfaces {}): keep \"stop\": true on exactly one",
                stops.len(),
                stops.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", ")
            ),
        ),
    }
    let moved = if elements_fine { placements(spec) } else { None };
    for i in 0..spec.surfaces.len().saturating_sub(1) {
        match &moved {
            Some(at) if !rigid_pair(spec, at, i) => check_moved_edge(&mut out, spec, at, i),
            _ => check_edge(&mut out, spec, i),
        }
    }
    if let Some(last) = spec.surfaces.last() {
        if last.thickness.is_finite() && last.thickness <= 0.0 {
            out.error(
                spec.surfaces.len(),
                "thickness",
                format!(
                    "the last thickness is the distance to the film and must be > 0 mm (got {} mm)",
                    last.thickness
                ),
            );
        }
    }
    out.0.sort_by_key(|f| f.surface.unwrap_or(0));
    out.0
}

/// The smallest |radius| a surface may have, mm (1/radius must stay a
/// sensible number: a subnormal radius would make the curvature infinite).
pub const MIN_RADIUS: f64 = 1e-6;
/// The largest thickness or semi-diameter, mm (sums of many of them stay
/// far from overflow).
pub const MAX_LENGTH: f64 = 1e9;
/// The most surfaces a prescription may have.
pub const MAX_SURFACES: usize = 1000;
/// The largest constant refractive index (germanium, the highest optical
/// material in common use, is about 4 in the infrared).
pub const MAX_IOR: f64 = 10.0;

/// A surface's `type` and `focal_length_mm`: an ideal (`"paraxial"`)
/// surface needs a finite, non-zero focal length, is a plane, and has the
/// same medium on both sides.
fn check_paraxial(out: &mut Findings, spec: &PrescriptionSpec, i: usize) {
    let (s, n) = (&spec.surfaces[i], i + 1);
    match s.kind.as_deref() {
        None => {
            if s.focal_length_mm.is_some() {
                out.error(
                    n,
                    "focal_length_mm",
                    "focal_length_mm belongs to an ideal lens: add \"type\": \"paraxial\", or remove focal_length_mm".into(),
                );
            }
        }
        Some("paraxial") => {
            match s.focal_length_mm {
                None => out.error(
                    n,
                    "focal_length_mm",
                    "a paraxial surface needs focal_length_mm (mm; negative for a diverging lens)".into(),
                ),
                Some(f) if !f.is_finite() || f == 0.0 || f.abs() > MAX_LENGTH => out.error(
                    n,
                    "focal_length_mm",
                    format!("focal_length_mm {}: give a finite focal length in mm, not 0", num(f)),
                ),
                Some(_) => {}
            }
            if s.radius.is_some() || s.is_aspheric() {
                out.error(
                    n,
                    "type",
                    "a paraxial surface is a plane: remove its radius, conic and aspheric terms".into(),
                );
            }
            let before = if i == 0 { (1.0, None) } else { (spec.surfaces[i - 1].ior.unwrap_or(1.0), spec.surfaces[i - 1].glass.as_ref()) };
            if (s.ior.unwrap_or(1.0), s.glass.as_ref()) != before {
                out.error(
                    n,
                    "ior",
                    "a paraxial surface has the same medium on both sides: give it the ior or glass of the medium before it (an ideal lens in glass is two surfaces: the glass's, then the paraxial one)".into(),
                );
            }
        }
        Some(other) => out.error(
            n,
            "type",
            format!("type \"{other}\" is not a surface type: omit it (a sphere, plane or asphere) or give \"paraxial\" with focal_length_mm"),
        ),
    }
}

fn check_surface(out: &mut Findings, n: usize, s: &SurfaceSpec) {
    if let Some(r) = s.radius {
        if !r.is_finite() {
            out.error(
                n,
                "radius",
                format!("radius {r} is not a finite number: give a radius in mm or omit it for a plane"),
            );
        } else if r == 0.0 {
            out.error(n, "radius", "radius 0 is not a surface: omit \"radius\" (or use null) for a plane".into());
        } else if r.abs() < MIN_RADIUS {
            out.error(
                n,
                "radius",
                format!(
                    "radius {} mm is smaller than {MIN_RADIUS} mm: no lens surface is that curved (omit \"radius\" for a plane)",
                    num(r)
                ),
            );
        }
    }
    if !s.thickness.is_finite() {
        out.error(n, "thickness", format!("thickness {} is not a finite number of mm", s.thickness));
    } else if s.thickness > MAX_LENGTH {
        out.error(
            n,
            "thickness",
            format!(
                "thickness {} mm is over {} mm (1000 km): give the axial distance in mm",
                num(s.thickness),
                num(MAX_LENGTH)
            ),
        );
    } else if s.thickness < 0.0 {
        out.error(
            n,
            "thickness",
            format!("thickness {} mm is negative: give the axial distance to the next surface (>= 0)", s.thickness),
        );
    }
    check_asphere_terms(out, n, s);
    if s.ior.is_some() && s.glass.is_some() {
        out.error(
            n,
            "glass",
            "both \"ior\" and \"glass\" are given: keep one (a glass for a dispersive medium, ior for a constant index)".into(),
        );
    }
    if let Some(super::spec::GlassSpec::Model { nd, vd }) = s.glass {
        if !(nd.is_finite() && nd > 1.0 && nd <= MAX_IOR && vd.is_finite() && vd > 0.0) {
            out.error(n, "glass", format!("model glass nd = {nd}, vd = {vd}: give 1 < nd <= 10 and vd > 0"));
        }
    }
    if let Some(ior) = s.ior {
        if !ior.is_finite() || ior < 1.0 {
            out.error(n, "ior", format!("ior {ior} is not a refractive index >= 1 (1.0 is air; omit it for air)"));
        } else if ior > MAX_IOR {
            out.error(
                n,
                "ior",
                format!("ior {} is above {MAX_IOR}: no optical material has an index that high", num(ior)),
            );
        }
    }
    if let Some(sd) = s.semi_diameter {
        if sd.is_finite() && sd > MAX_LENGTH {
            out.error(
                n,
                "semi_diameter",
                format!("semi_diameter {} mm is over {} mm (1000 km)", num(sd), num(MAX_LENGTH)),
            );
        }
    }
    match s.semi_diameter {
        None if !s.stop => out.push(
            Severity::Warning,
            Some(n),
            Some("semi_diameter"),
            "no semi_diameter: this surface does not clip rays; give its clear radius in mm".into(),
        ),
        None => {}
        Some(sd) if !sd.is_finite() || sd <= 0.0 => {
            out.error(n, "semi_diameter", format!("semi_diameter {sd} mm must be a positive number of mm"))
        }
        Some(sd) if sd < MIN_RADIUS => out.error(
            n,
            "semi_diameter",
            format!("semi_diameter {} mm is smaller than {MIN_RADIUS} mm: no light gets through; give the clear radius in mm", num(sd)),
        ),
        Some(sd) if s.is_aspheric() => check_asphere_reach(out, n, s, sd),
        Some(sd) => {
            if let Some(r) = s.radius {
                if r.is_finite() && r != 0.0 && sd > r.abs() {
                    out.error(
                        n,
                        "semi_diameter",
                        format!(
                            "semi_diameter {sd} mm exceeds |radius| {} mm: the sphere is smaller than the aperture; reduce semi_diameter to at most {} mm",
                            r.abs(),
                            r.abs()
                        ),
                    );
                }
            }
        }
    }
}

/// The asphere's numbers: a finite conic constant, finite coefficients, no
/// more terms than the model holds.
fn check_asphere_terms(out: &mut Findings, n: usize, s: &SurfaceSpec) {
    use super::surface::MAX_ASPHERE_POWER;
    if let Some(k) = s.conic {
        if !k.is_finite() {
            out.error(
                n,
                "conic",
                format!("conic {k} is not a finite number: give the conic constant (0 for a sphere)"),
            );
        }
    }
    for (field, terms, most) in
        [("aspheric", &s.aspheric, MAX_ASPHERE_POWER / 2), ("odd_aspheric", &s.odd_aspheric, MAX_ASPHERE_POWER)]
    {
        let Some(terms) = terms else { continue };
        if terms.len() > most {
            out.error(
                n,
                field,
                format!(
                    "{} {field} terms: at most {most} (to r^{MAX_ASPHERE_POWER}); drop the trailing ones",
                    terms.len()
                ),
            );
        }
        if let Some((j, a)) = terms.iter().enumerate().find(|(_, a)| !a.is_finite()) {
            out.error(n, field, format!("{field} term {} is {a}: give finite coefficients", j + 1));
        }
    }
}

/// An asphere's profile must exist over the whole clear aperture: the
/// conic's square root real out to the semi-diameter, and no non-finite sag
/// (checked at [`EDGE_SAMPLES`] heights).
fn check_asphere_reach(out: &mut Findings, n: usize, s: &SurfaceSpec, sd: f64) {
    let Some(c) = s.curvature() else { return };
    if s.asphere().is_none() {
        return; // too many or bad terms: reported by check_asphere_terms
    }
    for k in 0..=EDGE_SAMPLES {
        let h = sd * k as f64 / EDGE_SAMPLES as f64;
        if !s.sag(h).is_some_and(f64::is_finite) {
            let k1 = 1.0 + s.conic.unwrap_or(0.0);
            let reach = if k1 > 0.0 && c != 0.0 { 1.0 / (c.abs() * k1.sqrt()) } else { f64::INFINITY };
            out.error(
                n,
                "semi_diameter",
                format!(
                    "the asphere is not defined at height {} mm inside semi_diameter {} mm (the conic reaches {} mm): reduce semi_diameter or check radius and conic",
                    num(h),
                    num(sd),
                    num(reach)
                ),
            );
            return;
        }
    }
}

/// Checks that surfaces i and i+1 (0-based) do not cross inside their common
/// clear aperture: edge thickness t + sag(i+1, h) - sag(i, h) >= 0.
fn check_edge(out: &mut Findings, spec: &PrescriptionSpec, i: usize) {
    let a = &spec.surfaces[i];
    let b = &spec.surfaces[i + 1];
    let (Some(ca), Some(cb)) = (a.curvature(), b.curvature()) else { return };
    let ok = |v: Option<f64>| v.filter(|x| x.is_finite() && *x > 0.0);
    let h_max = match (ok(a.semi_diameter), ok(b.semi_diameter)) {
        (Some(x), Some(y)) => x.min(y),
        (Some(x), None) | (None, Some(x)) => x,
        (None, None) => return,
    };
    // Stay on both spheres (a semi-diameter beyond |R| is reported
    // separately; so is an asphere not defined out to it).
    let mut h_max = h_max;
    for (c, s) in [(ca, a), (cb, b)] {
        if c != 0.0 && !s.is_aspheric() {
            h_max = h_max.min(1.0 / c.abs());
        }
    }
    if !a.thickness.is_finite() || a.thickness < 0.0 {
        return;
    }
    let mut worst = (f64::INFINITY, 0.0);
    for k in 0..=EDGE_SAMPLES {
        let h = h_max * k as f64 / EDGE_SAMPLES as f64;
        if let (Some(sa), Some(sb)) = (a.sag(h), b.sag(h)) {
            let edge = a.thickness + sb - sa;
            if edge < worst.0 {
                worst = (edge, h);
            }
        }
    }
    // Tolerance for rounding in the sags of surfaces that touch at the rim.
    let tol = 1e-9 * (1.0 + a.thickness.abs() + h_max);
    if worst.0 < -tol {
        let medium = match (a.ior, &a.glass) {
            (_, Some(_)) => "glass",
            (Some(n), _) if n != 1.0 => "glass",
            _ => "air",
        };
        out.error(
            i + 1,
            "thickness",
            format!(
                "surfaces {} and {} cross inside their common aperture: the {medium} between them is {:.6} mm thick at height {:.4} mm; increase thickness of surface {} by at least {:.6} mm or reduce the semi_diameters",
                i + 1,
                i + 2,
                worst.0,
                worst.1,
                i + 1,
                -worst.0
            ),
        );
    }
}
