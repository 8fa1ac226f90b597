//! A validated lens prescription: the data every computation reads.

use super::finding::{has_errors, Finding, Severity};
use super::placement::Placement;
use super::spec::{CoatingSpec, ElementSpec, GlassSpec, PrescriptionSpec, SurfaceSpec, VignettingFactors};
use super::surface::Surface;
use super::validate::validate;
use crate::coating::{Coating, MGF2_DESIGN_NM};
use crate::error::OpticsError;
use crate::glass::{Catalogs, Glass, GlassError, GlassRange, RangeWarning, LINE_C_NM, LINE_D_NM, LINE_F_NM};
use std::sync::Arc;

/// The wavelengths of a prescription that names none: F, d and C, nm.
pub const DEFAULT_WAVELENGTHS_NM: [f64; 3] = [LINE_F_NM, LINE_D_NM, LINE_C_NM];

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
    /// The glasses the surfaces name ([`Surface::glass`] indexes them).
    glasses: Arc<[Glass]>,
    /// The system's wavelengths, nm.
    wavelengths_nm: Vec<f64>,
    /// Each wavelength's weight (`None`: 1 each).
    wavelength_weights: Option<Vec<f64>>,
    /// The primary wavelength, nm.
    primary_nm: f64,
    /// The wavelength the surfaces' `ior` are for, nm.
    wavelength_nm: f64,
    /// AGF catalogues named in the file, as written.
    glass_catalogs: Option<Vec<String>>,
    /// The design's field angles, degrees.
    fields_deg: Option<Vec<f64>>,
    /// The design fields' vignetting factors (one per field).
    vignetting_factors: Option<Vec<VignettingFactors>>,
    /// The design's object distance, mm (`None`: infinity).
    object_distance_mm: Option<f64>,
    /// What building it had to decide, for the user (retired glass names
    /// taken as their successors).
    warnings: Vec<String>,
    /// Elements moved as rigid bodies, as written (validated: in range,
    /// not overlapping).
    elements: Vec<ElementSpec>,
    /// The focus group's first and last surfaces, 0-based (validated:
    /// a gap before and after it).
    focus_group: Option<(usize, usize)>,
    /// Each surface's coating as written (`None`: the default, see
    /// [`Prescription::coating`]).
    coatings: Vec<Option<Coating>>,
}

impl Prescription {
    /// Validates `spec` and builds the prescription. On any error returns
    /// every finding (errors and warnings); warnings alone do not fail.
    pub fn from_spec(spec: &PrescriptionSpec) -> Result<Self, Vec<Finding>> {
        Self::from_spec_with(spec, Catalogs::shipped())
    }

