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
