//! A validated lens prescription: the data every computation reads.

use super::finding::{has_errors, Finding, Severity};
use super::spec::{PrescriptionSpec, SurfaceSpec};
use super::surface::Surface;
use super::validate::validate;
use crate::error::OpticsError;

/// A validated prescription: surfaces object side first, exactly one stop,
/// every number finite. Build it with [`Prescription::from_spec`] or
/// [`Prescription::load`]; it cannot hold an invalid system.
///
/// Positions along the axis are z in mm from the first vertex, +z toward the
/// image.
#[derive(Debug, Clone, PartialEq)]
pub struct Prescription {
    name: String,
    source: Option<String>,
    surfaces: Vec<Surface>,
    stop: usize,
}

impl Prescription {
    /// Validates `spec` and builds the prescription. On any error returns
    /// every finding (errors and warnings); warnings alone do not fail.
    pub fn from_spec(spec: &PrescriptionSpec) -> Result<Self, Vec<Finding>> {
        let findings = validate(spec);
        if has_errors(&findings) {
            return Err(findings);
        }
        let surfaces: Vec<Surface> = spec.surfaces.iter().map(surface_from_spec).collect();
        let stop = surfaces.iter().position(|s| s.stop).ok_or_else(Vec::new)?;
        Ok(Prescription { name: spec.name.clone().unwrap_or_default(), source: spec.source.clone(), surfaces, stop })
    }

    /// The prescription as a file spec (radii, optional fields), for writing.
    pub fn to_spec(&self) -> PrescriptionSpec {
        PrescriptionSpec {
            name: (!self.name.is_empty()).then(|| self.name.clone()),
            source: self.source.clone(),
            units: Some("mm".into()),
            surfaces: self
                .surfaces
                .iter()
                .map(|s| SurfaceSpec {
                    radius: s.radius(),
                    thickness: s.thickness,
                    ior: (s.ior != 1.0).then_some(s.ior),
                    semi_diameter: s.semi_diameter,
                    stop: s.stop,
                })
                .collect(),
        }
    }

    /// Name given in the file (may be empty).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Source citation given in the file.
    pub fn source(&self) -> Option<&str> {
        self.source.as_deref()
    }

    /// The surfaces, object side first.
    pub fn surfaces(&self) -> &[Surface] {
        &self.surfaces
    }

    /// 0-based index of the aperture stop in [`Self::surfaces`].
    pub fn stop_index(&self) -> usize {
        self.stop
    }

    /// Clear radius of the aperture stop, mm.
    pub fn stop_semi_diameter(&self) -> f64 {
        // Validation guarantees the stop has a semi-diameter.
        self.surfaces[self.stop].semi_diameter.unwrap_or(0.0)
    }

    /// Refractive index in front of surface `i` (0-based): air (1.0) in object
    /// space, otherwise the `ior` of surface `i - 1`.
    pub fn index_before(&self, i: usize) -> f64 {
        if i == 0 {
            1.0
        } else {
            self.surfaces[i - 1].ior
        }
    }

    /// Refractive index of image space (after the last surface).
    pub fn image_index(&self) -> f64 {
        self.surfaces.last().map_or(1.0, |s| s.ior)
    }

    /// z of each surface's vertex, mm from the first vertex.
    pub fn vertex_z(&self) -> Vec<f64> {
        let mut z = 0.0;
        self.surfaces
            .iter()
            .map(|s| {
                let here = z;
                z += s.thickness;
                here
            })
            .collect()
    }

    /// z of the last surface's vertex, mm from the first vertex.
    pub fn last_vertex_z(&self) -> f64 {
        let n = self.surfaces.len();
        self.surfaces[..n - 1].iter().map(|s| s.thickness).sum()
    }

    /// Film distance: the last surface's thickness, mm.
    pub fn film_distance(&self) -> f64 {
        self.surfaces.last().map_or(0.0, |s| s.thickness)
    }

    /// Total track: first vertex to film, mm.
    pub fn total_track(&self) -> f64 {
        self.surfaces.iter().map(|s| s.thickness).sum()
    }

    /// A copy with the film at `film_distance` mm behind the last vertex.
    pub fn with_film_distance(&self, film_distance: f64) -> Result<Self, OpticsError> {
        if !(film_distance.is_finite() && film_distance > 0.0) {
            return Err(OpticsError::BadInput {
                name: "film_distance",
                value: film_distance,
                expected: "a positive, finite distance in mm behind the last vertex",
            });
        }
        let mut p = self.clone();
        if let Some(last) = p.surfaces.last_mut() {
            last.thickness = film_distance;
        }
        Ok(p)
    }

    /// A copy with the stop's clear radius set to `semi_diameter` mm,
    /// validated again (errors name what the larger stop breaks).
    pub fn with_stop_semi_diameter(&self, semi_diameter: f64) -> Result<Self, OpticsError> {
        let bad = OpticsError::BadInput {
            name: "stop semi_diameter",
            value: semi_diameter,
            expected: "a positive, finite radius in mm no larger than the stop surface's |radius|",
        };
        if !(semi_diameter.is_finite() && semi_diameter > 0.0) {
            return Err(bad);
        }
        if let Some(r) = self.surfaces[self.stop].radius() {
            if semi_diameter > r.abs() {
                return Err(bad);
            }
        }
        let mut p = self.clone();
        p.surfaces[self.stop].semi_diameter = Some(semi_diameter);
        // a larger stop may now cross its neighbours: check as a file would be
        let findings = validate(&p.to_spec());
        if has_errors(&findings) {
            let list = findings.iter().filter(|f| f.severity == Severity::Error).map(|f| f.to_string());
            return Err(OpticsError::Resized { findings: list.collect::<Vec<_>>().join("; ") });
        }
        Ok(p)
    }
}

fn surface_from_spec(s: &SurfaceSpec) -> Surface {
    Surface {
        curvature: s.radius.map_or(0.0, |r| 1.0 / r),
        thickness: s.thickness,
        ior: s.ior.unwrap_or(1.0),
        semi_diameter: s.semi_diameter,
        stop: s.stop,
    }
}
