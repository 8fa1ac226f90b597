//! The merit function of a design: the variables written into the
//! starting prescription, the candidate built and checked like any
//! prescription file, its operands measured.
//!
//! Merit = sqrt(sum w_i m_i^2 / sum w_i), with m_i the operand's miss of
//! its goal ([`super::operands::Goal::miss`]); the least-squares residuals
//! are sqrt(w_i) m_i / sqrt(sum w).

use super::operands::{Candidate, Operand};
use super::spec::{DesignSpec, GlassSubstitutionSpec};
use super::variables::Variable;
use super::DesignError;
use crate::glass::{Catalog, Catalogs};
use crate::paraxial::{imaging, FirstOrder, ObjectDistance};
use crate::{Prescription, PrescriptionSpec};
use std::path::Path;

/// A design ready to evaluate: the starting prescription, the variables,
/// the operands and the settings.
#[derive(Debug, Clone)]
pub struct Design {
    /// The starting prescription as written (what the designed file keeps
    /// but for the variables).
    pub start: PrescriptionSpec,
    /// The starting prescription with the merit function's wavelengths.
    evaluated: PrescriptionSpec,
    /// Where glass names are looked up.
    pub catalogs: Catalogs,
    /// The variables.
    pub variables: Vec<Variable>,
    /// The operands.
    pub operands: Vec<Operand>,
    /// The merit function's wavelengths and weights, nm.
    pub waves: Vec<(f64, f64)>,
    /// Whether each candidate's last thickness is solved to its paraxial
    /// image.
    pub paraxial_image: bool,
    /// Glass substitution after optimising, if asked.
    pub substitution: Option<GlassSubstitutionSpec>,
    /// The most iterations.
    pub max_iterations: usize,
}

/// One candidate's operand values and merit.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The prescription as written at these variables (the last thickness
    /// solved where asked).
    pub spec: PrescriptionSpec,
    /// The lens measured (the merit function's wavelengths).
    pub lens: Prescription,
    /// Each operand's value.
    pub values: Vec<f64>,
    /// The merit function.
    pub merit: f64,
}

impl Design {
    /// Reads a design file: its prescription (relative to the file), with
    /// the prescription's own glass catalogues and `extra` searched first.
    pub fn load(path: &Path, extra: Vec<Catalog>) -> Result<Design, DesignError> {
        let d: DesignSpec = super::read_json(path)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let (spec, catalogs) = crate::io::load_spec_and_catalogs(&dir.join(&d.prescription), extra)?;
        Design::new(&d, spec, catalogs)
    }

