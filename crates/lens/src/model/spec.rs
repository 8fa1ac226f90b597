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
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
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
    /// The weight of each wavelength of `wavelengths_nm` in polychromatic
    /// analyses (a spot's rays, as Zemax's wavelength weights; default 1
    /// each): finite, >= 0, not all 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength_weights: Option<Vec<f64>>,
    /// The primary wavelength, nm (default d, 587.5618): the pupils and the
    /// image plane of the analyses are this wavelength's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub primary_wavelength_nm: Option<f64>,
    /// Zemax AGF glass catalogues (paths relative to the prescription file)
    /// searched before the shipped ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glass_catalogs: Option<Vec<String>>,
    /// The field angles the design is for, degrees from the axis (as a
    /// design file lists them; analyses take their field as a flag).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fields_deg: Option<Vec<f64>>,
    /// Vignetting factors, one per field of `fields_deg` (as Zemax's `VDX`,
    /// `VDY`, `VCX`, `VCY`): fans and spot diagrams at a field fill the
    /// pupil the factors give (see [`VignettingFactors`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vignetting_factors: Option<Vec<VignettingFactors>>,
    /// The object distance the design is for, mm in front of the first
    /// vertex; omitted means infinity. `lens info` uses it unless given
    /// `--object-distance`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object_distance_mm: Option<f64>,
    /// Surfaces, object side first.
    pub surfaces: Vec<SurfaceSpec>,
    /// Elements moved as rigid bodies (decentred and tilted), each a run of
    /// surfaces; omitted: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements: Option<Vec<ElementSpec>>,
    /// The group that moves to focus (internal focusing), its first and
    /// last surfaces numbered from 1: focusing nearer moves it along the
    /// axis, the gap before it (the thickness after surface first - 1) and
    /// the gap after it (the thickness after surface last) changing by
    /// opposite amounts, while the rest of the lens and the film stay.
    /// Omitted: the whole lens moves (unit focusing, the film's distance
    /// changes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_group: Option<[usize; 2]>,
    /// What reading the file had to decide that its user should know (a
    /// Zemax file's retired glass name taken as its successor, say), one
    /// sentence each; not part of the file format.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

/// How a field's rays fill the entrance pupil, as Zemax's vignetting
/// factors: a ray of normalised pupil coordinates (px, py) is launched at
/// (`decenter_x` + px (1 - `compress_x`), `decenter_y` + py (1 -
/// `compress_y`)), so a design that vignettes by intent fans and spots
/// over the part of the pupil that passes. The chief ray is not moved.
/// All four are fractions of the pupil radius (0: none).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VignettingFactors {
    /// Shift of the pupil's centre in x, in pupil radii.
    #[serde(default)]
    pub decenter_x: f64,
    /// Shift of the pupil's centre in y, in pupil radii.
    #[serde(default)]
    pub decenter_y: f64,
    /// Fraction by which the pupil is narrowed in x (less than 1).
    #[serde(default)]
    pub compress_x: f64,
    /// Fraction by which the pupil is narrowed in y (less than 1).
    #[serde(default)]
    pub compress_y: f64,
}

impl VignettingFactors {
    /// Whether every factor is 0 (the full pupil).
    pub fn is_none(&self) -> bool {
        *self == VignettingFactors::default()
    }

    /// The launched pupil point of normalised pupil coordinates (px, py).
    pub fn apply(&self, px: f64, py: f64) -> (f64, f64) {
        (self.decenter_x + px * (1.0 - self.compress_x), self.decenter_y + py * (1.0 - self.compress_y))
    }
}

