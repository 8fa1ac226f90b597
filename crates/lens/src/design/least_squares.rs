//! Damped least squares (Levenberg–Marquardt) with bounds: minimises
//! sum r_i(x)^2 over a box lo <= x <= hi.
//!
//! Each iteration takes a forward-difference Jacobian (its columns
//! evaluated in parallel), then solves (J'J + lambda D) dx = -J'r on the
//! free variables (D the diagonal of J'J: Marquardt's scaling, so the
//! result does not depend on the variables' units). A variable at a bound
//! whose gradient points out of the box is held for that step; a step is
//! clipped into the box. lambda follows Nielsen's rule from the gain ratio
//! (actual over predicted reduction). A point where the residuals cannot
//! be evaluated (an invalid lens) counts as a failed step.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The most iterations (Jacobians).
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the sum of squares by less than
    /// this fraction of it.
    pub ftol: f64,
    /// Relative finite-difference step (times each variable's scale).
    pub fd_step: f64,
    /// Stop when the root of the sum of squares (the merit) fell by less
    /// than `stall_tol` of itself over the last `stall_iterations`
    /// iterations: the crawl along a kink (an inequality switching on and
    /// off, a ray vignetted and not) that damped least squares makes
    /// little progress on.
    pub stall_iterations: usize,
    /// See `stall_iterations`.
    pub stall_tol: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings { max_iterations: 200, ftol: 1e-10, fd_step: 1e-7, stall_iterations: 10, stall_tol: 1e-3 }
    }
}

/// Why the minimiser stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// Every residual is 0.
    Zero,
    /// The last accepted step gained less than `ftol`.
    Converged,
    /// No step in the damped directions lowers the sum (a minimum to the
    /// precision of the residuals, or a wall of invalid lenses).
    NoDescent,
    /// The merit fell by less than `stall_tol` over `stall_iterations`.
    Stalled,
    /// `max_iterations` reached.
    MaxIterations,
}

/// The result of [`minimize`].
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The best point found.
    pub x: Vec<f64>,
    /// Its residuals.
    pub residuals: Vec<f64>,
    /// Sum of squares after each iteration (the start first).
    pub history: Vec<f64>,
    /// Iterations (Jacobians) taken.
    pub iterations: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Why it stopped.
    pub stop: Stop,
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimises the sum of squares of `f(x)` from `x0` within `[lo, hi]`.
/// `scale[j]` is a typical size of variable j (its finite-difference step
/// is `fd_step * max(|x_j|, scale_j)`). `f` returns `None` where it cannot
/// be evaluated; at `x0` that is the caller's to have checked (the result
/// is then `None`).
pub fn minimize<F>(f: F, x0: &[f64], lo: &[f64], hi: &[f64], scale: &[f64], settings: Settings) -> Option<Minimum>
where
    F: Fn(&[f64]) -> Option<Vec<f64>> + Sync,
{
    let n = x0.len();
    let mut x: Vec<f64> = x0.iter().zip(lo.iter().zip(hi)).map(|(v, (a, b))| v.clamp(*a, *b)).collect();
    let mut r = f(&x)?;
    let mut evaluations = 1;
    let mut cost = sum_sq(&r);
    let mut history = vec![cost];
    let (mut lambda, mut nu) = (1e-3, 2.0);
    let mut iterations = 0;
    let mut stop = Stop::MaxIterations;
    while iterations < settings.max_iterations {
        if cost == 0.0 {
            stop = Stop::Zero;
            break;
        }
        iterations += 1;
        let (jac, evals) = jacobian(&f, &x, &r, lo, hi, scale, settings.fd_step);
        evaluations += evals;
        let m = r.len();
        let j = DMatrix::from_fn(m, n, |i, k| jac[k][i]);
        let rv = DVector::from_column_slice(&r);
        let a = j.transpose() * &j;
        let g = j.transpose() * &rv;
        // held: at a bound with the descent direction (-g) pointing out
        let free: Vec<usize> = (0..n)
            .filter(|&k| {
                let at_lo = x[k] <= lo[k] && g[k] > 0.0;
                let at_hi = x[k] >= hi[k] && g[k] < 0.0;
                !(at_lo || at_hi) && a[(k, k)] > 0.0
            })
            .collect();
        if free.is_empty() {
            stop = Stop::NoDescent;
            break;
        }
        let nf = free.len();
        let af = DMatrix::from_fn(nf, nf, |i, k| a[(free[i], free[k])]);
        let gf = DVector::from_fn(nf, |i, _| g[free[i]]);
        let diag_max = (0..nf).map(|i| af[(i, i)]).fold(0.0f64, f64::max);
        let mut accepted = false;
        let mut gained = f64::INFINITY;
        while lambda < 1e16 {
            let mut damped = af.clone();
            for i in 0..nf {
                damped[(i, i)] += lambda * af[(i, i)].max(1e-12 * diag_max);
            }
            let Some(ch) = damped.cholesky() else {
                lambda *= nu;
                nu *= 2.0;
                continue;
            };
            let step = ch.solve(&(-&gf));
            let mut trial = x.clone();
            for (i, &k) in free.iter().enumerate() {
                trial[k] = (x[k] + step[i]).clamp(lo[k], hi[k]);
            }
            if trial == x {
                break;
            }
            // predicted reduction of the linear model with the clipped step
            let dx = DVector::from_fn(n, |k, _| trial[k] - x[k]);
            let jd = &j * &dx;
            let predicted = -(2.0 * rv.dot(&jd) + jd.dot(&jd));
            evaluations += 1;
            match f(&trial) {
                Some(rt) if sum_sq(&rt) < cost => {
                    let new_cost = sum_sq(&rt);
                    let rho = if predicted > 0.0 { (cost - new_cost) / predicted } else { 0.5 };
                    lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    gained = (cost - new_cost) / cost;
                    x = trial;
                    r = rt;
                    cost = new_cost;
                    accepted = true;
                    break;
                }
                _ => {
                    lambda *= nu;
                    nu *= 2.0;
                }
            }
        }
        history.push(cost);
        if !accepted {
            stop = Stop::NoDescent;
            break;
        }
        if gained < settings.ftol {
            stop = Stop::Converged;
            break;
        }
        let k = history.len() - 1;
        if k >= settings.stall_iterations
            && history[k - settings.stall_iterations].sqrt() - history[k].sqrt()
                < settings.stall_tol * history[k].sqrt()
        {
            stop = Stop::Stalled;
            break;
        }
    }
    Some(Minimum { x, residuals: r, history, iterations, evaluations, stop })
}

