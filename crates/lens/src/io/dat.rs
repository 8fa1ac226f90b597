//! Import of pbrt-v4 realistic-camera lens files (`.dat`).
//!
//! Each non-comment line holds four numbers: radius (mm), thickness to the
//! next surface (mm), index after the surface and aperture DIAMETER (mm),
//! front (object side) first. Radius 0 marks the aperture stop (a plane);
//! index 0 means air. A last thickness of 0 means "put the film at the
//! paraxial focus for an object at infinity".

use crate::error::LoadError;
use crate::model::{Prescription, PrescriptionSpec, SurfaceSpec};

/// Parses a pbrt `.dat` lens file into a prescription spec (not yet
/// validated). `origin` names the file in errors.
///
/// ```
/// let text = "# a singlet\n50 3 1.5 20\n0 1 0 16\n-50 0 1 20\n";
/// let spec = lens::io::dat::parse_dat(text, "<doc>").unwrap();
/// assert!(spec.surfaces[1].stop);
/// // the film was placed at the paraxial focus for infinity
/// assert!(spec.surfaces[2].thickness > 40.0);
/// ```
pub fn parse_dat(text: &str, origin: &str) -> Result<PrescriptionSpec, LoadError> {
    let mut surfaces = Vec::new();
    let mut comments = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if let Some(c) = line.strip_prefix('#') {
            let c = c.trim().trim_matches('"').trim();
            // the column header ("radius axpos N aperture") is not a comment
            let lower = c.to_ascii_lowercase();
            let header = lower.contains("radius") && lower.contains("aperture");
            if !c.is_empty() && !header {
                comments.push(c.to_string());
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let err = |message: String| LoadError::Dat { origin: origin.to_string(), line: k + 1, message };
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.len() != 4 {
            return Err(err(format!(
                "expected 4 numbers (radius, thickness, ior, aperture diameter), found {}",
                fields.len()
            )));
        }
        let mut v = [0.0; 4];
        for (slot, (f, what)) in
            v.iter_mut().zip(fields.iter().zip(["radius", "thickness", "ior", "aperture diameter"]))
        {
            *slot = f.parse::<f64>().map_err(|_| err(format!("{what} \"{f}\" is not a number")))?;
        }
        let [radius, thickness, ior, diameter] = v;
        let stop = radius == 0.0;
        surfaces.push(SurfaceSpec {
            ior: Some(if ior == 0.0 { 1.0 } else { ior }),
            semi_diameter: Some(diameter / 2.0),
            stop,
            ..SurfaceSpec::new((!stop).then_some(radius), thickness)
        });
    }
    let mut spec = PrescriptionSpec {
        name: comments.first().cloned(),
        source: (comments.len() > 1).then(|| comments[1..].join("; ")),
        units: Some("mm".into()),
        wavelengths_nm: None,
        primary_wavelength_nm: None,
        surfaces,
        ..PrescriptionSpec::default()
    };
    focus_last_thickness_at_infinity(&mut spec);
    Ok(spec)
}

/// pbrt's convention: a last thickness of 0 places the film at the paraxial
/// focus for an object at infinity. Leaves the spec unchanged when it cannot
/// be focused (validation then reports why).
fn focus_last_thickness_at_infinity(spec: &mut PrescriptionSpec) {
    let Some(last) = spec.surfaces.last() else { return };
    if last.thickness != 0.0 {
        return;
    }
    let mut probe = spec.clone();
    if let Some(l) = probe.surfaces.last_mut() {
        l.thickness = 1.0;
    }
    let Ok(p) = Prescription::from_spec(&probe) else { return };
    if let Ok(first) = crate::paraxial::FirstOrder::of(&p) {
        if let Some(l) = spec.surfaces.last_mut() {
            l.thickness = first.bfl;
        }
    }
}

/// The prescription as a pbrt-v4 realistic-camera lens file (the format
/// [`parse_dat`] reads): one line per surface, front first, of radius,
/// thickness to the next surface (the last: to the film), the index after
/// the surface (1 for air) and the aperture diameter, all mm; the stop a
/// line of radius 0 (index 0 when air follows it, as pbrt's files write
/// it). A stop on a lens surface becomes a radius-0 line of thickness 0
/// just before that surface.
///
/// `wavelength_nm`: pbrt-v4's file holds one index per element (no
/// dispersion), so a lens with glasses is written at that wavelength and
/// refused without one. Also refused, each with the surface and the
/// reason: aspheres (pbrt traces spheres), paraxial surfaces, decentred or
/// tilted surfaces, plane refracting surfaces (radius 0 is pbrt's
/// aperture stop) and surfaces with no clear aperture (pbrt needs every
/// diameter).
///
/// ```
/// let p = lens::Prescription::load(
///     std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/double-gauss-50mm.json"),
/// )
/// .unwrap();
/// assert!(lens::io::dat::write_dat(&p, None).unwrap_err().contains("--wavelength-nm"));
/// let text = lens::io::dat::write_dat(&p, Some(587.5618)).unwrap();
/// let back = lens::io::dat::parse_dat(&text, "<doc>").unwrap();
/// assert_eq!(back.surfaces.len(), p.surfaces().len());
/// ```
pub fn write_dat(p: &Prescription, wavelength_nm: Option<f64>) -> Result<String, String> {
    let dispersive = p.surfaces().iter().any(|s| s.glass.is_some());
    let at = match wavelength_nm {
        Some(w) => p.at_wavelength(w).map_err(|e| e.to_string())?,
        None if dispersive => {
            return Err("pbrt-v4's lens file holds one index per element (no dispersion), and this lens has glasses: \
                 give --wavelength-nm to write their indices at one wavelength"
                .into())
        }
        None => p.clone(),
    };
    let mut out = format!("# {}\n", p.name().replace(['\n', '\r'], " "));
    if let Some(w) = wavelength_nm.filter(|_| dispersive) {
        out.push_str(&format!("# indices at {w} nm (pbrt-v4 has no dispersion)\n"));
    }
    out.push_str("# radius\tthickness\tior\taperture\n");
    let mut before = 1.0;
    for (i, s) in at.surfaces().iter().enumerate() {
        let n = i + 1;
        let refuse = |why: &str| Err(format!("surface {n}: {why}; pbrt-v4's lens file cannot hold it"));
        if s.asphere.is_some() {
            return refuse("an asphere (pbrt's realistic camera traces spheres)");
        }
        if s.paraxial.is_some() {
            return refuse("an ideal (paraxial) lens");
        }
        if s.decenter_mm != [0.0; 2]
            || s.tilt_deg != [0.0; 2]
            || p.elements().iter().any(|e| (e.surfaces[0]..=e.surfaces[1]).contains(&n))
        {
            return refuse("decentred or tilted (pbrt's elements are co-axial)");
        }
        let Some(sd) = s.semi_diameter else {
            return refuse("no clear aperture (pbrt needs every element's diameter: give semi_diameter, or convert with --clear-apertures)");
        };
        let is_plane = s.curvature == 0.0;
        if is_plane && !(s.stop && s.ior == before) {
            return refuse("a plane refracting surface (pbrt reads radius 0 as the aperture stop)");
        }
        let stop_line =
            |ior_after: f64| format!("0\t{}\t{}\t{}\n", 0.0, if ior_after == 1.0 { 0.0 } else { ior_after }, 2.0 * sd);
        if s.stop && is_plane {
            // the stop itself: radius 0, its own thickness
            let eta = if s.ior == 1.0 { 0.0 } else { s.ior };
            out.push_str(&format!("0\t{}\t{eta}\t{}\n", s.thickness, 2.0 * sd));
        } else {
            if s.stop {
                // a stop on a lens surface: pbrt's stop line just before it
                out.push_str(&stop_line(before));
            }
            out.push_str(&format!("{}\t{}\t{}\t{}\n", 1.0 / s.curvature, s.thickness, s.ior, 2.0 * sd));
        }
        before = s.ior;
    }
    Ok(out)
}
