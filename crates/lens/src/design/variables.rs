//! Design variables: which number of a prescription an optimiser may
//! change, read from and written into a [`PrescriptionSpec`], with bounds.
//!
//! A radius is varied as its curvature (1/mm) so that a surface may pass
//! through flat; its bounds are given as radii and turned into curvature
//! bounds (they must not include 0 mm: a radius of 0 is no surface).

use super::spec::VariableSpec;
use super::DesignError;
use crate::model::spec::GlassSpec;
use crate::PrescriptionSpec;
use serde::Serialize;

/// The number a variable changes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "param")]
pub enum Param {
    /// The surface's curvature (1/mm, + when its centre lies toward the
    /// image); written to the file as its radius (a plane when 0).
    Curvature,
    /// The distance to the next surface, mm.
    Thickness,
    /// The conic constant.
    Conic,
    /// The even-asphere coefficient of r^`order` (order 2, 4, ..., 16), mm^(1-order).
    Aspheric {
        /// The power of r (even, 2 to 16).
        order: usize,
    },
    /// nd of the model glass after the surface (or its constant index `ior`).
    Nd,
    /// vd of the model glass after the surface.
    Vd,
}

impl Param {
    /// The name as a design file writes it.
    pub fn name(&self) -> String {
        match self {
            Param::Curvature => "curvature".into(),
            Param::Thickness => "thickness".into(),
            Param::Conic => "conic".into(),
            Param::Aspheric { order } => format!("aspheric r^{order}"),
            Param::Nd => "nd".into(),
            Param::Vd => "vd".into(),
        }
    }
}

/// One variable: a parameter of one surface (0-based index) with bounds in
/// the variable's own unit (curvature 1/mm for a radius).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variable {
    /// The surface, numbered from 1 as in the design file.
    pub surface: usize,
    /// What is varied.
    #[serde(flatten)]
    pub param: Param,
    /// Lower bound (the variable's unit), -infinity when none.
    pub lower: f64,
    /// Upper bound, +infinity when none.
    pub upper: f64,
    /// Whether the file gave the variable as a radius (reports print the
    /// radius).
    pub as_radius: bool,
}

impl Variable {
    /// The variable of `v` (the `index`-th of the file, from 0) on `spec`,
    /// checked: the surface exists, the parameter applies to it, the
    /// bounds are ordered and hold the starting value.
    pub fn from_spec(v: &VariableSpec, index: usize, spec: &PrescriptionSpec) -> Result<Variable, DesignError> {
        let what = format!("variable {} (surface {}, {})", index + 1, v.surface, v.param);
        let bad = |why: String| DesignError::Variable { what: what.clone(), why };
        let n = spec.surfaces.len();
        if v.surface == 0 || v.surface > n {
            return Err(bad(format!("the prescription has surfaces 1 to {n}")));
        }
        let s = &spec.surfaces[v.surface - 1];
        let (param, as_radius) = match v.param.as_str() {
            "radius" => (Param::Curvature, true),
            "curvature" => (Param::Curvature, false),
            "thickness" => (Param::Thickness, false),
            "conic" => (Param::Conic, false),
            "aspheric" => match v.order {
                Some(order) if order % 2 == 0 && (2..=16).contains(&order) => (Param::Aspheric { order }, false),
                Some(order) => {
                    return Err(bad(format!("order {order}: an even-asphere term is of r^2, r^4, ... r^16")));
                }
                None => return Err(bad("give \"order\": the power of r of the coefficient (2, 4, ... 16)".into())),
            },
            "nd" => (Param::Nd, false),
            "vd" => (Param::Vd, false),
            other => {
                return Err(bad(format!(
                    "unknown parameter \"{other}\": one of radius, curvature, thickness, conic, aspheric, nd, vd"
                )))
            }
        };
        if v.order.is_some() && !matches!(param, Param::Aspheric { .. }) {
            return Err(bad("\"order\" belongs to an aspheric variable only".into()));
        }
        if s.kind.is_some() && !matches!(param, Param::Thickness) {
            return Err(bad("an ideal (paraxial) surface has no radius, conic, asphere or glass to vary".into()));
        }
        match (param, &s.glass, s.ior) {
            (Param::Nd, Some(GlassSpec::Name(g)), _) | (Param::Vd, Some(GlassSpec::Name(g)), _) => {
                return Err(bad(format!(
                    "the glass after it is the catalogue glass {g}: write it as a model glass {{\"nd\": ..., \"vd\": ...}} to vary it"
                )));
            }
            (Param::Nd, None, None) | (Param::Vd, None, None) => {
                return Err(bad("air follows this surface: there is no glass to vary".into()));
            }
            (Param::Vd, None, Some(_)) => {
                return Err(bad(
                    "the medium after it is a constant index (\"ior\"), without dispersion: write a model glass {\"nd\": ..., \"vd\": ...} to vary vd".into(),
                ));
            }
            _ => {}
        }
        for (name, b) in [("min", v.min), ("max", v.max)] {
            if b.is_some_and(|b| !b.is_finite()) {
                return Err(bad(format!("\"{name}\" must be a finite number")));
            }
        }
        let (mut lower, mut upper) = (v.min.unwrap_or(f64::NEG_INFINITY), v.max.unwrap_or(f64::INFINITY));
        if lower > upper {
            return Err(bad(format!("min {lower} is above max {upper}")));
        }
        if as_radius {
            // radius bounds become curvature bounds, on one side of 0 only
            // (a flat surface is the radius at infinity on either side)
            (lower, upper) = match (v.min, v.max) {
                (None, None) => (lower, upper),
                (Some(a), Some(b)) if a > 0.0 || b < 0.0 => (1.0 / b, 1.0 / a),
                (Some(a), None) if a > 0.0 => (0.0, 1.0 / a),
                (None, Some(b)) if b < 0.0 => (1.0 / b, 0.0),
                _ => {
                    return Err(bad(format!(
                        "the radius bounds [{}, {}] reach across 0 mm (no surface): give bounds of one sign (a radius from 10 to 200 mm, or from -200 to -10 mm), or bound its curvature instead (\"param\": \"curvature\")",
                        v.min.map_or("-infinity".into(), |b| b.to_string()),
                        v.max.map_or("infinity".into(), |b| b.to_string())
                    )))
                }
            };
        }
        let var = Variable { surface: v.surface, param, lower, upper, as_radius };
        let start = var.read(spec);
        if start < var.lower || start > var.upper {
            return Err(bad(format!(
                "its starting value {} lies outside its bounds [{}, {}]: widen them or change the prescription",
                var.shown(start),
                v.min.map_or("-infinity".into(), |b| b.to_string()),
                v.max.map_or("infinity".into(), |b| b.to_string())
            )));
        }
        Ok(var)
    }