    /// [`Self::from_spec`] with glass names looked up in `catalogs`. Every
    /// surface's glass must be known and have an index at every wavelength
    /// of the system, extrapolated outside its data (findings name the
    /// surface, the glass and what to change; [`Self::glass_range`] gives
    /// the warnings to report, or refuses); the surfaces' indices are then
    /// those of the primary wavelength.
    pub fn from_spec_with(spec: &PrescriptionSpec, catalogs: &Catalogs) -> Result<Self, Vec<Finding>> {
        let mut findings = validate(spec);
        let wavelengths_nm = spec.wavelengths_nm.clone().unwrap_or_else(|| DEFAULT_WAVELENGTHS_NM.to_vec());
        let primary_nm = spec.primary_wavelength_nm.unwrap_or(if spec.wavelengths_nm.is_some() {
            wavelengths_nm.get(wavelengths_nm.len() / 2).copied().unwrap_or(LINE_D_NM)
        } else {
            LINE_D_NM
        });
        let mut glasses: Vec<Glass> = Vec::new();
        let mut warnings = spec.warnings.clone();
        let mut surfaces: Vec<Surface> = Vec::with_capacity(spec.surfaces.len());
        let mut coatings = Vec::with_capacity(spec.surfaces.len());
        for (i, s) in spec.surfaces.iter().enumerate() {
            let mut surf = surface_from_spec(s);
            match s.coating.as_ref().map(|c| c.coating()) {
                None => coatings.push(None),
                Some(Ok(c)) => coatings.push(Some(c)),
                Some(Err(message)) => {
                    coatings.push(None);
                    findings.push(Finding {
                        severity: Severity::Error,
                        surface: Some(i + 1),
                        field: Some("coating"),
                        message,
                    })
                }
            }
            if let Some(g) = &s.glass {
                let found = match g {
                    GlassSpec::Name(name) => catalogs.resolve(name).map(|(g, w)| {
                        warnings.extend(w.map(|w| format!("surface {}: {w}", i + 1)));
                        g.clone()
                    }),
                    GlassSpec::Model { nd, vd } => Glass::model(*nd, *vd),
                };
                match found {
                    Ok(glass) => {
                        let mut bad = false;
                        for &nm in wavelengths_nm.iter().chain([primary_nm].iter()) {
                            if let Err(e) = glass.index(nm) {
                                findings.push(Finding {
                                    severity: Severity::Error,
                                    surface: Some(i + 1),
                                    field: Some("glass"),
                                    message: e.to_string(),
                                });
                                bad = true;
                                break;
                            }
                        }
                        if !bad {
                            surf.ior = glass.index(primary_nm).unwrap_or(1.0);
                            // one entry per distinct glass: the batch tracer
                            // evaluates each once per ray
                            surf.glass = Some(glasses.iter().position(|g| *g == glass).unwrap_or_else(|| {
                                glasses.push(glass);
                                glasses.len() - 1
                            }));
                        }
                    }
                    Err(e) => findings.push(Finding {
                        severity: Severity::Error,
                        surface: Some(i + 1),
                        field: Some("glass"),
                        message: e.to_string(),
                    }),
                }
            }
            surfaces.push(surf);
        }
        if has_errors(&findings) {
            findings.sort_by_key(|f| f.surface.unwrap_or(0));
            return Err(findings);
        }
        let stop = surfaces.iter().position(|s| s.stop).ok_or_else(Vec::new)?;
        Ok(Prescription {
            name: spec.name.clone().unwrap_or_default(),
            source: spec.source.clone(),
            surfaces,
            stop,
            glasses: glasses.into(),
            wavelengths_nm,
            wavelength_weights: spec.wavelength_weights.clone(),
            primary_nm,
            wavelength_nm: primary_nm,
            glass_catalogs: spec.glass_catalogs.clone(),
            fields_deg: spec.fields_deg.clone(),
            vignetting_factors: spec.vignetting_factors.clone(),
            object_distance_mm: spec.object_distance_mm,
            warnings,
            elements: spec.elements.clone().unwrap_or_default(),
            focus_group: spec.focus_group.map(|[a, b]| (a - 1, b - 1)),
            coatings,
        })
    }

    /// What building the prescription had to decide that its user should
    /// know, one sentence each: a retired glass name taken as the vendor's
    /// successor ([`Catalogs::resolve`]), a Zemax file's glass found outside
    /// its `GCAT` vendors.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The same system at `wavelength_nm`: every glass's index at that
    /// wavelength (constant indices unchanged, to the bit). Errors where a
    /// glass has no data there.
    ///
    /// ```
    /// let p = lens::Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "glass": "SCHOTT:N-BK7", "semi_diameter": 12.7, "stop": true},
    ///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
    /// let blue = p.at_wavelength(486.1327).unwrap();
    /// assert!(blue.surfaces()[0].ior > p.surfaces()[0].ior);
    /// ```
    pub fn at_wavelength(&self, wavelength_nm: f64) -> Result<Prescription, GlassError> {
        self.at_wavelength_with(wavelength_nm, GlassRange::Extrapolate)
    }

    /// [`Self::at_wavelength`] with the choice of what to do outside a
    /// glass's data ([`GlassRange`]): extrapolate (the default), or refuse.
    pub fn at_wavelength_with(&self, wavelength_nm: f64, range: GlassRange) -> Result<Prescription, GlassError> {
        let mut p = self.clone();
        for s in &mut p.surfaces {
            if let Some(g) = s.glass {
                s.ior = self.glasses[g].index_with(wavelength_nm, range)?;
            }
        }
        p.wavelength_nm = wavelength_nm;
        Ok(p)
    }