/// Forward-difference Jacobian columns (each a vector of residual
/// derivatives), in parallel; a step that would leave the box, or lands on
/// a point that cannot be evaluated, is taken backward instead; where
/// neither works the column is 0 (the variable held this iteration).
fn jacobian<F>(f: &F, x: &[f64], r: &[f64], lo: &[f64], hi: &[f64], scale: &[f64], fd: f64) -> (Vec<Vec<f64>>, usize)
where
    F: Fn(&[f64]) -> Option<Vec<f64>> + Sync,
{
    let cols: Vec<(Vec<f64>, usize)> = (0..x.len())
        .into_par_iter()
        .map(|k| {
            let h = fd * x[k].abs().max(scale[k]);
            let mut evals = 0;
            for h in [h, -h] {
                let v = x[k] + h;
                if v > hi[k] || v < lo[k] {
                    continue;
                }
                let mut xp = x.to_vec();
                xp[k] = v;
                let dh = v - x[k]; // the step as represented
                evals += 1;
                if let Some(rp) = f(&xp) {
                    return (rp.iter().zip(r).map(|(a, b)| (a - b) / dh).collect(), evals);
                }
            }
            (vec![0.0; r.len()], evals)
        })
        .collect();
    let evals = cols.iter().map(|c| c.1).sum();
    (cols.into_iter().map(|c| c.0).collect(), evals)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as least squares (r = (10 (y - x^2), 1 - x)) reaches its
    /// minimum (1, 1) from (-1.2, 1).
    #[test]
    fn rosenbrock() {
        let f = |x: &[f64]| Some(vec![10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]]);
        let inf = f64::INFINITY;
        let m = minimize(f, &[-1.2, 1.0], &[-inf, -inf], &[inf, inf], &[1.0, 1.0], Settings::default()).unwrap();
        assert!((m.x[0] - 1.0).abs() < 1e-6 && (m.x[1] - 1.0).abs() < 1e-6, "{m:?}");
    }

    /// A bound that holds the minimum back: min (x - 3)^2 + (y + 1)^2 with
    /// x <= 2, y >= 0 ends at the corner (2, 0).
    #[test]
    fn bounds_hold() {
        let f = |x: &[f64]| Some(vec![x[0] - 3.0, x[1] + 1.0]);
        let m = minimize(f, &[0.0, 1.0], &[-10.0, 0.0], &[2.0, 10.0], &[1.0, 1.0], Settings::default()).unwrap();
        assert!((m.x[0] - 2.0).abs() < 1e-12 && m.x[1].abs() < 1e-12, "{m:?}");
    }

    /// Points that cannot be evaluated are stepped around: the valid region
    /// is x < 1.5 and the minimum of (x - 2)^2 within it is approached.
    #[test]
    fn invalid_points_are_rejected() {
        let f = |x: &[f64]| (x[0] < 1.5).then(|| vec![x[0] - 2.0]);
        let m = minimize(f, &[0.0], &[-10.0], &[10.0], &[1.0], Settings::default()).unwrap();
        assert!(m.x[0] < 1.5 && m.x[0] > 1.49, "{m:?}");
    }
}
