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
    /// Wavelengths of the system, nm (default F, d, C: 486.1327, 587.5618,
    /// 656.2725).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelengths_nm: Option<Vec<f64>>,
    /// The primary wavelength, nm (default d, 587.5618): the pupils and the
    /// image plane of the analyses are this wavelength's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub primary_wavelength_nm: Option<f64>,
    /// Zemax AGF glass catalogues (paths relative to the prescription file)
    /// searched before the shipped ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glass_catalogs: Option<Vec<String>>,
    /// Surfaces, object side first.
    pub surfaces: Vec<SurfaceSpec>,
}

/// The glass after a surface: a catalogue name or a model glass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum GlassSpec {
    /// `VENDOR:NAME` (vendor in any case), or `NAME` where one loaded
    /// catalogue has it.
    Name(String),
    /// A model glass reproducing nd and vd exactly (docs/glass.md).
    Model {
        /// Index at the d line, 587.5618 nm.
        nd: f64,
        /// Abbe number (nd - 1) / (nF - nC).
        vd: f64,
    },
}

/// One surface as written in a prescription file. Lengths in mm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// Radius of curvature in mm, + when the centre lies toward the image;
    /// omitted or `null` for a plane. 0 is an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Axial distance to the next surface (last surface: to the film), mm.
    pub thickness: f64,
    /// Index of the medium after this surface, constant at every
    /// wavelength; omitted (with no `glass`) means air (1.0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ior: Option<f64>,
    /// The glass after this surface (instead of `ior`): dispersive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glass: Option<GlassSpec>,
    /// Clear-aperture radius in mm; omitted means the surface does not clip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub semi_diameter: Option<f64>,
    /// Marks the aperture stop (exactly one surface).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub stop: bool,
}