    /// The design of `d` over the starting prescription `start`, glass
    /// names looked up in `catalogs`. Checks every variable and operand and
    /// that the starting lens can be measured.
    pub fn new(d: &DesignSpec, start: PrescriptionSpec, catalogs: Catalogs) -> Result<Design, DesignError> {
        if d.operands.is_empty() {
            return Err(DesignError::Spec("\"operands\" is empty: give at least one operand".into()));
        }
        if d.variables.is_empty() {
            return Err(DesignError::Spec("\"variables\" is empty: give at least one variable".into()));
        }
        let variables = d
            .variables
            .iter()
            .enumerate()
            .map(|(i, v)| Variable::from_spec(v, i, &start))
            .collect::<Result<Vec<_>, _>>()?;
        for (i, a) in variables.iter().enumerate() {
            if let Some(j) = variables[..i].iter().position(|b| b.surface == a.surface && b.param == a.param) {
                return Err(DesignError::Spec(format!(
                    "variables {} and {} both vary {}: give each once",
                    j + 1,
                    i + 1,
                    a.label()
                )));
            }
        }
        let operands = d
            .operands
            .iter()
            .enumerate()
            .map(|(i, o)| Operand::from_spec(o, i, &start))
            .collect::<Result<Vec<_>, _>>()?;
        if operands.iter().all(|o| o.weight == 0.0) {
            return Err(DesignError::Spec("every operand has weight 0: the merit function is 0 for any lens".into()));
        }
        let image = match d.image.as_deref() {
            None | Some("surface") => false,
            Some("paraxial") => true,
            Some(x) => return Err(DesignError::Spec(format!("image \"{x}\": one of \"surface\", \"paraxial\""))),
        };
        let last = start.surfaces.len();
        if image && variables.iter().any(|v| v.surface == last && v.param == super::variables::Param::Thickness) {
            return Err(DesignError::Spec(format!(
                "surface {last}'s thickness is a variable, but \"image\": \"paraxial\" solves it: drop one"
            )));
        }
        let mut evaluated = start.clone();
        if let Some(w) = &d.wavelengths_nm {
            if w.is_empty() || w.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(DesignError::Spec("wavelengths_nm: give one or more wavelengths above 0 nm".into()));
            }
            evaluated.wavelengths_nm = Some(w.clone());
            evaluated.wavelength_weights = d.wavelength_weights.clone();
            let keep = start.primary_wavelength_nm.filter(|p| w.contains(p));
            evaluated.primary_wavelength_nm = d.primary_wavelength_nm.or(keep);
        } else if d.wavelength_weights.is_some() {
            return Err(DesignError::Spec("wavelength_weights needs wavelengths_nm beside it".into()));
        } else if d.primary_wavelength_nm.is_some() {
            evaluated.primary_wavelength_nm = d.primary_wavelength_nm;
        }
        let lens = Prescription::from_spec_with(&evaluated, &catalogs)
            .map_err(|findings| DesignError::Invalid { what: "the starting lens".into(), findings })?;
        let waves = lens.wavelengths_nm().iter().copied().zip(lens.wavelength_weights()).collect();
        let max_iterations = d.max_iterations.unwrap_or(200);
        let design = Design {
            start,
            evaluated,
            catalogs,
            variables,
            operands,
            waves,
            paraxial_image: image,
            substitution: d.glass_substitution.clone(),
            max_iterations,
        };
        // the start must be measurable: every operand named if not
        design.evaluate(&design.start_values()).map_err(|e| match e {
            DesignError::Measure { what, why } => {
                DesignError::Measure { what: format!("{what} of the starting lens"), why }
            }
            e => e,
        })?;
        Ok(design)
    }

    /// The same design from another start (glasses substituted, say),
    /// keeping the variables `keep` accepts and the merit's wavelengths.
    pub fn with_start(&self, start: PrescriptionSpec, keep: impl Fn(&Variable) -> bool) -> Result<Design, DesignError> {
        let mut evaluated = start.clone();
        evaluated.wavelengths_nm = self.evaluated.wavelengths_nm.clone();
        evaluated.wavelength_weights = self.evaluated.wavelength_weights.clone();
        evaluated.primary_wavelength_nm = self.evaluated.primary_wavelength_nm;
        Prescription::from_spec_with(&evaluated, &self.catalogs).map_err(|findings| DesignError::Invalid {
            what: "the lens with its glasses substituted".into(),
            findings,
        })?;
        let variables: Vec<Variable> = self.variables.iter().filter(|v| keep(v)).cloned().collect();
        if variables.is_empty() {
            return Err(DesignError::Spec("no variable is left to optimise after glass substitution".into()));
        }
        Ok(Design { start, evaluated, variables, ..self.clone() })
    }

    /// `written` with the merit function's wavelengths.
    fn with_merit_wavelengths(&self, written: &PrescriptionSpec) -> PrescriptionSpec {
        let mut evaluated = written.clone();
        evaluated.wavelengths_nm = self.evaluated.wavelengths_nm.clone();
        evaluated.wavelength_weights = self.evaluated.wavelength_weights.clone();
        evaluated.primary_wavelength_nm = self.evaluated.primary_wavelength_nm;
        evaluated
    }

    /// The lens of the prescription `written` as this design measures it
    /// (the merit function's wavelengths), without its variables applied.
    pub fn measured_lens(&self, written: &PrescriptionSpec) -> Result<Prescription, DesignError> {
        Prescription::from_spec_with(&self.with_merit_wavelengths(written), &self.catalogs)
            .map_err(|findings| DesignError::Invalid { what: "the lens".into(), findings })
    }

    /// The variables' starting values.
    pub fn start_values(&self) -> Vec<f64> {
        self.variables.iter().map(|v| v.read(&self.start)).collect()
    }

    /// The prescription at `x` as written (the start's wavelengths), and
    /// the lens to measure (the merit's wavelengths), the last thickness
    /// solved to the paraxial image where asked.
    pub fn lens_at(&self, x: &[f64]) -> Result<(PrescriptionSpec, Prescription), DesignError> {
        let mut written = self.start.clone();
        let mut evaluated = self.evaluated.clone();
        for (v, &value) in self.variables.iter().zip(x) {
            v.write(&mut written, value);
            v.write(&mut evaluated, value);
        }
        let invalid = |findings| DesignError::Invalid { what: "the lens at these variables".into(), findings };
        let mut lens = Prescription::from_spec_with(&evaluated, &self.catalogs).map_err(invalid)?;
        if self.paraxial_image {
            let measure = |e: crate::OpticsError| DesignError::Measure {
                what: "the paraxial image solve".into(),
                why: e.to_string(),
            };
            let first = FirstOrder::of(&lens).map_err(measure)?;
            let object =
                ObjectDistance::from_mm(lens.object_distance_mm().unwrap_or(f64::INFINITY)).map_err(measure)?;
            let d = imaging(&lens, &first, object).map_err(measure)?.image_distance;
            lens = lens.with_film_distance(d).map_err(measure)?;
            if let Some(last) = written.surfaces.last_mut() {
                last.thickness = d;
            }
        }
        Ok((written, lens))
    }

    /// The operand values and merit at `x`.
    pub fn evaluate(&self, x: &[f64]) -> Result<Evaluation, DesignError> {
        let (spec, lens) = self.lens_at(x)?;
        let first = FirstOrder::of(&lens)
            .map_err(|e| DesignError::Measure { what: "first-order data".into(), why: e.to_string() })?;
        let c = Candidate { lens: &lens, first, spec: &spec, waves: &self.waves };
        let values = self
            .operands
            .iter()
            .enumerate()
            .map(|(i, o)| {
                c.measure(&o.measure).map_err(|why| DesignError::Measure {
                    what: format!("operand {} ({} {})", i + 1, o.name(), o.place()).trim_end().replace(" )", ")"),
                    why,
                })
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let merit = self.merit_of(&values);
        Ok(Evaluation { spec, lens, values, merit })
    }

    /// The least-squares residuals of operand values: sqrt(w_i / sum w)
    /// times each miss, so that their sum of squares is the merit squared.
    pub fn residuals(&self, values: &[f64]) -> Vec<f64> {
        let total: f64 = self.operands.iter().map(|o| o.weight).sum();
        self.operands.iter().zip(values).map(|(o, &v)| (o.weight / total).sqrt() * o.goal.miss(v)).collect()
    }

    /// The merit function of operand values.
    pub fn merit_of(&self, values: &[f64]) -> f64 {
        self.residuals(values).iter().map(|r| r * r).sum::<f64>().sqrt()
    }
}