/// A run of surfaces moved as one rigid body: decentred by `decenter_mm`,
/// then tilted about x, then about the new y, about the decentred vertex
/// of its first surface (Zemax's coordinate break, order 0). The surfaces
/// after the last, and the film, stay where they were.
///
/// ```
/// let spec = lens::PrescriptionSpec::from_json_str(r#"{"surfaces": [
///   {"radius": 50, "thickness": 4, "ior": 1.5, "semi_diameter": 10, "stop": true},
///   {"radius": -50, "thickness": 95, "semi_diameter": 10}],
///  "elements": [{"surfaces": [1, 2], "decenter_mm": [0, 0.1], "tilt_deg": [0.5, 0]}]}"#, "<doc>").unwrap();
/// assert_eq!(spec.elements.unwrap()[0].surfaces, [1, 2]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementSpec {
    /// The first and last surface of the element, numbered from 1,
    /// inclusive.
    pub surfaces: [usize; 2],
    /// Decentre of the element, mm in x and y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decenter_mm: Option<[f64; 2]>,
    /// Tilt of the element, degrees: about x, then about the new y
    /// (right-handed: a positive tilt about x turns the element's axis
    /// toward -y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_deg: Option<[f64; 2]>,
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
    /// Conic constant k of an aspheric surface (0 or omitted: the sphere of
    /// `radius`; -1 a paraboloid). See [`crate::model::surface::Asphere`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conic: Option<f64>,
    /// Even-asphere coefficients: of r^2, r^4, r^6, ... (at most 8, to
    /// r^16), lengths in mm (a_j in mm^(1-j)), added to the conic's sag.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aspheric: Option<Vec<f64>>,
    /// Odd-asphere coefficients: of r^1, r^2, r^3, ... (at most 16), mm,
    /// added to the conic's sag (and to `aspheric`'s terms).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub odd_aspheric: Option<Vec<f64>>,
    /// The surface's type: omitted for a sphere, plane or asphere;
    /// `"paraxial"` for an ideal thin lens (Zemax's paraxial surface) of
    /// `focal_length_mm`, in a plane, with the same medium on both sides.
    #[serde(default, rename = "type", skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// The focal length of a `"paraxial"` surface, mm (negative: diverging).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focal_length_mm: Option<f64>,
    /// Decentre of this surface alone, mm in x and y; the coordinates are
    /// restored after it (the next vertex stays on the axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decenter_mm: Option<[f64; 2]>,
    /// Tilt of this surface alone, degrees: about x, then about the new y,
    /// about its decentred vertex (right-handed; Zemax's coordinate break
    /// of order 0, reversed after the surface).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt_deg: Option<[f64; 2]>,
    /// The surface's anti-reflection coating: `"none"`, `"MgF2"` (a
    /// quarter-wave magnesium fluoride layer at 550 nm), or a list of
    /// layers from the object side. Omitted: MgF2 where one side is air and
    /// the other glass, none elsewhere (cemented, air to air).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coating: Option<CoatingSpec>,
}

/// A surface's coating as written: a name (`"none"`, `"MgF2"`) or thin
/// films listed from the object side (the side light comes from on its way
/// to the image).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum CoatingSpec {
    /// `"none"` (bare glass) or `"MgF2"` (single layer, quarter wave at
    /// 550 nm), in any case.
    Name(String),
    /// Thin films, object side first.
    Layers(Vec<LayerSpec>),
}

/// One thin film of a coating.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// Refractive index (lossless, >= 1).
    pub index: f64,
    /// Physical thickness, nm (>= 0).
    pub thickness_nm: f64,
}

