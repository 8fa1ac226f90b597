//! Tolerancing (docs/tolerancing.md): how a design survives manufacturing.
//!
//! - [`spec`]: the tolerance file as written;
//! - [`perturbation`]: each tolerance, its distribution, and how a drawn
//!   value changes the prescription;
//! - [`criterion`]: the number a lens is judged by, after its compensators
//!   are adjusted;
//! - this module: the sensitivity table (each tolerance at + and - alone),
//!   the Monte Carlo trials and their statistics, shares of the trials and
//!   their merge.
//!
//! **Reproducible at any scale**: trial k draws its values from a random
//! stream made from (seed, k) alone, and its lens is judged by
//! deterministic code (the analyses sum in a fixed order whatever the
//! thread count), so a trial's result is the same bit for bit on any
//! machine, thread count or share; the statistics are computed from the
//! trials in the order of k.

pub mod criterion;
pub mod perturbation;
pub mod spec;

pub use criterion::Criterion;
pub use perturbation::{Distribution, Tolerance};
pub use spec::ToleranceSpec;

use crate::design::DesignError;
use crate::glass::{Catalog, Catalogs};
use crate::PrescriptionSpec;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The most trials of one run (its results are held in memory, about 40
/// bytes a trial).
pub const MAX_TRIALS: u64 = 100_000_000;

/// A tolerance analysis ready to run.
#[derive(Debug, Clone)]
pub struct Tolerancing {
    /// The nominal prescription (toleranced glasses as model glasses).
    pub nominal: PrescriptionSpec,
    /// The tolerances, in the file's order (the order values are drawn).
    pub tolerances: Vec<Tolerance>,
    /// The criterion and compensators.
    pub criterion: Criterion,
    /// The pass mark, if given.
    pub threshold: Option<f64>,
    /// Identifies the analysis (the nominal lens, tolerances, criterion):
    /// shares of different analyses are not merged.
    pub digest: String,
}

/// One trial's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrialResult {
    /// The trial's number, from 0.
    pub trial: u64,
    /// Its criterion after compensation, or `None` when it failed.
    pub value: Option<f64>,
    /// Why it failed: `"invalid: ..."` for a lens that is not one
    /// (surfaces crossing), `"unmeasured: ..."` for one that cannot be
    /// measured (every ray of a field blocked).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// One row of the sensitivity table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sensitivity {
    /// The tolerance, in words.
    pub tolerance: String,
    /// Its size.
    pub plus_minus: f64,
    /// The criterion with the tolerance at +plus_minus alone (None: failed).
    pub plus: Option<f64>,
    /// At -plus_minus.
    pub minus: Option<f64>,
    /// The larger change from nominal of the two (worse direction first:
    /// positive when the lens gets worse).
    pub change: Option<f64>,
}

/// The results of some or all trials: what `--shard I/N -o` writes and
/// `merge` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Share {
    /// The analysis's digest.
    pub digest: String,
    /// The seed.
    pub seed: u64,
    /// Trials of the whole run.
    pub trials: u64,
    /// This share (1-based) and the number of shares.
    pub shard: [u64; 2],
    /// The nominal criterion.
    pub nominal: f64,
    /// The sensitivity table.
    pub sensitivity: Vec<Sensitivity>,
    /// The share's trials, in order.
    pub results: Vec<TrialResult>,
}

/// Monte Carlo statistics over every trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Statistics {
    /// Trials run.
    pub trials: u64,
    /// Trials judged.
    pub judged: u64,
    /// Trials whose lens was not valid (surfaces crossing).
    pub invalid: u64,
    /// Trials whose lens could not be measured.
    pub unmeasured: u64,
    /// Mean criterion of the judged trials.
    pub mean: f64,
    /// Its standard deviation.
    pub std: f64,
    /// Percentiles 10, 50, 90, 98 (linear between order statistics).
    pub percentiles: Percentiles,
    /// The pass mark and the share of all trials meeting it (a failed
    /// trial does not).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
    /// See `threshold`.
    #[serde(rename = "yield", skip_serializing_if = "Option::is_none")]
    pub yield_fraction: Option<f64>,
    /// The worst trials (up to five): number, criterion and the values
    /// drawn for each tolerance.
    pub worst: Vec<Worst>,
    /// The first failure of each kind, to show what went wrong.
    pub failures: Vec<String>,
}

/// Percentiles of the criterion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Percentiles {
    /// 10th.
    pub p10: f64,
    /// 50th (median).
    pub p50: f64,
    /// 90th.
    pub p90: f64,
    /// 98th.
    pub p98: f64,
}

/// One of the worst trials.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Worst {
    /// The trial.
    pub trial: u64,
    /// Its criterion.
    pub value: f64,
    /// The values drawn, one per tolerance.
    pub drawn: Vec<f64>,
}

impl Tolerancing {
    /// Reads a tolerance file (its prescription relative to it).
    pub fn load(path: &Path, extra: Vec<Catalog>) -> Result<Tolerancing, DesignError> {
        let t: ToleranceSpec = crate::design::read_json(path)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let (spec, catalogs) = crate::io::load_spec_and_catalogs(&dir.join(&t.prescription), extra)?;
        Tolerancing::new(&t, spec, &catalogs)
    }

