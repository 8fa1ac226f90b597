//! How pupil-sampled statistics converge with the number of rays: each
//! estimate beside its run time and its difference from a dense reference.

use super::fan::ImagePlane;
use super::launch::{Aim, Field};
use super::pattern::Pattern;
use super::spot::spot_diagram;
use crate::analysis::focus::AxialBundle;
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::focus::film_distance_with;
use crate::paraxial::FirstOrder;
use crate::paraxial::ObjectDistance;
use serde::Serialize;
use std::time::Instant;

/// One estimate of a statistic.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergenceRow {
    /// The method and its size ("square 33", "Gauss-Legendre 16", ...).
    pub method: String,
    /// Rays traced.
    pub rays: usize,
    /// Wall time, seconds.
    pub seconds: f64,
    /// The estimate, mm.
    pub estimate: f64,
    /// |estimate - reference|, mm.
    pub error: f64,
}

/// A statistic's convergence table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Convergence {
    /// What is estimated.
    pub statistic: String,
    /// The dense reference and how it was obtained.
    pub reference: f64,
    /// How the reference was computed.
    pub reference_method: String,
    /// The estimates.
    pub rows: Vec<ConvergenceRow>,
}

/// RMS spot radius (about the centroid) at `field` on the paraxial image
/// plane, by the four pupil patterns at growing sizes, against 1024
/// Gauss-Legendre rings (4.2 million rays; a 1025 x 1025 square grid is
/// off by 4e-4 on axis, where the rings have converged to 1e-14).
pub fn spot_rms(p: &Prescription, field: Field) -> Result<Convergence, OpticsError> {
    let run = |pattern: Pattern, n: usize| -> Result<(usize, f64, f64), OpticsError> {
        let t = Instant::now();
        let s = spot_diagram(p, field, pattern, n, Aim::Paraxial, ImagePlane::Paraxial)?;
        Ok((s.rays + s.vignetted, t.elapsed().as_secs_f64(), s.rms_radius))
    };
    let (_, _, reference) = run(Pattern::Gauss, 1024)?;
    let mut rows = Vec::new();
    let sizes: [(Pattern, &str, &[usize]); 4] = [
        (Pattern::Gauss, "gauss", &[2, 4, 8, 12, 16, 32, 64]),
        (Pattern::Square, "square", &[5, 9, 17, 33, 65, 129, 257]),
        (Pattern::Hexapolar, "hexapolar", &[2, 4, 8, 16, 32, 64, 128]),
        (Pattern::Random, "random", &[100, 1000, 10_000, 100_000]),
    ];
    for (pattern, name, ns) in sizes {
        for &n in ns {
            let (rays, seconds, estimate) = run(pattern, n)?;
            let default = if pattern == Pattern::default() && n == 12 { " (the default)" } else { "" };
            rows.push(ConvergenceRow {
                method: format!("{name} {n}{default}"),
                rays,
                seconds,
                estimate,
                error: (estimate - reference).abs(),
            });
        }
    }
    Ok(Convergence {
        statistic: format!("RMS spot radius at {}, paraxial image plane", field.describe()),
        reference,
        reference_method: "Gauss-Legendre rings, 1024 rings of 4100 points".into(),
        rows,
    })
}

/// RMS blur diameter of an on-axis object at `s2` mm with the lens focused
/// at `s1` mm, by Gauss–Legendre rings (the method `lens coc` uses), against
/// 512 rings.
pub fn coc_rms(p: &Prescription, s1: f64, s2: f64) -> Result<Convergence, OpticsError> {
    let first = FirstOrder::of(p)?;
    let film = film_distance_with(p, &first, ObjectDistance::from_mm(s1)?)?;
    let object = ObjectDistance::from_mm(s2)?;
    let estimate = |nodes: usize| -> Result<(f64, f64, usize), OpticsError> {
        let t = Instant::now();
        let b = AxialBundle::trace_with(p, &first, object, film, nodes)?;
        Ok((t.elapsed().as_secs_f64(), 2.0 * b.rms_at(0.0), b.rays))
    };
    let (_, reference, _) = estimate(512)?;
    let mut rows = Vec::new();
    for nodes in [2, 4, 8, 16, 32, 48, 96] {
        // rays: one meridional ray per ring, plus the pupil-fill search and
        // the 513-ray fan that measures the geometric diameter
        let (seconds, e, rays) = estimate(nodes)?;
        rows.push(ConvergenceRow {
            method: format!("Gauss-Legendre {nodes}"),
            rays,
            seconds,
            estimate: e,
            error: (e - reference).abs(),
        });
    }
    Ok(Convergence {
        statistic: format!("RMS blur diameter of an object at {s2} mm, focused at {s1} mm"),
        reference,
        reference_method: "Gauss-Legendre, 512 rings".into(),
        rows,
    })
}