    /// The variable's value in `spec` (curvature 1/mm for a radius; 0 for
    /// an unset conic or coefficient).
    pub fn read(&self, spec: &PrescriptionSpec) -> f64 {
        let s = &spec.surfaces[self.surface - 1];
        match self.param {
            Param::Curvature => s.curvature().unwrap_or(0.0),
            Param::Thickness => s.thickness,
            Param::Conic => s.conic.unwrap_or(0.0),
            Param::Aspheric { order } => s.aspheric.as_ref().and_then(|a| a.get(order / 2 - 1)).copied().unwrap_or(0.0),
            Param::Nd => match &s.glass {
                Some(GlassSpec::Model { nd, .. }) => *nd,
                _ => s.ior.unwrap_or(1.0),
            },
            Param::Vd => match &s.glass {
                Some(GlassSpec::Model { vd, .. }) => *vd,
                _ => 0.0,
            },
        }
    }

    /// Writes `x` (the variable's unit) into `spec`.
    pub fn write(&self, spec: &mut PrescriptionSpec, x: f64) {
        let s = &mut spec.surfaces[self.surface - 1];
        match self.param {
            Param::Curvature => s.radius = (x != 0.0).then(|| 1.0 / x),
            Param::Thickness => s.thickness = x,
            Param::Conic => s.conic = Some(x),
            Param::Aspheric { order } => {
                let a = s.aspheric.get_or_insert_with(Vec::new);
                let k = order / 2 - 1;
                if a.len() <= k {
                    a.resize(k + 1, 0.0);
                }
                a[k] = x;
            }
            Param::Nd => match &mut s.glass {
                Some(GlassSpec::Model { nd, .. }) => *nd = x,
                _ => s.ior = Some(x),
            },
            Param::Vd => {
                if let Some(GlassSpec::Model { vd, .. }) = &mut s.glass {
                    *vd = x
                }
            }
        }
    }

    /// A value as reports show it: a radius for a variable given as one
    /// (`inf` for flat), the value itself otherwise.
    pub fn shown(&self, x: f64) -> f64 {
        if self.as_radius {
            if x == 0.0 {
                f64::INFINITY
            } else {
                1.0 / x
            }
        } else {
            x
        }
    }

    /// The variable's name for reports: `surface 3 radius`.
    pub fn label(&self) -> String {
        let p = if self.as_radius { "radius".to_string() } else { self.param.name() };
        format!("surface {} {p}", self.surface)
    }

    /// A typical size of the variable at `x`, for finite-difference steps:
    /// the scale on which it changes the lens.
    pub fn scale(&self, x: f64, spec: &PrescriptionSpec) -> f64 {
        let typical = match self.param {
            // a curvature's scale is that of the lens: 1 / (its aperture
            // or 10 mm)
            Param::Curvature => {
                let sd = spec.surfaces[self.surface - 1].semi_diameter.unwrap_or(10.0).max(1e-3);
                1.0 / (100.0 * sd)
            }
            Param::Thickness => 1.0,
            Param::Conic => 1.0,
            Param::Aspheric { order } => {
                let sd = spec.surfaces[self.surface - 1].semi_diameter.unwrap_or(10.0).max(1e-3);
                // a coefficient that moves the rim by 1 um
                1e-3 / sd.powi(order as i32)
            }
            Param::Nd => 0.01,
            Param::Vd => 1.0,
        };
        x.abs().max(typical)
    }
}
