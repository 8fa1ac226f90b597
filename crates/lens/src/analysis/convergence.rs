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
    /// The estimate, in the statistic's unit.
    pub estimate: f64,
    /// |estimate - reference|, in the statistic's unit.
    pub error: f64,
}

/// A statistic's convergence table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Convergence {
    /// What is estimated.
    pub statistic: String,
    /// Its unit ("mm", "waves", or "" for a ratio).
    pub unit: String,
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
        unit: "mm".into(),
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
        unit: "mm".into(),
        statistic: format!("RMS blur diameter of an object at {s2} mm, focused at {s1} mm"),
        reference,
        reference_method: "Gauss-Legendre, 512 rings".into(),
        rows,
    })
}

/// The wave statistics at `field` on the prescription's image surface
/// against the pupil grid's width (16 to 512 samples across), each against
/// the 1024 grid: RMS to chief (waves), the Strehl ratio, and the Standard
/// Zernike defocus term Z4 (waves). A grid too coarse for the wavefront
/// (more than half a wave between samples) is left out, as the analyses
/// refuse it.
pub fn wave_statistics(p: &Prescription, field: Field) -> Result<Vec<Convergence>, OpticsError> {
    use super::wave::{stats, wavefront, zernike};
    let launcher = super::Launcher::new(p, field, Aim::Paraxial)?;
    let run = |n: usize| -> Result<Option<(usize, f64, [f64; 3])>, OpticsError> {
        let t = Instant::now();
        let w = match wavefront(p, p, &launcher, n, ImagePlane::ImageSurface) {
            Ok(w) => w,
            Err(OpticsError::PupilUndersampled { .. }) => return Ok(None),
            Err(e) => return Err(e),
        };
        let s = stats(&w);
        let z4 =
            zernike::fit(&w, zernike::ZernikeKind::Standard, zernike::TERMS).map_or(f64::NAN, |f| f.coefficients[3]);
        Ok(Some((w.opd_waves.len(), t.elapsed().as_secs_f64(), [s.rms_to_chief, s.strehl, z4])))
    };
    let (_, _, reference) = run(1024)?.ok_or(OpticsError::BadInput {
        name: "pupil grid",
        value: 1024.0,
        expected: "a wavefront that 1024 samples across resolve (within half a wave between neighbours)",
    })?;
    let mut rows: [Vec<ConvergenceRow>; 3] = Default::default();
    for n in [16, 32, 64, 128, 256, 512] {
        let Some((rays, seconds, estimate)) = run(n)? else { continue };
        let default = if n == super::wave::DEFAULT_GRID { " (the default)" } else { "" };
        for k in 0..3 {
            rows[k].push(ConvergenceRow {
                method: format!("grid {n}{default}"),
                rays,
                seconds,
                estimate: estimate[k],
                error: (estimate[k] - reference[k]).abs(),
            });
        }
    }
    let [rms, strehl, z4] = rows;
    let named = |name: &str, unit: &str, k: usize, rows: Vec<ConvergenceRow>| Convergence {
        statistic: format!("{name} at {}, image surface", field.describe()),
        unit: unit.into(),
        reference: reference[k],
        reference_method: "the 1024 x 1024 pupil grid".into(),
        rows,
    };
    Ok(vec![
        named("RMS wavefront error (to chief)", "waves", 0, rms),
        named("Strehl ratio", "", 1, strehl),
        named("Standard Zernike Z4 (defocus)", "waves", 2, z4),
    ])
}
