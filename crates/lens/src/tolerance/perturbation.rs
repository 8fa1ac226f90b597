//! Tolerances: one manufacturing error each, its size and distribution,
//! and how a drawn value changes a prescription.

use super::spec::ToleranceItemSpec;
use crate::design::DesignError;
use crate::model::spec::{ElementSpec, GlassSpec};
use crate::PrescriptionSpec;
use serde::Serialize;

/// What a tolerance changes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum Kind {
    /// The radius, mm added.
    Radius {
        /// Surface, from 1.
        surface: usize,
    },
    /// Power fringes at the test wavelength: the sag at the semi-diameter
    /// changes by fringes x wavelength / 2.
    Fringes {
        /// Surface, from 1.
        surface: usize,
        /// Test wavelength, nm.
        test_wavelength_nm: f64,
    },
    /// The thickness after the surface, mm added.
    Thickness {
        /// Surface, from 1.
        surface: usize,
    },
    /// The index (nd) of the glass after the surface, added.
    Index {
        /// Surface, from 1.
        surface: usize,
    },
    /// The Abbe number of the glass after the surface, added.
    Abbe {
        /// Surface, from 1.
        surface: usize,
    },
    /// The surface alone decentred, mm.
    SurfaceDecenter {
        /// Surface, from 1.
        surface: usize,
        /// 0 for x, 1 for y.
        axis: usize,
    },
    /// The surface alone tilted, degrees.
    SurfaceTilt {
        /// Surface, from 1.
        surface: usize,
        /// 0 about x, 1 about y.
        axis: usize,
    },
    /// The element (surfaces first..=last) decentred, mm.
    ElementDecenter {
        /// First and last surface, from 1.
        surfaces: [usize; 2],
        /// 0 for x, 1 for y.
        axis: usize,
    },
    /// The element tilted, degrees.
    ElementTilt {
        /// First and last surface, from 1.
        surfaces: [usize; 2],
        /// 0 about x, 1 about y.
        axis: usize,
    },
}

/// How a tolerance's values are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Distribution {
    /// Normal with sigma = plus_minus / 2, truncated at +-plus_minus.
    Normal,
    /// Uniform over +-plus_minus.
    Uniform,
}

impl Distribution {
    /// The distribution of a name (`None`: normal).
    pub fn parse(name: Option<&str>) -> Result<Distribution, String> {
        match name {
            None | Some("normal") => Ok(Distribution::Normal),
            Some("uniform") => Ok(Distribution::Uniform),
            Some(x) => Err(format!("distribution \"{x}\": one of \"normal\", \"uniform\"")),
        }
    }
}

/// One tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// What it changes.
    #[serde(flatten)]
    pub kind: Kind,
    /// The largest departure either way.
    pub plus_minus: f64,
    /// How values are drawn.
    pub distribution: Distribution,
}

