//! The tolerance file (JSON) as a user writes it (docs/tolerancing.md).

use crate::design::spec::VariableSpec;
use serde::{Deserialize, Serialize};

/// A tolerance file as written.
///
/// ```
/// let t: lens::tolerance::ToleranceSpec = serde_json::from_str(r#"{
///   "prescription": "lens.json",
///   "tolerances": [{"type": "radius", "surface": 1, "plus_minus": 0.1},
///                  {"type": "element_tilt", "surfaces": [1, 2], "axis": "x", "plus_minus": 0.05}],
///   "compensators": [{"type": "back_focus"}],
///   "criterion": {"type": "rms_spot", "fields_deg": [0, 10, 14]},
///   "threshold": 0.03}"#).unwrap();
/// assert_eq!(t.tolerances.len(), 2);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToleranceSpec {
    /// The nominal prescription, relative to the tolerance file.
    pub prescription: String,
    /// What varies from lens to lens.
    pub tolerances: Vec<ToleranceItemSpec>,
    /// The default distribution: `"normal"` (sigma = plus_minus / 2,
    /// truncated at +-plus_minus, i.e. +-2 sigma; the default) or
    /// `"uniform"` (over +-plus_minus).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distribution: Option<String>,
    /// What is adjusted on each lens to recover: `{"type": "back_focus"}`
    /// (the last thickness) or a variable as in a design file.
    #[serde(default)]
    pub compensators: Vec<CompensatorSpec>,
    /// What is judged.
    pub criterion: CriterionSpec,
    /// A lens passes when its criterion is at most this (at least this for
    /// an MTF); gives the yield.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
    /// Wavelengths of the criterion, nm (default: the prescription's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelengths_nm: Option<Vec<f64>>,
}

/// One tolerance as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToleranceItemSpec {
    /// `radius` (mm), `fringes` (power fringes at `test_wavelength_nm`),
    /// `thickness` (mm), `index`, `abbe` (Abbe number), `surface_decenter`
    /// (mm), `surface_tilt` (degrees), `element_decenter`, `element_tilt`.
    #[serde(rename = "type")]
    pub kind: String,
    /// The surface (from 1) of a surface tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<usize>,
    /// The first and last surface (from 1) of an element tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surfaces: Option<[usize; 2]>,
    /// `"x"` or `"y"` for a decentre or tilt.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<String>,
    /// The tolerance: the largest departure either way.
    pub plus_minus: f64,
    /// This tolerance's distribution (default the file's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distribution: Option<String>,
    /// The test wavelength of a `fringes` tolerance, nm (default 546.074,
    /// the mercury e line).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_wavelength_nm: Option<f64>,
}

/// A compensator as written: `{"type": "back_focus"}` or a design
/// variable (`{"surface": 7, "param": "thickness"}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum CompensatorSpec {
    /// The back focus.
    Named {
        /// `"back_focus"`.
        #[serde(rename = "type")]
        kind: String,
    },
    /// Any design variable.
    Variable(VariableSpec),
}

/// The criterion as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CriterionSpec {
    /// `rms_spot` (mm), `rms_wavefront` (waves) or `mtf`.
    #[serde(rename = "type")]
    pub kind: String,
    /// The fields judged, degrees (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fields_deg: Option<Vec<f64>>,
    /// Each judged field's x component, degrees, in the order of
    /// `fields_deg` (default 0 each: fields along y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fields_x_deg: Option<Vec<f64>>,
    /// Gauss rings of an RMS spot (default 6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rings: Option<usize>,
    /// The frequency of an MTF criterion, cycles/mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency_per_mm: Option<f64>,
    /// `tangential`, `sagittal` or `mean` (default) for an MTF.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
}
