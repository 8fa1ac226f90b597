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

use super::autocorrelation::{across, transfer};
use super::opd::Probe;
use crate::analysis::bundle;
use crate::analysis::fan::ImagePlane;
use crate::analysis::{Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::trace::{RayBatch, Tracer};
use nalgebra::Complex;
use std::f64::consts::{PI, TAU};

/// How far a value may move when the nodes double for refinement to stop
/// (the finer value is kept: its own error is then about a tenth of that,
/// the convergence being fast; docs/analyses.md).
pub const TOLERANCE: f64 = 1e-3;

/// Quadrature nodes per axis at the start, and the most refinement goes to.
const FIRST_NODES: usize = 16;
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
    let vig = launcher.vignetting(p)?;
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
    let o = otf(p, traced, launcher, plane, frequencies, true)?;
    let norms = |v: &[Complex<f64>]| v.iter().map(|c| c.norm()).collect::<Vec<f64>>();
    Ok(Mtf {
        field: launcher.field(),
        wavelength_nm: traced.wavelength_nm(),
        image_z: o.image_z,
        frequencies_per_mm: frequencies.to_vec(),
        tangential: norms(&o.tangential),
        sagittal: norms(&o.sagittal),
        diffraction_limit_tangential: o.limit_tangential,
        diffraction_limit_sagittal: o.limit_sagittal,
        cutoff_tangential_per_mm: o.cutoffs.0,
        cutoff_sagittal_per_mm: o.cutoffs.1,
        nodes: o.nodes,
    })
}

/// The polychromatic MTF of `launcher`'s field: each of `wavelengths`
/// ((nm, weight) pairs) traced through `p` at that wavelength to the
/// primary's `plane`, its OTF moved to the primary wavelength's chief-ray
/// image point (times exp(-2 pi i nu d), d its own chief point's offset
/// along the direction: lateral colour lowers the sum) and the OTFs summed
/// with the weights over their sum; a wavelength contributes nothing beyond
/// its own cutoff. The frequencies must lie above 0 and below the largest
/// cutoff; the cutoffs reported are the largest over the wavelengths, and
/// the diffraction limit the weighted sum of each wavelength's.
pub fn polychromatic_mtf(
    p: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
    frequencies: &[f64],
    wavelengths: &[(f64, f64)],
) -> Result<Mtf, OpticsError> {
    let weight: f64 = wavelengths.iter().map(|w| w.1).sum();
    let bad_weight = |w: f64| w.is_nan() || w < 0.0;
    if wavelengths.is_empty() || !weight.is_finite() || weight <= 0.0 || wavelengths.iter().any(|w| bad_weight(w.1)) {
        return Err(OpticsError::BadInput {
            name: "wavelength weights",
            value: weight,
            expected: "at least one wavelength, weights of 0 or more with a positive sum",
        });
    }
    let primary = Probe::new(p, p, launcher, plane)?.chief_image();
    let mut parts = Vec::with_capacity(wavelengths.len());
    for &(nm, w) in wavelengths {
        let traced = p.at_wavelength(nm)?;
        let o = otf(p, &traced, launcher, plane, frequencies, false)?;
        parts.push((o, w));
    }
    let top = parts.iter().fold((0.0f64, 0.0f64), |m, (o, _)| (m.0.max(o.cutoffs.0), m.1.max(o.cutoffs.1)));
    check_frequencies(frequencies, top.0.min(top.1))?;
    let zero = Complex::new(0.0, 0.0);
    let (mut t, mut s) = (vec![zero; frequencies.len()], vec![zero; frequencies.len()]);
    let (mut lt, mut ls) = (vec![0.0; frequencies.len()], vec![0.0; frequencies.len()]);
    for (o, w) in &parts {
        let d = o.chief - primary;
        for (k, &f) in frequencies.iter().enumerate() {
            t[k] += o.tangential[k] * Complex::from_polar(*w, -TAU * f * d.y);
            s[k] += o.sagittal[k] * Complex::from_polar(*w, -TAU * f * d.x);
            lt[k] += w * o.limit_tangential[k];
            ls[k] += w * o.limit_sagittal[k];
        }
    }
    let image_z = parts.first().map_or(0.0, |(o, _)| o.image_z);
    Ok(Mtf {
        field: launcher.field(),
        wavelength_nm: p.wavelength_nm(),
        image_z,
        frequencies_per_mm: frequencies.to_vec(),
        tangential: t.iter().map(|c| c.norm() / weight).collect(),
        sagittal: s.iter().map(|c| c.norm() / weight).collect(),
        diffraction_limit_tangential: lt.iter().map(|v| v / weight).collect(),
        diffraction_limit_sagittal: ls.iter().map(|v| v / weight).collect(),
        cutoff_tangential_per_mm: top.0,
        cutoff_sagittal_per_mm: top.1,
        nodes: parts.iter().map(|(o, _)| o.nodes).max().unwrap_or(0),
    })
}