impl Tolerance {
    /// The tolerance of `t` (the `index`-th of the file, from 0) on `spec`,
    /// checked.
    pub fn from_spec(
        t: &ToleranceItemSpec,
        index: usize,
        spec: &PrescriptionSpec,
        default: Distribution,
    ) -> Result<Tolerance, DesignError> {
        let what = format!("tolerance {} ({})", index + 1, t.kind);
        let bad = |why: String| DesignError::Tolerance(format!("{what}: {why}"));
        let n = spec.surfaces.len();
        let surface = || -> Result<usize, DesignError> {
            match t.surface {
                Some(s) if (1..=n).contains(&s) => Ok(s),
                Some(s) => Err(bad(format!("surface {s}: the prescription has surfaces 1 to {n}"))),
                None => Err(bad("give \"surface\" (numbered from 1)".into())),
            }
        };
        let axis = || -> Result<usize, DesignError> {
            match t.axis.as_deref() {
                Some("x") => Ok(0),
                Some("y") => Ok(1),
                Some(a) => Err(bad(format!("axis \"{a}\": \"x\" or \"y\""))),
                None => Err(bad("give \"axis\": \"x\" or \"y\"".into())),
            }
        };
        let elements = || -> Result<[usize; 2], DesignError> {
            match t.surfaces {
                Some([a, b]) if a >= 1 && a <= b && b <= n => Ok([a, b]),
                Some([a, b]) => Err(bad(format!(
                    "surfaces [{a}, {b}]: give the first and last surface of the element, 1 <= first <= last <= {n}"
                ))),
                None => Err(bad("give \"surfaces\": [first, last] (numbered from 1)".into())),
            }
        };
        if !(t.plus_minus.is_finite() && t.plus_minus >= 0.0) {
            return Err(bad(format!("plus_minus {}: give a finite tolerance of 0 or more", t.plus_minus)));
        }
        let glass_after = |s: usize, abbe: bool| -> Result<(), DesignError> {
            let surf = &spec.surfaces[s - 1];
            match (&surf.glass, surf.ior) {
                (Some(_), _) => Ok(()),
                (None, Some(_)) if !abbe => Ok(()),
                (None, Some(_)) => {
                    Err(bad(format!("surface {s} is followed by a constant index (\"ior\"): it has no Abbe number")))
                }
                (None, None) => Err(bad(format!("air follows surface {s}: there is no glass"))),
            }
        };
        const KINDS: [&str; 9] = [
            "radius",
            "fringes",
            "thickness",
            "index",
            "abbe",
            "surface_decenter",
            "surface_tilt",
            "element_decenter",
            "element_tilt",
        ];
        if !KINDS.contains(&t.kind.as_str()) {
            return Err(bad(format!("unknown type \"{}\": one of {}", t.kind, KINDS.join(", "))));
        }
        let uses_surface = matches!(
            t.kind.as_str(),
            "radius" | "fringes" | "thickness" | "index" | "abbe" | "surface_decenter" | "surface_tilt"
        );
        if t.surface.is_some() && !uses_surface {
            return Err(bad("\"surface\" does not apply: an element tolerance names \"surfaces\"".into()));
        }
        if t.surfaces.is_some() && uses_surface {
            return Err(bad("\"surfaces\" does not apply: give \"surface\"".into()));
        }
        if t.test_wavelength_nm.is_some() && t.kind != "fringes" {
            return Err(bad("\"test_wavelength_nm\" belongs to a fringes tolerance".into()));
        }
        let kind = match t.kind.as_str() {
            "radius" => Kind::Radius { surface: surface()? },
            "fringes" => {
                let s = surface()?;
                if spec.surfaces[s - 1].semi_diameter.is_none() {
                    return Err(bad(format!("surface {s} has no semi_diameter: fringes are counted over it")));
                }
                let nm = t.test_wavelength_nm.unwrap_or(crate::glass::LINE_E_NM);
                if !(nm.is_finite() && nm > 0.0) {
                    return Err(bad(format!("test_wavelength_nm {nm}: give a wavelength above 0")));
                }
                Kind::Fringes { surface: s, test_wavelength_nm: nm }
            }
            "thickness" => Kind::Thickness { surface: surface()? },
            "index" => {
                let s = surface()?;
                glass_after(s, false)?;
                Kind::Index { surface: s }
            }
            "abbe" => {
                let s = surface()?;
                glass_after(s, true)?;
                Kind::Abbe { surface: s }
            }
            "surface_decenter" => Kind::SurfaceDecenter { surface: surface()?, axis: axis()? },
            "surface_tilt" => Kind::SurfaceTilt { surface: surface()?, axis: axis()? },
            "element_decenter" => Kind::ElementDecenter { surfaces: elements()?, axis: axis()? },
            "element_tilt" => Kind::ElementTilt { surfaces: elements()?, axis: axis()? },
            other => {
                return Err(bad(format!(
                    "unknown type \"{other}\": one of radius, fringes, thickness, index, abbe, surface_decenter, surface_tilt, element_decenter, element_tilt"
                )))
            }
        };
        if matches!(kind, Kind::Radius { .. } | Kind::Thickness { .. } | Kind::Fringes { .. }) && t.axis.is_some()
            || matches!(kind, Kind::Index { .. } | Kind::Abbe { .. }) && t.axis.is_some()
        {
            return Err(bad("\"axis\" belongs to a decentre or tilt".into()));
        }
        let distribution = match &t.distribution {
            Some(d) => Distribution::parse(Some(d)).map_err(bad)?,
            None => default,
        };
        Ok(Tolerance { kind, plus_minus: t.plus_minus, distribution })
    }

    /// A short name for tables: `radius s1`, `element tilt x s1-2`.
    pub fn label(&self) -> String {
        let ax = |a: usize| if a == 0 { "x" } else { "y" };
        match self.kind {
            Kind::Radius { surface } => format!("radius s{surface}"),
            Kind::Fringes { surface, .. } => format!("fringes s{surface}"),
            Kind::Thickness { surface } => format!("thickness s{surface}"),
            Kind::Index { surface } => format!("index s{surface}"),
            Kind::Abbe { surface } => format!("abbe s{surface}"),
            Kind::SurfaceDecenter { surface, axis } => format!("decenter {} s{surface}", ax(axis)),
            Kind::SurfaceTilt { surface, axis } => format!("tilt {} s{surface}", ax(axis)),
            Kind::ElementDecenter { surfaces: [a, b], axis } => format!("element decenter {} s{a}-{b}", ax(axis)),
            Kind::ElementTilt { surfaces: [a, b], axis } => format!("element tilt {} s{a}-{b}", ax(axis)),
        }
    }

