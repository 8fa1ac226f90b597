//! The prescription file format (JSON), as written by a user: radii, not
//! curvatures, and optional fields. It is checked by [`super::validate`] and
//! turned into a [`super::Prescription`]; [`crate::io`] reads and writes it.

use serde::{Deserialize, Serialize};

/// A prescription file as written (see docs/prescription-format.md).
///
/// ```
/// let spec = lens::PrescriptionSpec::from_json_str(r#"{
///   "name": "plano-convex",
///   "surfaces": [
///     {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
///     {"thickness": 97.1, "semi_diameter": 12.7}
///   ]
/// }"#, "<doc>").unwrap();
/// assert_eq!(spec.surfaces.len(), 2);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrescriptionSpec {
    /// Human-readable name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Where the numbers come from (patent, book, catalogue).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Length unit; only `"mm"` is accepted (omitted means mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// Surfaces, object side first.
    pub surfaces: Vec<SurfaceSpec>,
}

/// One surface as written in a prescription file. Lengths in mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// Radius of curvature in mm, + when the centre lies toward the image;
    /// omitted or `null` for a plane. 0 is an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Axial distance to the next surface (last surface: to the film), mm.
    pub thickness: f64,
    /// Index of the medium after this surface; omitted means air (1.0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ior: Option<f64>,
    /// Clear-aperture radius in mm; omitted means the surface does not clip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub semi_diameter: Option<f64>,
    /// Marks the aperture stop (exactly one surface).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub stop: bool,
}