/// One wavelength's OTF at a list of frequencies, about its own chief
/// ray's image point.
struct Otf {
    tangential: Vec<Complex<f64>>,
    sagittal: Vec<Complex<f64>>,
    limit_tangential: Vec<f64>,
    limit_sagittal: Vec<f64>,
    cutoffs: (f64, f64),
    nodes: usize,
    image_z: f64,
    chief: glam::DVec3,
}

/// Refuses frequencies not above 0, or (`below`) at or above a cutoff.
fn check_frequencies(frequencies: &[f64], below: f64) -> Result<(), OpticsError> {
    for &f in frequencies {
        if !(f.is_finite() && f > 0.0) {
            return Err(OpticsError::BadInput {
                name: "MTF frequency (cycles/mm)",
                value: f,
                expected: "a frequency above 0",
            });
        }
        if f >= below {
            return Err(OpticsError::BadInput {
                name: "MTF frequency (cycles/mm)",
                value: f,
                expected: "a frequency below the field's cutoff (see cutoff_tangential_per_mm and cutoff_sagittal_per_mm: the MTF is 0 beyond it)",
            });
        }
    }
    Ok(())
}

/// The OTF of `launcher`'s field through `traced` at `frequencies`,
/// refined until no value moves by [`TOLERANCE`]; `strict`: a frequency at
/// or beyond a cutoff is refused, else its value there is 0.
fn otf(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
    frequencies: &[f64],
    strict: bool,
) -> Result<Otf, OpticsError> {
    let probe = Probe::new(p, traced, launcher, plane)?;
    let (ct, cs) = cutoffs(p, traced, launcher, probe.image_z)?;
    check_frequencies(frequencies, if strict { ct.min(cs) } else { f64::INFINITY })?;
    // every (direction, normalised shift) asked that lies inside the
    // pupil's reach (index into the answers), the shifts of both
    let mut asked: Vec<(Direction, f64)> = Vec::new();
    let mut slot: Vec<Option<usize>> = Vec::new();
    for &f in frequencies {
        for (d, c) in [(Direction::Tangential, ct), (Direction::Sagittal, cs)] {
            let s = 2.0 * f / c;
            if s < 2.0 {
                slot.push(Some(asked.len()));
                asked.push((d, s));
            } else {
                slot.push(None);
            }
        }
    }
    // the pupil's own integral (the zero shift) first, then each shift's;
    // their spans across the shift found once for every refinement
    let all: Vec<(Direction, f64)> =
        std::iter::once((Direction::Tangential, 0.0)).chain(asked.iter().copied()).collect();
    let spans = across(&probe, &all)?;
    let mut nodes = FIRST_NODES;
    let mut last = transfer(&probe, &all, &spans, nodes)?;
    loop {
        if nodes * 2 > MOST_NODES {
            break;
        }
        let next = transfer(&probe, &all, &spans, nodes * 2)?;
        let moved = last.0.iter().zip(&next.0).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
        nodes *= 2;
        last = next;
        if moved < TOLERANCE {
            break;
        }
    }
    let (values, limits) = last;
    let zero = Complex::new(0.0, 0.0);
    let pick = |d: usize| slot.iter().skip(d).step_by(2).map(|k| k.map_or(zero, |k| values[k])).collect::<Vec<_>>();
    let pick_limit =
        |d: usize| slot.iter().skip(d).step_by(2).map(|k| k.map_or(0.0, |k| limits[k])).collect::<Vec<_>>();
    Ok(Otf {
        tangential: pick(0),
        sagittal: pick(1),
        limit_tangential: pick_limit(0),
        limit_sagittal: pick_limit(1),
        cutoffs: (ct, cs),
        nodes,
        image_z: probe.image_z,
        chief: probe.chief_image(),
    })
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

/// The geometric MTF of a spot diagram at `frequencies` (cycles/mm): the
/// modulus of the Fourier transform of its ray density, |sum w exp(-2 pi i
/// nu y)| / sum w along y (tangential) and likewise along x (sagittal),
/// with the rays' pupil weights. `None` for a spot without rays.
pub fn geometric_mtf(spot: &crate::analysis::spot::SpotDiagram, frequencies: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let total: f64 = spot.weights.iter().sum();
    if spot.hits.is_empty() || total <= 0.0 {
        return None;
    }
    let along = |axis: usize| -> Vec<f64> {
        frequencies
            .iter()
            .map(|&f| {
                let s: Complex<f64> = spot
                    .hits
                    .iter()
                    .zip(&spot.weights)
                    .map(|(h, w)| Complex::from_polar(*w, -TAU * f * (h[axis] - spot.centroid[axis])))
                    .sum();
                s.norm() / total
            })
            .collect()
    };
    Some((along(1), along(0)))
}