    /// Adds `delta` (the tolerance's unit) to `spec`. A toleranced glass is
    /// a model glass by then ([`model_glasses`]).
    pub fn apply(&self, spec: &mut PrescriptionSpec, delta: f64) {
        if delta == 0.0 {
            return;
        }
        match self.kind {
            Kind::Radius { surface } => {
                let s = &mut spec.surfaces[surface - 1];
                if let Some(r) = s.radius {
                    s.radius = Some(r + delta);
                }
            }
            Kind::Fringes { surface, test_wavelength_nm } => {
                let s = &mut spec.surfaces[surface - 1];
                let h = s.semi_diameter.unwrap_or(0.0);
                let c = s.curvature().unwrap_or(0.0);
                // the sphere whose sag at h is the old one's plus
                // fringes x lambda / 2: c = 2 z / (z^2 + h^2)
                if let Some(z) = crate::model::surface::sag(c, h) {
                    let z = z + delta * test_wavelength_nm * 1e-6 / 2.0;
                    let c = 2.0 * z / (z * z + h * h);
                    s.radius = (c != 0.0).then(|| 1.0 / c);
                }
            }
            Kind::Thickness { surface } => spec.surfaces[surface - 1].thickness += delta,
            Kind::Index { surface } => {
                let s = &mut spec.surfaces[surface - 1];
                match &mut s.glass {
                    Some(GlassSpec::Model { nd, .. }) => *nd += delta,
                    _ => s.ior = s.ior.map(|n| n + delta),
                }
            }
            Kind::Abbe { surface } => {
                if let Some(GlassSpec::Model { vd, .. }) = &mut spec.surfaces[surface - 1].glass {
                    *vd += delta
                }
            }
            Kind::SurfaceDecenter { surface, axis } => {
                spec.surfaces[surface - 1].decenter_mm.get_or_insert([0.0, 0.0])[axis] += delta
            }
            Kind::SurfaceTilt { surface, axis } => {
                spec.surfaces[surface - 1].tilt_deg.get_or_insert([0.0, 0.0])[axis] += delta
            }
            Kind::ElementDecenter { surfaces, axis } => {
                element(spec, surfaces).decenter_mm.get_or_insert([0.0, 0.0])[axis] += delta
            }
            Kind::ElementTilt { surfaces, axis } => {
                element(spec, surfaces).tilt_deg.get_or_insert([0.0, 0.0])[axis] += delta
            }
        }
    }
}

/// The element of `spec` over `surfaces`, added (unmoved) if it has none.
fn element(spec: &mut PrescriptionSpec, surfaces: [usize; 2]) -> &mut ElementSpec {
    let list = spec.elements.get_or_insert_with(Vec::new);
    let k = match list.iter().position(|e| e.surfaces == surfaces) {
        Some(k) => k,
        None => {
            list.push(ElementSpec { surfaces, decenter_mm: None, tilt_deg: None });
            list.len() - 1
        }
    };
    &mut list[k]
}

/// `spec` with every glass that carries an index or Abbe tolerance written
/// as the model glass of its nd and vd (docs/glass.md), so that a drawn
/// change adds to them; the nominal lens is evaluated so too.
pub fn model_glasses(
    spec: &PrescriptionSpec,
    tolerances: &[Tolerance],
    catalogs: &crate::glass::Catalogs,
) -> Result<PrescriptionSpec, DesignError> {
    let mut out = spec.clone();
    for t in tolerances {
        let s = match t.kind {
            Kind::Index { surface } | Kind::Abbe { surface } => surface,
            _ => continue,
        };
        if let Some(GlassSpec::Name(name)) = &spec.surfaces[s - 1].glass {
            let (g, _) = catalogs.resolve(name).map_err(|e| DesignError::Tolerance(format!("surface {s}: {e}")))?;
            let (nd, vd) = (g.nd(), g.vd());
            let (Ok(nd), Ok(vd)) = (nd, vd) else {
                return Err(DesignError::Tolerance(format!(
                    "surface {s}: the glass {name} has no nd or vd (its data do not cover the d, F and C lines): it cannot take an index or Abbe tolerance"
                )));
            };
            out.surfaces[s - 1].glass = Some(GlassSpec::Model { nd, vd });
        }
    }
    Ok(out)
}
