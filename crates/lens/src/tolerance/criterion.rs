//! The criterion a toleranced lens is judged by, with its compensators
//! adjusted first.
//!
//! The criterion is built of design operands, one per field (RMS spot,
//! RMS wavefront or MTF: the numbers `lens spot`, `lens wavefront`, `lens
//! mtf` print): for an RMS, the root of the mean square over the fields;
//! for an MTF, the mean. Compensators are design variables optimised by
//! damped least squares against those operands, with one exception done
//! in closed form: the back focus alone against an RMS spot. The rays
//! past the last surface are straight lines, so each field's mean square
//! spot radius about its centroid is exactly a quadratic in the film's
//! shift dz (`SpotDiagram::rms_at_shift`), and the sum over the fields is
//! least at dz = -sum b_i / sum c_i.

use super::spec::{CompensatorSpec, CriterionSpec};
use crate::analysis::fan::ImagePlane;
use crate::analysis::pattern::Pattern;
use crate::analysis::spot::spot_polychromatic;
use crate::analysis::{Aim, Field, Launcher};
use crate::design::spec::{DesignSpec, OperandSpec, VariableSpec};
use crate::design::{Design, DesignError};
use crate::glass::Catalogs;
use crate::paraxial::FirstOrder;
use crate::{Prescription, PrescriptionSpec};

/// How a lens is judged.
#[derive(Debug, Clone)]
pub struct Criterion {
    /// `rms_spot`, `rms_wavefront` or `mtf`.
    pub kind: String,
    /// The fields, degrees (y).
    pub fields_deg: Vec<f64>,
    /// Each field's x component, degrees (0: along y).
    pub fields_x_deg: Vec<f64>,
    /// Gauss rings of an RMS spot.
    pub rings: usize,
    /// The operands (one per field) and the compensators as a design.
    design: Design,
    /// Back focus alone against an RMS spot: done in closed form.
    closed_form: bool,
    /// The back focus is a compensator: least squares starts from the
    /// film of least RMS spot (an MTF against focus has side lobes a
    /// start at the nominal film can fall into).
    back_focus: bool,
}

impl Criterion {
    /// The criterion of `c` with `compensators` on the nominal `spec`.
    pub fn new(
        c: &CriterionSpec,
        compensators: &[CompensatorSpec],
        wavelengths_nm: Option<Vec<f64>>,
        spec: &PrescriptionSpec,
        catalogs: &Catalogs,
    ) -> Result<Criterion, DesignError> {
        let bad = |why: String| DesignError::Tolerance(format!("criterion: {why}"));
        let fields_deg = c.fields_deg.clone().unwrap_or_else(|| vec![0.0]);
        if fields_deg.is_empty() {
            return Err(bad("fields_deg is empty: give one field or more".into()));
        }
        let fields_x_deg = c.fields_x_deg.clone().unwrap_or_else(|| vec![0.0; fields_deg.len()]);
        if fields_x_deg.len() != fields_deg.len() {
            return Err(bad(format!(
                "fields_x_deg has {} angles and fields_deg {}: give each field's x component, in the same order",
                fields_x_deg.len(),
                fields_deg.len()
            )));
        }
        let rings = c.rings.unwrap_or(6);
        match c.kind.as_str() {
            "rms_spot" | "rms_wavefront" | "mtf" => {}
            k => return Err(bad(format!("type \"{k}\": one of rms_spot, rms_wavefront, mtf"))),
        }
        if c.kind != "rms_spot" && c.rings.is_some() {
            return Err(bad("\"rings\" belongs to an rms_spot criterion".into()));
        }
        if c.kind != "mtf" && (c.frequency_per_mm.is_some() || c.orientation.is_some()) {
            return Err(bad("\"frequency_per_mm\" and \"orientation\" belong to an mtf criterion".into()));
        }
        if c.kind == "mtf" && c.frequency_per_mm.is_none() {
            return Err(bad("give \"frequency_per_mm\" (cycles/mm) for an mtf criterion".into()));
        }
        let operands = fields_deg
            .iter()
            .zip(&fields_x_deg)
            .map(|(&f, &x)| OperandSpec {
                kind: c.kind.clone(),
                field_deg: Some(f),
                field_x_deg: (x != 0.0).then_some(x),
                rings: (c.kind == "rms_spot").then_some(rings),
                frequency_per_mm: c.frequency_per_mm,
                orientation: c.orientation.clone(),
                ..OperandSpec::default()
            })
            .collect();
        let last = spec.surfaces.len();
        let mut variables = Vec::new();
        let mut back_focus = false;
        for (i, comp) in compensators.iter().enumerate() {
            match comp {
                CompensatorSpec::Named { kind } if kind == "back_focus" => {
                    back_focus = true;
                    variables.push(VariableSpec {
                        surface: last,
                        param: "thickness".into(),
                        order: None,
                        min: Some(0.0),
                        max: None,
                    });
                }
                CompensatorSpec::Named { kind } => {
                    return Err(DesignError::Tolerance(format!(
                        "compensator {}: \"{kind}\": give {{\"type\": \"back_focus\"}} or a variable ({{\"surface\": 3, \"param\": \"thickness\"}})",
                        i + 1
                    )))
                }
                CompensatorSpec::Variable(v) => variables.push(v.clone()),
            }
        }
        let compensated = !variables.is_empty();
        if !compensated {
            // a design needs a variable; with none it is only evaluated
            variables.push(VariableSpec {
                surface: last,
                param: "thickness".into(),
                order: None,
                min: None,
                max: None,
            });
        }
        let d = DesignSpec {
            prescription: String::new(),
            variables,
            operands,
            wavelengths_nm,
            wavelength_weights: None,
            primary_wavelength_nm: None,
            image: None,
            glass_substitution: None,
            max_iterations: Some(if compensated { 30 } else { 0 }),
        };
        let design = Design::new(&d, spec.clone(), catalogs.clone()).map_err(|e| match e {
            DesignError::Variable { what, why } => DesignError::Tolerance(format!("compensator: {what}: {why}")),
            e => e,
        })?;
        let closed_form = back_focus && compensators.len() == 1 && c.kind == "rms_spot";
        Ok(Criterion { kind: c.kind.clone(), fields_deg, fields_x_deg, rings, design, closed_form, back_focus })
    }