    /// The glasses at `wavelengths_nm` under `range`: the warnings to
    /// report for each glass and wavelength outside its data (one each,
    /// in surface order), or the error of the first that has no index
    /// there or that [`GlassRange::Strict`] refuses.
    ///
    /// ```
    /// use lens::glass::GlassRange;
    /// let p = lens::Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "glass": "HIKARI:SK16", "semi_diameter": 12.7, "stop": true},
    ///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
    /// let w = p.glass_range(&[587.5618, 706.5188], GlassRange::Extrapolate).unwrap();
    /// assert_eq!(w.len(), 1);
    /// assert_eq!((w[0].glass.as_str(), w[0].range_nm), ("HIKARI:SK16", [400.0, 700.0]));
    /// assert!(p.glass_range(&[706.5188], GlassRange::Strict).is_err());
    /// ```
    pub fn glass_range(&self, wavelengths_nm: &[f64], range: GlassRange) -> Result<Vec<RangeWarning>, GlassError> {
        let mut out: Vec<RangeWarning> = Vec::new();
        for g in self.glasses.iter() {
            for &nm in wavelengths_nm {
                g.index_with(nm, range)?;
                if let Some(w) = g.range_warning(nm) {
                    if !out.contains(&w) {
                        out.push(w);
                    }
                }
            }
        }
        Ok(out)
    }

    /// The field angles the design is for, degrees (empty when the file
    /// names none).
    pub fn fields_deg(&self) -> &[f64] {
        self.fields_deg.as_deref().unwrap_or(&[])
    }

    /// The design fields' vignetting factors, one per field of
    /// [`Self::fields_deg`] (empty when the file gives none).
    pub fn vignetting_factors(&self) -> &[VignettingFactors] {
        self.vignetting_factors.as_deref().unwrap_or(&[])
    }

