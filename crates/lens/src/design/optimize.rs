//! The optimisation loop: the dependence check, damped least squares from
//! the start, and glass substitution with its re-optimisation.

use super::glass_substitution::{nearest, Substitution};
use super::least_squares::{minimize, Minimum, Settings, Stop};
use super::merit::{Design, Evaluation};
use super::variables::Param;
use super::DesignError;
use crate::model::spec::GlassSpec;
use rayon::prelude::*;
use std::time::Instant;

/// What an optimisation did.
#[derive(Debug, Clone)]
pub struct Optimized {
    /// The start: variables, operand values, merit.
    pub start: Evaluation,
    /// The variables' starting values.
    pub x_start: Vec<f64>,
    /// The end.
    pub end: Evaluation,
    /// The variables' final values (those left after glass substitution:
    /// see `variables`).
    pub x_end: Vec<f64>,
    /// The design the end belongs to (after substitution its glasses are
    /// catalogue glasses and their nd and vd no longer variables).
    pub design: Design,
    /// The merit after each iteration (the start first), across both
    /// passes when glasses were substituted.
    pub history: Vec<f64>,
    /// Iterations (Jacobians).
    pub iterations: usize,
    /// Merit evaluations.
    pub evaluations: usize,
    /// Wall time, seconds.
    pub seconds: f64,
    /// Why the (last) pass stopped.
    pub stop: Stop,
    /// Model glasses replaced.
    pub substitutions: Vec<Substitution>,
    /// What the user should know (a variable that changes no operand).
    pub warnings: Vec<String>,
}

/// Optimises `design` from its start.
pub fn optimize(design: &Design) -> Result<Optimized, DesignError> {
    let t0 = Instant::now();
    let x_start = design.start_values();
    let start = design.evaluate(&x_start)?;
    // with no iteration to take, the start is only evaluated
    let warnings = if design.max_iterations > 0 { dependence(design, &x_start, &start)? } else { Vec::new() };
    let (mut m, mut evaluations) = refine(design, &x_start)?;
    let mut history: Vec<f64> = m.history.iter().map(|c| c.sqrt()).collect();
    let mut iterations = m.iterations;
    let mut substitutions = Vec::new();
    let mut design = design.clone();
    if let Some(sub) = design.substitution.clone() {
        let (spec, _) = design.lens_at(&m.x)?;
        let mut replaced = spec.clone();
        for (i, s) in spec.surfaces.iter().enumerate() {
            if let Some(GlassSpec::Model { nd, vd }) = s.glass {
                let (g, catalogue) = nearest(&design.catalogs, sub.catalogs.as_deref(), nd, vd).ok_or_else(|| {
                    DesignError::Spec(format!(
                        "glass_substitution: no glass in the catalogues {:?} has nd and vd",
                        sub.catalogs.clone().unwrap_or_default()
                    ))
                })?;
                replaced.surfaces[i].glass = Some(GlassSpec::Name(g.full_name()));
                substitutions.push(Substitution { surface: i + 1, model: [nd, vd], glass: g.full_name(), catalogue });
            }
        }
        if !substitutions.is_empty() {
            design = design.with_start(replaced, |v| !matches!(v.param, Param::Nd | Param::Vd))?;
            let x = design.start_values();
            let (m2, e2) = refine(&design, &x)?;
            history.extend(m2.history.iter().skip(1).map(|c| c.sqrt()));
            iterations += m2.iterations;
            evaluations += e2;
            m = m2;
        }
    }
    let end = design.evaluate(&m.x)?;
    Ok(Optimized {
        start,
        x_start,
        end,
        x_end: m.x,
        design,
        history,
        iterations,
        evaluations,
        seconds: t0.elapsed().as_secs_f64(),
        stop: m.stop,
        substitutions,
        warnings,
    })
}

/// Damped least squares on `design` from `x0` (evaluations counted).
pub fn refine(design: &Design, x0: &[f64]) -> Result<(Minimum, usize), DesignError> {
    let lo: Vec<f64> = design.variables.iter().map(|v| v.lower).collect();
    let hi: Vec<f64> = design.variables.iter().map(|v| v.upper).collect();
    let scale: Vec<f64> = design.variables.iter().zip(x0).map(|(v, &x)| v.scale(x, &design.start)).collect();
    let settings = Settings { max_iterations: design.max_iterations, ..Settings::default() };
    let f = |x: &[f64]| design.evaluate(x).ok().map(|e| design.residuals(&e.values));
    let m = minimize(f, x0, &lo, &hi, &scale, settings)
        .ok_or_else(|| DesignError::Spec("the starting lens cannot be evaluated".into()))?;
    let evaluations = m.evaluations;
    Ok((m, evaluations))
}

/// Each variable nudged (by a step a thousand times the Jacobian's): the
/// variables that change no operand value are named in warnings; when none
/// changes any, the merit function does not depend on the variables and
/// that is an error.
fn dependence(design: &Design, x0: &[f64], start: &Evaluation) -> Result<Vec<String>, DesignError> {
    let moves: Vec<bool> = (0..x0.len())
        .into_par_iter()
        .map(|k| {
            let v = &design.variables[k];
            let h = 1e-4 * v.scale(x0[k], &design.start);
            [h, -h].iter().any(|h| {
                let mut x = x0.to_vec();
                x[k] = (x0[k] + h).clamp(v.lower, v.upper);
                x[k] != x0[k]
                    && design.evaluate(&x).is_ok_and(|e| {
                        e.values
                            .iter()
                            .zip(&start.values)
                            .zip(&design.operands)
                            .any(|((a, b), o)| a != b && o.weight > 0.0)
                    })
            })
        })
        .collect();
    let still: Vec<String> =
        design.variables.iter().zip(&moves).filter(|(_, m)| !**m).map(|(v, _)| v.label()).collect();
    if still.len() == design.variables.len() {
        return Err(DesignError::NoDependence(format!(
            "no operand of weight above 0 changes when {} changes: vary what the operands measure",
            still.join(", ")
        )));
    }
    Ok(still.into_iter().map(|l| format!("{l} changes no operand of weight above 0: it stays where it is")).collect())
}
