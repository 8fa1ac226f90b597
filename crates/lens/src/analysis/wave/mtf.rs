//! The diffraction MTF: the modulus of the optical transfer function, the
//! autocorrelation of the pupil function P = A exp(2 pi i W) normalised to
//! 1 at zero frequency, evaluated **at each frequency asked**, not at the
//! nearest bin of an FFT.
//!
//! A frequency nu (cycles/mm on the image plane) along a direction shifts
//! the pupil by s = 2 nu / nu_c in normalised pupil units, nu_c the
//! cutoff of that direction: n' |m(+1) - m(-1)| / lambda from the image-
//! space direction cosines of the real rays through the pupil's rim along
//! it (tangential: along the field's meridional direction, y; sagittal:
//! across it, x), traced with every aperture open. The overlap of the pupil
//! with its shifted copy is a lens-shaped region of the unit disk,
//! integrated by Gauss-Legendre quadrature in coordinates that follow it
//! (across the shift b = c sin(phi), c = sqrt(1 - s^2/4); along it, between
//! the two circles), with the rays traced at each node's two ends, x +- s/2:
//! exact for an aberration-free unvignetted pupil, fast for smooth
//! wavefronts, and refined (nodes doubled) until no value moves by more
//! than [`TOLERANCE`] where vignetting cuts the pupil.

use super::opd::Probe;
use crate::analysis::bundle;
use crate::analysis::fan::ImagePlane;
use crate::analysis::quadrature::gauss_legendre;
use crate::analysis::{Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::trace::{RayBatch, Tracer};
use nalgebra::Complex;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// How far refinement lets a value move before it stops.
pub const TOLERANCE: f64 = 1e-4;

/// Quadrature nodes per axis at the start, and the most refinement goes to.
const FIRST_NODES: usize = 24;
const MOST_NODES: usize = 384;

/// The MTF of one field at one wavelength.
#[derive(Debug, Clone, PartialEq)]
pub struct Mtf {
    /// The field.
    pub field: Field,
    /// The wavelength, nm.
    pub wavelength_nm: f64,
    /// z of the image plane, mm from the first vertex.
    pub image_z: f64,
    /// The frequencies asked, cycles/mm.
    pub frequencies_per_mm: Vec<f64>,
    /// The MTF along the meridional direction (y) at each frequency.
    pub tangential: Vec<f64>,
    /// The MTF across it (x) at each frequency.
    pub sagittal: Vec<f64>,
    /// The same pupil's MTF without aberration (W = 0), tangential.
    pub diffraction_limit_tangential: Vec<f64>,
    /// The same, sagittal.
    pub diffraction_limit_sagittal: Vec<f64>,
    /// The tangential cutoff, cycles/mm.
    pub cutoff_tangential_per_mm: f64,
    /// The sagittal cutoff, cycles/mm.
    pub cutoff_sagittal_per_mm: f64,
    /// Quadrature nodes per axis where the values settled.
    pub nodes: usize,
}

/// The direction of a frequency in the image plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Along the field's meridional direction (y).
    Tangential,
    /// Across it (x).
    Sagittal,
}

/// The image-space cutoffs (tangential, sagittal), cycles/mm, of
/// `launcher`'s field through `traced` to the plane `image_z` (mm from the
/// first vertex): from the real rays through the pupil's rim at (0, +-1)
/// and (+-1, 0), every aperture open.
pub fn cutoffs(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    image_z: f64,
) -> Result<(f64, f64), OpticsError> {
    let tracer = Tracer::forward_to_film_open(traced, image_z - traced.last_vertex_z());
    let vig = p.vignetting_at(launcher.field_angle_deg());
    let rim = [(0.0, 1.0), (0.0, -1.0), (1.0, 0.0), (-1.0, 0.0)].map(|(x, y)| vig.apply(x, y));
    let mut batch = RayBatch::with_capacity(4);
    bundle::launch(launcher, rim.into_iter(), &mut batch)?;
    tracer.trace_soa(&mut batch);
    if batch.status.iter().any(|s| *s != 0) {
        return Err(OpticsError::NoRealRays {
            why: format!(
                "a ray through the rim of the pupil at {} does not reach the image even with every aperture open, so the MTF's cutoff cannot be found",
                launcher.field().describe()
            ),
        });
    }
    let scale = traced.image_index() / (traced.wavelength_nm() * 1e-6);
    let t = (batch.dy[0] - batch.dy[1]).abs() * scale;
    let s = (batch.dx[2] - batch.dx[3]).abs() * scale;
    Ok((t, s))
}