    /// The analysis of `t` on the nominal `spec`.
    pub fn new(t: &ToleranceSpec, spec: PrescriptionSpec, catalogs: &Catalogs) -> Result<Tolerancing, DesignError> {
        if t.tolerances.is_empty() {
            return Err(DesignError::Tolerance("\"tolerances\" is empty: give at least one".into()));
        }
        let default = Distribution::parse(t.distribution.as_deref()).map_err(DesignError::Tolerance)?;
        let tolerances = t
            .tolerances
            .iter()
            .enumerate()
            .map(|(i, x)| Tolerance::from_spec(x, i, &spec, default))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(th) = t.threshold {
            if !th.is_finite() {
                return Err(DesignError::Tolerance(format!("threshold {th}: give a finite number")));
            }
        }
        let nominal = perturbation::model_glasses(&spec, &tolerances, catalogs)?;
        let criterion = Criterion::new(&t.criterion, &t.compensators, t.wavelengths_nm.clone(), &nominal, catalogs)?;
        let digest =
            format!("{:016x}", fnv1a(&(serde_json::to_string(t).unwrap_or_default() + &nominal.to_json_string())));
        let tol = Tolerancing { nominal, tolerances, criterion, threshold: t.threshold, digest };
        tol.criterion.judge(&tol.nominal).map_err(|e| DesignError::Tolerance(format!("the nominal lens: {e}")))?;
        Ok(tol)
    }