    /// The vignetting factors for a field of `deg` degrees from the axis:
    /// those of the design field nearest it in angle (the first of two as
    /// near), as optiland takes them; none when the file gives none.
    pub fn vignetting_at(&self, deg: f64) -> VignettingFactors {
        let mut best: Option<(f64, VignettingFactors)> = None;
        for (f, v) in self.fields_deg().iter().zip(self.vignetting_factors()) {
            let d = (f.abs() - deg.abs()).abs();
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, *v));
            }
        }
        best.map(|(_, v)| v).unwrap_or_default()
    }

    /// The object distance the design is for, mm in front of the first
    /// vertex; `None` for infinity.
    pub fn object_distance_mm(&self) -> Option<f64> {
        self.object_distance_mm
    }

    /// The wavelength the surfaces' indices are for, nm.
    pub fn wavelength_nm(&self) -> f64 {
        self.wavelength_nm
    }

    /// The primary wavelength, nm.
    pub fn primary_wavelength_nm(&self) -> f64 {
        self.primary_nm
    }

    /// The system's wavelengths, nm.
    pub fn wavelengths_nm(&self) -> &[f64] {
        &self.wavelengths_nm
    }

    /// Each wavelength's weight in polychromatic analyses, in the order of
    /// [`Self::wavelengths_nm`] (1 each unless the file gives weights).
    pub fn wavelength_weights(&self) -> Vec<f64> {
        self.wavelength_weights.clone().unwrap_or_else(|| vec![1.0; self.wavelengths_nm.len()])
    }

    /// The glasses the surfaces name.
    pub fn glasses(&self) -> &[Glass] {
        &self.glasses
    }

    /// The glasses, shared (what a tracer keeps to evaluate them per ray).
    pub(crate) fn glasses_shared(&self) -> Arc<[Glass]> {
        Arc::clone(&self.glasses)
    }

    /// The glass after surface `i` (0-based), if it has one.
    pub fn glass_after(&self, i: usize) -> Option<&Glass> {
        self.surfaces.get(i)?.glass.and_then(|g| self.glasses.get(g))
    }

    /// Whether any index depends on wavelength.
    pub fn is_dispersive(&self) -> bool {
        !self.glasses.is_empty()
    }

    /// The prescription as a file spec (radii, optional fields), for writing.
    pub fn to_spec(&self) -> PrescriptionSpec {
        PrescriptionSpec {
            name: (!self.name.is_empty()).then(|| self.name.clone()),
            source: self.source.clone(),
            units: Some("mm".into()),
            wavelengths_nm: (self.wavelengths_nm != DEFAULT_WAVELENGTHS_NM).then(|| self.wavelengths_nm.clone()),
            wavelength_weights: self.wavelength_weights.clone(),
            primary_wavelength_nm: (self.primary_nm != LINE_D_NM).then_some(self.primary_nm),
            glass_catalogs: self.glass_catalogs.clone(),
            fields_deg: self.fields_deg.clone(),
            vignetting_factors: self.vignetting_factors.clone(),
            object_distance_mm: self.object_distance_mm,
            warnings: Vec::new(),
            elements: (!self.elements.is_empty()).then(|| self.elements.clone()),
            focus_group: self.focus_group.map(|(a, b)| [a + 1, b + 1]),
            surfaces: self
                .surfaces
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let glass = s.glass.and_then(|g| self.glasses.get(g)).map(|g| {
                        match (g.catalog.as_str(), g.catalog_nd, g.catalog_vd) {
                            ("MODEL", Some(nd), Some(vd)) => GlassSpec::Model { nd, vd },
                            _ => GlassSpec::Name(g.full_name()),
                        }
                    });
                    let (conic, aspheric, odd_aspheric) = match &s.asphere {
                        None => (None, None, None),
                        Some(a) => {
                            let conic = (a.conic != 0.0).then_some(a.conic);
                            if a.degree() == 0 {
                                (conic, None, None)
                            } else if a.is_even() {
                                (conic, Some(a.even_terms()), None)
                            } else {
                                (conic, None, Some(a.all_terms()))
                            }
                        }
                    };
                    SurfaceSpec {
                        radius: s.radius(),
                        thickness: s.thickness,
                        ior: (glass.is_none() && s.ior != 1.0).then_some(s.ior),
                        glass,
                        semi_diameter: s.semi_diameter,
                        stop: s.stop,
                        conic,
                        aspheric,
                        odd_aspheric,
                        kind: s.paraxial.map(|_| "paraxial".to_string()),
                        focal_length_mm: s.paraxial,
                        decenter_mm: (s.decenter_mm != [0.0; 2]).then_some(s.decenter_mm),
                        tilt_deg: (s.tilt_deg != [0.0; 2]).then_some(s.tilt_deg),
                        coating: self.coatings.get(i).cloned().flatten().map(|c| CoatingSpec::of(&c)),
                    }
                })
                .collect(),
        }
    }

    /// The coating of surface `i` (0-based): as written, else the default:
    /// a single MgF2 layer (quarter wave at [`MGF2_DESIGN_NM`]) where one
    /// side is air (index 1, no glass) and the other is not, bare
    /// elsewhere (cemented surfaces, air to air). [`Coating::None`] past
    /// the last surface.
    pub fn coating(&self, i: usize) -> Coating {
        if let Some(Some(c)) = self.coatings.get(i) {
            return c.clone();
        }
        let Some(s) = self.surfaces.get(i) else { return Coating::None };
        let air_before = i == 0 || (self.surfaces[i - 1].glass.is_none() && self.surfaces[i - 1].ior == 1.0);
        let air_after = s.glass.is_none() && s.ior == 1.0;
        if air_before != air_after && s.paraxial.is_none() {
            Coating::MgF2 { design_nm: MGF2_DESIGN_NM }
        } else {
            Coating::None
        }
    }

    /// Every surface's coating ([`Self::coating`]), in order.
    pub fn coatings(&self) -> Vec<Coating> {
        (0..self.surfaces.len()).map(|i| self.coating(i)).collect()
    }

    /// The same lens with every surface given `coating` (`Some(Coating::None)`:
    /// all bare), or with the defaults of [`Self::coating`] restored
    /// (`None`); a renderer's per-lens override.
    pub fn with_coatings(&self, coating: Option<Coating>) -> Prescription {
        let mut p = self.clone();
        p.coatings = vec![coating; self.surfaces.len()];
        p
    }

    /// The focus group's first and last surfaces, 0-based (`None`: the
    /// lens focuses as a whole).
    pub fn focus_group(&self) -> Option<(usize, usize)> {
        self.focus_group
    }

    /// The prescription with its focus group moved `shift_mm` toward the
    /// image (the gap before the group grows by it, the gap after shrinks):
    /// errors when a gap would close or there is no focus group.
    pub fn with_focus_group_shift(&self, shift_mm: f64) -> Result<Self, OpticsError> {
        let Some((first, last)) = self.focus_group else {
            return Err(OpticsError::BadInput {
                name: "focus group",
                value: shift_mm,
                expected: "a prescription that names its focus_group",
            });
        };
        let before = self.surfaces[first - 1].thickness + shift_mm;
        let after = self.surfaces[last].thickness - shift_mm;
        if !(shift_mm.is_finite() && before > 0.0 && after > 0.0) {
            return Err(OpticsError::FocusGroupTravel {
                shift: shift_mm,
                before: self.surfaces[first - 1].thickness,
                after: self.surfaces[last].thickness,
            });
        }
        let mut p = self.clone();
        p.surfaces[first - 1].thickness = before;
        p.surfaces[last].thickness = after;
        Ok(p)
    }

    /// The elements moved as rigid bodies, as written (surfaces numbered
    /// from 1).
    pub fn elements(&self) -> &[ElementSpec] {
        &self.elements
    }

    /// Where surface `i` (0-based) sits when it, or its element, is
    /// decentred or tilted: its own motion within its element's; `None`
    /// for a surface on the axis (or past the last). One surface of
    /// [`Self::placements`].
    pub fn placement(&self, i: usize) -> Option<Placement> {
        self.placements().get(i).copied().flatten()
    }

    /// [`Self::placement`] of every surface, the vertices' positions
    /// computed once (empty work for a lens with no motions).
    pub fn placements(&self) -> Vec<Option<Placement>> {
        let moved = |s: &Surface| s.decenter_mm != [0.0; 2] || s.tilt_deg != [0.0; 2];
        if self.elements.is_empty() && !self.surfaces.iter().any(moved) {
            return vec![None; self.surfaces.len()];
        }
        let z = self.vertex_z();
        let of =
            |(i, s): (usize, &Surface)| super::placement::of_surface(i, s.decenter_mm, s.tilt_deg, &z, &self.elements);
        self.surfaces.iter().enumerate().map(of).collect()
    }

    /// Whether any surface is decentred or tilted (first-order data are
    /// then those of the co-axial system).
    pub fn is_tilted(&self) -> bool {
        self.placements().iter().any(Option::is_some)
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

    /// A copy with every clear aperture but the stop's set to
    /// `semi_diameters` (0-based, one per surface; `None` for a surface
    /// that does not clip; the stop's entry is ignored), validated again
    /// (errors name surfaces that then cross).
    pub fn with_clear_apertures(&self, semi_diameters: &[Option<f64>]) -> Result<Self, OpticsError> {
        let mut p = self.clone();
        for (i, s) in p.surfaces.iter_mut().enumerate() {
            if !s.stop {
                s.semi_diameter = semi_diameters.get(i).copied().flatten();
            }
        }
        p.validated_again()
    }

    /// `self` after a change of apertures, validated as a file would be
    /// (larger apertures may make surfaces cross): errors list what breaks.
    fn validated_again(self) -> Result<Self, OpticsError> {
        let findings = validate(&self.to_spec());
        if has_errors(&findings) {
            let list = findings.iter().filter(|f| f.severity == Severity::Error).map(|f| f.to_string());
            return Err(OpticsError::Resized { findings: list.collect::<Vec<_>>().join("; ") });
        }
        Ok(self)
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
        if self.surfaces[self.stop].sag(semi_diameter).is_none() {
            return Err(bad);
        }
        let mut p = self.clone();
        p.surfaces[self.stop].semi_diameter = Some(semi_diameter);
        // a larger stop may now cross its neighbours
        p.validated_again()
    }
}

fn surface_from_spec(s: &SurfaceSpec) -> Surface {
    Surface {
        curvature: s.radius.map_or(0.0, |r| 1.0 / r),
        thickness: s.thickness,
        ior: s.ior.unwrap_or(1.0),
        glass: None,
        semi_diameter: s.semi_diameter,
        stop: s.stop,
        asphere: s.asphere(),
        paraxial: s.paraxial_focal_length(),
        decenter_mm: s.decenter_mm.unwrap_or([0.0; 2]),
        tilt_deg: s.tilt_deg.unwrap_or([0.0; 2]),
    }
}