/// The MTF of `launcher`'s field at `frequencies` (cycles/mm, each above 0
/// and below the field's cutoffs), traced through `traced` to `plane` (see
/// [`Probe::new`]).
pub fn mtf(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
    frequencies: &[f64],
) -> Result<Mtf, OpticsError> {
    let probe = Probe::new(p, traced, launcher, plane)?;
    let (ct, cs) = cutoffs(p, traced, launcher, probe.image_z)?;
    for &f in frequencies {
        if !(f.is_finite() && f > 0.0) {
            return Err(OpticsError::BadInput {
                name: "MTF frequency (cycles/mm)",
                value: f,
                expected: "a frequency above 0",
            });
        }
        if f >= ct.min(cs) {
            return Err(OpticsError::BadInput {
                name: "MTF frequency (cycles/mm)",
                value: f,
                expected: "a frequency below the field's cutoff (see cutoff_tangential_per_mm and cutoff_sagittal_per_mm: the MTF is 0 beyond it)",
            });
        }
    }
    // every (direction, normalised shift) asked, the shifts of both
    let shifts: Vec<(Direction, f64)> = frequencies
        .iter()
        .flat_map(|&f| [(Direction::Tangential, 2.0 * f / ct), (Direction::Sagittal, 2.0 * f / cs)])
        .collect();
    let mut nodes = FIRST_NODES;
    let mut last = transfer(&probe, &shifts, nodes)?;
    loop {
        if nodes * 2 > MOST_NODES {
            break;
        }
        let next = transfer(&probe, &shifts, nodes * 2)?;
        let moved = last.0.iter().zip(&next.0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        nodes *= 2;
        last = next;
        if moved < TOLERANCE {
            break;
        }
    }
    let (values, limits) = last;
    let pick = |v: &[f64], d: usize| v.iter().skip(d).step_by(2).copied().collect::<Vec<f64>>();
    Ok(Mtf {
        field: launcher.field(),
        wavelength_nm: traced.wavelength_nm(),
        image_z: probe.image_z,
        frequencies_per_mm: frequencies.to_vec(),
        tangential: pick(&values, 0),
        sagittal: pick(&values, 1),
        diffraction_limit_tangential: pick(&limits, 0),
        diffraction_limit_sagittal: pick(&limits, 1),
        cutoff_tangential_per_mm: ct,
        cutoff_sagittal_per_mm: cs,
        nodes,
    })
}

/// The MTF at each (direction, normalised shift) and the same pupil's
/// without aberration, with `n` x `n` quadrature nodes over each overlap.
fn transfer(probe: &Probe, shifts: &[(Direction, f64)], n: usize) -> Result<(Vec<f64>, Vec<f64>), OpticsError> {
    // the pupil's own integral (the zero shift) first, then each shift's
    // node pairs, all traced together
    let mut points = Vec::new();
    let mut weights = Vec::new();
    let mut spans = Vec::new();
    for (d, s) in std::iter::once((Direction::Tangential, 0.0)).chain(shifts.iter().copied()) {
        let start = weights.len();
        for (a, b, w) in overlap_nodes(s, n) {
            let (x, y) = match d {
                Direction::Tangential => (b, a),
                Direction::Sagittal => (a, b),
            };
            let (hx, hy) = match d {
                Direction::Tangential => (0.0, 0.5 * s),
                Direction::Sagittal => (0.5 * s, 0.0),
            };
            points.push((x + hx, y + hy));
            points.push((x - hx, y - hy));
            weights.push(w);
        }
        spans.push(start..weights.len());
    }
    let at = probe.at(&points)?;
    let sum = |k: usize, aberrated: bool| -> Complex<f64> {
        spans[k]
            .clone()
            .map(|i| match (at[2 * i], at[2 * i + 1]) {
                (Some((w1, _)), Some((w2, _))) => {
                    let phase = if aberrated { TAU * (w1 - w2) } else { 0.0 };
                    Complex::from_polar(weights[i], phase)
                }
                _ => Complex::new(0.0, 0.0),
            })
            .sum()
    };
    let pupil = sum(0, false).re;
    if pupil <= 0.0 {
        return Err(OpticsError::NoRealRays {
            why: format!("every ray of the pupil is vignetted at {}", probe.field().describe()),
        });
    }
    let values = (1..spans.len()).map(|k| sum(k, true).norm() / pupil).collect();
    let limits = (1..spans.len()).map(|k| sum(k, false).norm() / pupil).collect();
    Ok((values, limits))
}

/// Gauss-Legendre nodes (along the shift a, across it b, weight) over the
/// overlap of the unit disk with its copy shifted by `s` (0 <= s < 2)
/// along a: b = c sin(phi), c = sqrt(1 - s^2/4); a between the circles,
/// |a| <= sqrt(1 - b^2) - s/2.
pub fn overlap_nodes(s: f64, n: usize) -> Vec<(f64, f64, f64)> {
    let c = (1.0 - 0.25 * s * s).max(0.0).sqrt();
    let (phis, wphi) = gauss_legendre(n, -FRAC_PI_2, FRAC_PI_2);
    let (taus, wtau) = gauss_legendre(n, -1.0, 1.0);
    let mut out = Vec::with_capacity(n * n);
    for (phi, wp) in phis.iter().zip(&wphi) {
        let b = c * phi.sin();
        let half = ((1.0 - b * b).max(0.0).sqrt() - 0.5 * s).max(0.0);
        let jacobian = c * phi.cos() * half;
        for (tau, wt) in taus.iter().zip(&wtau) {
            out.push((half * tau, b, wp * wt * jacobian));
        }
    }
    out
}

/// The MTF of an aberration-free circular pupil at `x` = nu / nu_c:
/// (2 / pi) (acos x - x sqrt(1 - x^2)), 0 beyond the cutoff.
pub fn diffraction_limited(x: f64) -> f64 {
    if x >= 1.0 {
        return 0.0;
    }
    let x = x.max(0.0);
    (2.0 / PI) * (x.acos() - x * (1.0 - x * x).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overlap_nodes_integrate_the_lens_shaped_area() {
        // the integrand's corner near the ends of b (width s / 2) slows
        // the convergence at small shifts: 2e-8 of the area at 24 nodes
        for s in [0.0, 0.001, 0.01, 0.3, 1.0, 1.7, 1.99] {
            let area: f64 = overlap_nodes(s, 24).iter().map(|n| n.2).sum();
            let want = PI * diffraction_limited(0.5 * s);
            println!("s {s}: {area:.15} against {want:.15} ({:.1e})", (area - want) / want);
            assert!((area - want).abs() < 1e-7 * want, "s {s}");
        }
    }
}