    /// Whether a smaller value is better (an RMS) or a larger (an MTF).
    pub fn lower_is_better(&self) -> bool {
        self.kind != "mtf"
    }

    /// The criterion of the lens `spec` after compensation, and the
    /// compensators' values. Errors (the lens invalid, a field not
    /// measurable) say why.
    pub fn judge(&self, spec: &PrescriptionSpec) -> Result<(f64, Vec<f64>), DesignError> {
        if self.closed_form {
            return self.closed_form_back_focus(&self.design.measured_lens(spec)?);
        }
        let mut spec = spec.clone();
        if self.back_focus {
            if let Ok((_, film)) = self.closed_form_back_focus(&self.design.measured_lens(&spec)?) {
                if let Some(last) = spec.surfaces.last_mut() {
                    last.thickness = film[0];
                }
            }
        }
        let design = self.design.with_start(spec, |_| true)?;
        let x0 = design.start_values();
        let x = if design.max_iterations > 0 { crate::design::optimize::refine(&design, &x0)?.0.x } else { x0 };
        let e = design.evaluate(&x)?;
        Ok((self.combine(&e.values), x))
    }

    /// Per-field values into one number.
    fn combine(&self, values: &[f64]) -> f64 {
        let n = values.len() as f64;
        if self.lower_is_better() {
            (values.iter().map(|v| v * v).sum::<f64>() / n).sqrt()
        } else {
            values.iter().sum::<f64>() / n
        }
    }

    /// The back focus refocused for the least mean square spot over the
    /// fields, in closed form.
    fn closed_form_back_focus(&self, lens: &Prescription) -> Result<(f64, Vec<f64>), DesignError> {
        let waves = &self.design.waves;
        let why = |x: f64, f: f64| {
            move |e: crate::OpticsError| DesignError::Measure {
                what: match x {
                    0.0 => format!("the RMS spot at field {} deg", crate::error::num(f)),
                    _ => {
                        format!("the RMS spot at field x {} deg, y {} deg", crate::error::num(x), crate::error::num(f))
                    }
                },
                why: e.to_string(),
            }
        };
        let first = FirstOrder::of(lens).map_err(why(0.0, 0.0))?;
        let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
        for (&f, &x) in self.fields_deg.iter().zip(&self.fields_x_deg) {
            let field = Field::at_angles(lens, &first, x, f);
            let l = Launcher::with_first(lens, &first, field, Aim::Auto).map_err(why(x, f))?;
            let s = spot_polychromatic(lens, &l, Pattern::Gauss, self.rings, ImagePlane::ImageSurface, waves)
                .map_err(why(x, f))?;
            let (q0, qp, qm) = (s.rms_at_shift(0.0).powi(2), s.rms_at_shift(1.0).powi(2), s.rms_at_shift(-1.0).powi(2));
            a += q0;
            b += (qp - qm) / 4.0;
            c += (qp + qm) / 2.0 - q0;
        }
        let film = lens.film_distance();
        let mut dz = if c > 0.0 { -b / c } else { 0.0 };
        if film + dz <= 0.0 {
            dz = -film * 0.999; // the film cannot pass the last vertex
        }
        let n = self.fields_deg.len() as f64;
        let value = ((a + 2.0 * b * dz + c * dz * dz).max(0.0) / n).sqrt();
        Ok((value, vec![film + dz]))
    }
}
