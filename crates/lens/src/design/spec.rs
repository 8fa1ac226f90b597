//! The design file (JSON): a starting prescription, the variables, the
//! merit function's operands and the evaluation settings, as a user writes
//! them (docs/design.md). Checked and turned into a [`super::Design`].

use serde::{Deserialize, Serialize};

/// A design file as written.
///
/// ```
/// let d: lens::design::DesignSpec = serde_json::from_str(r#"{
///   "prescription": "start.json",
///   "variables": [{"surface": 1, "param": "radius", "min": 10, "max": 200},
///                 {"surface": 2, "param": "thickness"}],
///   "operands": [{"type": "efl", "target": 50.0, "weight": 1},
///                {"type": "rms_spot", "field_deg": 0, "weight": 1},
///                {"type": "edge_thickness", "surface": 2, "min": 0.5}],
///   "wavelengths_nm": [587.5618], "image": "paraxial"}"#).unwrap();
/// assert_eq!(d.variables.len(), 2);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignSpec {
    /// The starting prescription (JSON, `.zmx` or `.dat`), relative to the
    /// design file.
    pub prescription: String,
    /// What the optimiser may change.
    pub variables: Vec<VariableSpec>,
    /// The merit function: operands with targets and weights.
    pub operands: Vec<OperandSpec>,
    /// Wavelengths of the merit function, nm (default: the prescription's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelengths_nm: Option<Vec<f64>>,
    /// Each wavelength's weight (default 1 each; with `wavelengths_nm`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength_weights: Option<Vec<f64>>,
    /// The primary wavelength, nm: first-order data, pupils and the
    /// paraxial image are its (default: the prescription's where it is one
    /// of `wavelengths_nm`, else the middle one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub primary_wavelength_nm: Option<f64>,
    /// Where images are evaluated: `"surface"` (the prescription's image
    /// surface, its last thickness as written or varied; the default) or
    /// `"paraxial"` (the last thickness solved to the paraxial image of
    /// each candidate: a solve).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// Replace model glasses by catalogue glasses after optimising, then
    /// optimise again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glass_substitution: Option<GlassSubstitutionSpec>,
    /// The most iterations of damped least squares (default 200).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iterations: Option<usize>,
}

/// One variable as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariableSpec {
    /// The surface, numbered from 1.
    pub surface: usize,
    /// `radius`, `curvature`, `thickness`, `conic`, `aspheric` (with
    /// `order`), `nd` or `vd` (of the model glass after the surface).
    pub param: String,
    /// The power of r of an `aspheric` coefficient: 2, 4, ... 16.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order: Option<usize>,
    /// Lower bound, in the parameter's unit (a radius in mm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
}

/// One operand of the merit function as written. Which keys apply depends
/// on `type` (docs/design.md lists them); a key that does not apply is an
/// error.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperandSpec {
    /// `efl`, `f_number`, `back_focus`, `total_track`, `magnification`,
    /// `rms_spot`, `rms_wavefront`, `mtf`, `distortion`, `ray_x`, `ray_y`,
    /// `center_thickness`, `edge_thickness`.
    #[serde(rename = "type")]
    pub kind: String,
    /// The target value (default 0 for aberrations, required for the
    /// first-order operands).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<f64>,
    /// `"="` (the default), `"<"` (at most the target) or `">"` (at least).
    #[serde(default, rename = "kind", skip_serializing_if = "Option::is_none")]
    pub relation: Option<String>,
    /// A lower bound: the operand adds nothing while at or above it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// An upper bound: the operand adds nothing while at or below it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// Weight, >= 0 (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weight: Option<f64>,
    /// Field angle, degrees from the axis (toward +y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field_deg: Option<f64>,
    /// The field's x component, degrees (Zemax's and optiland's component
    /// angles; for lenses with decentred or tilted surfaces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field_x_deg: Option<f64>,
    /// The surface (from 1) of a thickness operand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<usize>,
    /// One wavelength, nm, instead of the merit function's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength_nm: Option<f64>,
    /// The spatial frequency of an `mtf` operand, cycles/mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency_per_mm: Option<f64>,
    /// `tangential`, `sagittal` or `mean` (default) for an `mtf` operand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
    /// Normalised pupil coordinates of a `ray_x` / `ray_y` operand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub px: Option<f64>,
    /// See `px`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub py: Option<f64>,
    /// Gauss rings of an `rms_spot` operand (default 12, as `lens spot`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rings: Option<usize>,
}

/// Glass substitution after optimising.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlassSubstitutionSpec {
    /// The catalogues to choose from (vendor names, `SCHOTT`); default all
    /// loaded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub catalogs: Option<Vec<String>>,
}