impl CoatingSpec {
    /// The coating, or what is wrong with it (a sentence naming what to
    /// change).
    pub fn coating(&self) -> Result<crate::coating::Coating, String> {
        use crate::coating::{Coating, Layer, MGF2_DESIGN_NM};
        match self {
            CoatingSpec::Name(n) if n.eq_ignore_ascii_case("none") => Ok(Coating::None),
            CoatingSpec::Name(n) if n.eq_ignore_ascii_case("mgf2") => Ok(Coating::MgF2 { design_nm: MGF2_DESIGN_NM }),
            CoatingSpec::Name(n) => Err(format!("unknown coating \"{n}\": use \"none\", \"MgF2\" or a list of layers")),
            CoatingSpec::Layers(l) => {
                for (k, l) in l.iter().enumerate() {
                    if !(l.index.is_finite() && l.index >= 1.0) {
                        return Err(format!("coating layer {}: index {} must be a number >= 1", k + 1, l.index));
                    }
                    if !(l.thickness_nm.is_finite() && l.thickness_nm >= 0.0) {
                        return Err(format!(
                            "coating layer {}: thickness_nm {} must be a number >= 0",
                            k + 1,
                            l.thickness_nm
                        ));
                    }
                }
                Ok(Coating::Layers(l.iter().map(|l| Layer { index: l.index, thickness_nm: l.thickness_nm }).collect()))
            }
        }
    }

    /// The spec of a coating (the inverse of [`Self::coating`]).
    pub fn of(c: &crate::coating::Coating) -> Self {
        use crate::coating::{Coating, MGF2_DESIGN_NM};
        match c {
            Coating::None => CoatingSpec::Name("none".into()),
            Coating::MgF2 { design_nm } if *design_nm == MGF2_DESIGN_NM => CoatingSpec::Name("MgF2".into()),
            c => CoatingSpec::Layers(
                c.layers().iter().map(|l| LayerSpec { index: l.index, thickness_nm: l.thickness_nm }).collect(),
            ),
        }
    }
}

impl SurfaceSpec {
    /// A surface of `radius` (mm, `None` for a plane) and `thickness` mm
    /// in air, with every optional field unset.
    pub fn new(radius: Option<f64>, thickness: f64) -> Self {
        SurfaceSpec {
            radius,
            thickness,
            ior: None,
            glass: None,
            semi_diameter: None,
            stop: false,
            conic: None,
            aspheric: None,
            odd_aspheric: None,
            kind: None,
            focal_length_mm: None,
            decenter_mm: None,
            tilt_deg: None,
            coating: None,
        }
    }

    /// The focal length (mm) of an ideal (`"paraxial"`) surface, `None` for
    /// any other.
    pub fn paraxial_focal_length(&self) -> Option<f64> {
        (self.kind.as_deref() == Some("paraxial")).then_some(self.focal_length_mm).flatten()
    }

    /// Whether the file gives this surface a conic or aspheric terms.
    pub fn is_aspheric(&self) -> bool {
        self.conic.is_some_and(|k| k != 0.0)
            || self.aspheric.as_ref().is_some_and(|a| a.iter().any(|x| *x != 0.0))
            || self.odd_aspheric.as_ref().is_some_and(|a| a.iter().any(|x| *x != 0.0))
    }

    /// The surface's asphere as written, `None` for a sphere or plane (or
    /// when there are too many terms, which validation reports).
    pub fn asphere(&self) -> Option<crate::model::surface::Asphere> {
        if !self.is_aspheric() {
            return None;
        }
        crate::model::surface::Asphere::new(
            self.conic.unwrap_or(0.0),
            self.aspheric.as_deref().unwrap_or(&[]),
            self.odd_aspheric.as_deref().unwrap_or(&[]),
        )
    }

    /// Curvature 1/mm of the base sphere as written (0 for a plane),
    /// `None` for a radius that is not a number or 0.
    pub fn curvature(&self) -> Option<f64> {
        match self.radius {
            Some(r) if r.is_finite() && r != 0.0 => Some(1.0 / r),
            Some(_) => None,
            None => Some(0.0),
        }
    }

    /// Sag mm at height `h` mm, as [`crate::model::Surface::sag`]; `None`
    /// where the surface does not reach `h` or its numbers are unusable.
    pub fn sag(&self, h: f64) -> Option<f64> {
        let c = self.curvature()?;
        let asphere = self.asphere();
        if asphere.is_none() && self.is_aspheric() {
            return None; // terms that do not make an asphere (too many)
        }
        crate::model::surface::profile_sag(c, asphere.as_ref(), h)
    }
}