    /// The values trial `k` of `seed` draws, one per tolerance: from a
    /// generator seeded by (seed, k) alone.
    pub fn draw(&self, seed: u64, k: u64) -> Vec<f64> {
        let mut z = seed ^ k.wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(z ^ (z >> 31) ^ seed.rotate_left(17));
        self.tolerances
            .iter()
            .map(|t| match t.distribution {
                Distribution::Uniform => t.plus_minus * (2.0 * rng.random::<f64>() - 1.0),
                Distribution::Normal => loop {
                    // Box-Muller, rejected beyond 2 sigma
                    let (u, v): (f64, f64) = (rng.random(), rng.random());
                    let g = (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos();
                    if g.abs() <= 2.0 {
                        break g * t.plus_minus / 2.0;
                    }
                },
            })
            .collect()
    }

    /// The lens with `values` (one per tolerance) applied.
    pub fn perturbed(&self, values: &[f64]) -> PrescriptionSpec {
        let mut s = self.nominal.clone();
        for (t, &v) in self.tolerances.iter().zip(values) {
            t.apply(&mut s, v);
        }
        s
    }

    /// The criterion of the lens with `values` applied, or why it failed.
    pub fn judge(&self, values: &[f64]) -> Result<f64, String> {
        match self.criterion.judge(&self.perturbed(values)) {
            Ok((v, _)) => Ok(v),
            Err(DesignError::Invalid { findings, .. }) => Err(format!(
                "invalid: {}",
                findings
                    .iter()
                    .find(|f| f.severity == crate::model::Severity::Error)
                    .map_or(String::new(), |f| f.to_string())
            )),
            Err(e) => Err(format!("unmeasured: {e}")),
        }
    }

    /// The nominal criterion.
    pub fn nominal_value(&self) -> Result<f64, String> {
        self.judge(&vec![0.0; self.tolerances.len()])
    }

    /// Each tolerance at + and - its size alone.
    pub fn sensitivity(&self) -> Result<Vec<Sensitivity>, String> {
        let nominal = self.nominal_value()?;
        let sign = if self.criterion.lower_is_better() { 1.0 } else { -1.0 };
        Ok((0..self.tolerances.len())
            .into_par_iter()
            .map(|i| {
                let t = &self.tolerances[i];
                let at = |v: f64| {
                    let mut values = vec![0.0; self.tolerances.len()];
                    values[i] = v;
                    self.judge(&values).ok()
                };
                let (plus, minus) = (at(t.plus_minus), at(-t.plus_minus));
                let change = match (plus, minus) {
                    (Some(p), Some(m)) => Some((sign * (p - nominal)).max(sign * (m - nominal))),
                    (Some(p), None) | (None, Some(p)) => Some(sign * (p - nominal)),
                    (None, None) => None,
                };
                Sensitivity { tolerance: t.label(), plus_minus: t.plus_minus, plus, minus, change }
            })
            .collect())
    }

    /// Runs share `shard` = [i, n] (1-based) of `trials` trials of `seed`:
    /// the trials k with k mod n = i - 1, in parallel.
    pub fn run(&self, seed: u64, trials: u64, shard: [u64; 2]) -> Result<Share, String> {
        let [i, n] = shard;
        if n == 0 || i == 0 || i > n {
            return Err(format!("share {i}/{n}: give I/N with 1 <= I <= N"));
        }
        if trials == 0 || trials > MAX_TRIALS {
            return Err(format!(
                "{trials} trials: give 1 to {MAX_TRIALS} (a run's results are held in memory; split a larger study into runs of other seeds)"
            ));
        }
        let nominal = self.nominal_value()?;
        let sensitivity = self.sensitivity()?;
        let ks: Vec<u64> = (i - 1..trials).step_by(n as usize).collect();
        let results = ks
            .into_par_iter()
            .map(|k| match self.judge(&self.draw(seed, k)) {
                Ok(v) => TrialResult { trial: k, value: Some(v), failure: None },
                Err(why) => TrialResult { trial: k, value: None, failure: Some(why) },
            })
            .collect();
        Ok(Share { digest: self.digest.clone(), seed, trials, shard, nominal, sensitivity, results })
    }

    /// The statistics of every trial, from shares that together hold each
    /// trial once.
    pub fn statistics(&self, shares: &[Share]) -> Result<Statistics, String> {
        let all = merge(shares)?;
        let lower = self.criterion.lower_is_better();
        let mut judged: Vec<(u64, f64)> = all.results.iter().filter_map(|r| r.value.map(|v| (r.trial, v))).collect();
        let count = |prefix: &str| {
            all.results.iter().filter(|r| r.failure.as_deref().is_some_and(|f| f.starts_with(prefix))).count() as u64
        };
        let mut failures = Vec::new();
        for prefix in ["invalid", "unmeasured"] {
            if let Some(r) = all.results.iter().find(|r| r.failure.as_deref().is_some_and(|f| f.starts_with(prefix))) {
                failures.push(format!("trial {}: {}", r.trial, r.failure.clone().unwrap_or_default()));
            }
        }
        if judged.is_empty() {
            return Err(format!(
                "none of the {} trials could be judged ({}): reduce the tolerances",
                all.trials,
                failures.join("; ")
            ));
        }
        let n = judged.len() as f64;
        let mean = judged.iter().map(|j| j.1).sum::<f64>() / n;
        let std = (judged.iter().map(|j| (j.1 - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
        let mut sorted: Vec<f64> = judged.iter().map(|j| j.1).collect();
        sorted.sort_by(f64::total_cmp);
        let pct = |p: f64| {
            if sorted.is_empty() {
                return f64::NAN;
            }
            let x = p / 100.0 * (sorted.len() - 1) as f64;
            let (lo, hi) = (x.floor() as usize, x.ceil() as usize);
            sorted[lo] + (sorted[hi] - sorted[lo]) * (x - lo as f64)
        };
        let percentiles = Percentiles { p10: pct(10.0), p50: pct(50.0), p90: pct(90.0), p98: pct(98.0) };
        let yield_fraction = self.threshold.map(|th| {
            judged.iter().filter(|j| if lower { j.1 <= th } else { j.1 >= th }).count() as f64 / all.trials as f64
        });
        judged.sort_by(|a, b| if lower { b.1.total_cmp(&a.1) } else { a.1.total_cmp(&b.1) }.then(a.0.cmp(&b.0)));
        let worst =
            judged.iter().take(5).map(|&(k, v)| Worst { trial: k, value: v, drawn: self.draw(all.seed, k) }).collect();
        Ok(Statistics {
            trials: all.trials,
            judged: judged.len() as u64,
            invalid: count("invalid"),
            unmeasured: count("unmeasured"),
            mean,
            std,
            percentiles,
            threshold: self.threshold,
            yield_fraction,
            worst,
            failures,
        })
    }
}

/// Joins shares of one analysis into one holding every trial once, in
/// order; refuses shares of different analyses, seeds or trial counts, a
/// trial twice, or a trial missing.
pub fn merge(shares: &[Share]) -> Result<Share, String> {
    let first = shares.first().ok_or("no shares to merge")?;
    for (i, s) in shares.iter().enumerate() {
        if s.digest != first.digest {
            return Err(format!(
                "share {} is of another analysis (digest {}, the first's {}): merge the shares of one tolerance file",
                i + 1,
                s.digest,
                first.digest
            ));
        }
        if s.seed != first.seed || s.trials != first.trials {
            return Err(format!(
                "share {} has seed {} and {} trials, the first seed {} and {} trials: merge the shares of one run",
                i + 1,
                s.seed,
                s.trials,
                first.seed,
                first.trials
            ));
        }
    }
    let mut results: Vec<TrialResult> = shares.iter().flat_map(|s| s.results.iter().cloned()).collect();
    results.sort_by_key(|r| r.trial);
    for (k, r) in results.iter().enumerate() {
        if r.trial != k as u64 {
            return Err(if r.trial < k as u64 {
                format!("trial {} is in two shares: give each share once", r.trial)
            } else {
                format!("trial {k} is in no share: give every share of the run (1/N to N/N)")
            });
        }
    }
    if results.len() as u64 != first.trials {
        return Err(format!(
            "the shares hold {} of the {} trials: give every share of the run (1/N to N/N)",
            results.len(),
            first.trials
        ));
    }
    Ok(Share { results, shard: [1, 1], ..first.clone() })
}

/// FNV-1a, 64 bits: a digest of a text (not for security).
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}
