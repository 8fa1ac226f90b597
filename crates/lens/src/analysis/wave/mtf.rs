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

/// The OTF at each (direction, normalised shift) of `all` but the first
/// (the zero shift, the pupil's own integral) and the same pupil's MTF without
/// aberration, with `n` chords across each overlap (over its span across,
/// `spans`) and `n` nodes along each chord's passing part.
///
/// The overlap of the unit disk with its shifted copy is cut into chords
/// along the shift (b = c sin(phi) at Gauss-Legendre nodes in phi); on
/// each chord the part where both ends' rays pass is found (samples along
/// it, then bisection of every change between passing and blocked), and
/// integrated by Gauss-Legendre over exactly that part: vignetting's edges
/// do not cut through the nodes, so the integral converges as fast as the
/// wavefront is smooth along the chords.
fn transfer(
    probe: &Probe,
    all: &[(Direction, f64)],
    spans: &[(f64, f64)],
    n: usize,
) -> Result<(Vec<Complex<f64>>, Vec<f64>), OpticsError> {
    let (phis, wphi) = gauss_legendre(n, -FRAC_PI_2, FRAC_PI_2);
    let mut chords = Vec::with_capacity(all.len() * n);
    for (k, &(d, s)) in all.iter().enumerate() {
        // b = m + r sin(phi) over the span where any ray pair passes (the
        // substitution takes the square-root ends of a rounded region)
        let (lo, hi) = spans[k];
        let (m, r) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        if r <= 0.0 {
            continue;
        }
        for (phi, w) in phis.iter().zip(&wphi) {
            let b = m + r * phi.sin();
            let half = ((1.0 - b * b).max(0.0).sqrt() - 0.5 * s).max(0.0);
            chords.push(Chord { shift: k, direction: d, s, b, half, weight: w * r * phi.cos(), parts: Vec::new() });
        }
    }
    find_parts(probe, &mut chords)?;
    // the nodes along every chord's passing parts, traced together
    let (taus, wtau) = gauss_legendre(n, -1.0, 1.0);
    let mut points = Vec::new();
    let mut weights = Vec::new();
    let mut owner = Vec::new();
    for ch in &chords {
        for &(lo, hi) in &ch.parts {
            let (mid, len) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            for (t, w) in taus.iter().zip(&wtau) {
                let (p, q) = ch.ends(mid + len * t);
                points.push(p);
                points.push(q);
                weights.push(ch.weight * len * w);
                owner.push(ch.shift);
            }
        }
    }
    let opd = probe.opd(&points)?;
    let mut sums = vec![Complex::new(0.0, 0.0); all.len()];
    let mut areas = vec![0.0; all.len()];
    for (i, &k) in owner.iter().enumerate() {
        // a node of a passing part whose ray is blocked after all (an
        // island smaller than the samples' spacing): left out
        if let (Some(w1), Some(w2)) = (opd[2 * i], opd[2 * i + 1]) {
            sums[k] += Complex::from_polar(weights[i], TAU * (w1 - w2));
            areas[k] += weights[i];
        }
    }
    let pupil = areas[0];
    if pupil <= 0.0 {
        return Err(OpticsError::NoRealRays {
            why: format!("every ray of the pupil is vignetted at {}", probe.field().describe()),
        });
    }
    let values = sums[1..].iter().map(|v| v / pupil).collect();
    let limits = areas[1..].iter().map(|a| a / pupil).collect();
    Ok((values, limits))
}

/// Samples along a chord when looking for its passing parts.
const CHORD_SAMPLES: usize = 24;

/// Bisections of each change between passing and blocked along a chord.
const BISECTIONS: usize = 26;

/// One chord of an overlap: at b across the shift, a from -half to +half
/// along it.
struct Chord {
    shift: usize,
    direction: Direction,
    s: f64,
    b: f64,
    half: f64,
    /// The quadrature weight across the chords (with the substitution's
    /// Jacobian).
    weight: f64,
    /// Where both ends' rays pass: (a0, a1) intervals, in order.
    parts: Vec<(f64, f64)>,
}

impl Chord {
    /// The two pupil points of the node at `a` along the chord: x + s/2 and
    /// x - s/2 along the shift.
    fn ends(&self, a: f64) -> ((f64, f64), (f64, f64)) {
        let h = 0.5 * self.s;
        match self.direction {
            Direction::Tangential => ((self.b, a + h), (self.b, a - h)),
            Direction::Sagittal => ((a + h, self.b), (a - h, self.b)),
        }
    }

    /// The chord's k-th sample of [`CHORD_SAMPLES`], from end to end.
    fn sample(&self, k: usize) -> f64 {
        self.half * (-1.0 + 2.0 * k as f64 / (CHORD_SAMPLES - 1) as f64)
    }
}

/// Chords across the overlap sampled when looking for its span across the
/// shift.
const SPAN_SAMPLES: usize = 33;

/// For each (direction, shift): the span of b (across the shift) over
/// which some pair of rays x +- s/2 passes: chords sampled across the
/// overlap, then the first and last passing ones' edges bisected (a span
/// reaching the overlap's own edge, +-sqrt(1 - s^2/4), ends there).
fn across(probe: &Probe, all: &[(Direction, f64)]) -> Result<Vec<(f64, f64)>, OpticsError> {
    let chord = |k: usize, b: f64| {
        let (d, s) = all[k];
        let half = ((1.0 - b * b).max(0.0).sqrt() - 0.5 * s).max(0.0);
        Chord { shift: k, direction: d, s, b, half, weight: 0.0, parts: Vec::new() }
    };
    let limit = |k: usize| (1.0 - 0.25 * all[k].1 * all[k].1).max(0.0).sqrt();
    // whether any sample pair along each chord passes, for a list of chords
    let any_pass = |chords: &[Chord]| -> Result<Vec<bool>, OpticsError> {
        let mut points = Vec::with_capacity(chords.len() * CHORD_SAMPLES * 2);
        for ch in chords {
            for j in 0..CHORD_SAMPLES {
                let (p, q) = ch.ends(ch.sample(j));
                points.push(p);
                points.push(q);
            }
        }
        let opd = probe.opd(&points)?;
        Ok((0..chords.len())
            .map(|c| {
                (0..CHORD_SAMPLES).any(|j| {
                    opd[2 * (c * CHORD_SAMPLES + j)].is_some() && opd[2 * (c * CHORD_SAMPLES + j) + 1].is_some()
                })
            })
            .collect())
    };
    let grid = |k: usize, i: usize| limit(k) * (-1.0 + 2.0 * i as f64 / (SPAN_SAMPLES - 1) as f64);
    let sampled: Vec<Chord> = (0..all.len())
        .flat_map(|k| (0..SPAN_SAMPLES).map(move |i| (k, i)))
        .map(|(k, i)| chord(k, grid(k, i)))
        .collect();
    let passes = any_pass(&sampled)?;
    // per shift: the bracket of each end (passing b, blocked b), or the
    // overlap's edge where the outermost sample passes
    let mut ends: Vec<[Option<(f64, f64)>; 2]> = Vec::with_capacity(all.len());
    let mut spans: Vec<(f64, f64)> = Vec::with_capacity(all.len());
    for k in 0..all.len() {
        let v = &passes[k * SPAN_SAMPLES..(k + 1) * SPAN_SAMPLES];
        let (Some(first), Some(last)) = (v.iter().position(|p| *p), v.iter().rposition(|p| *p)) else {
            spans.push((0.0, 0.0));
            ends.push([None, None]);
            continue;
        };
        let low = (first > 0).then(|| (grid(k, first), grid(k, first - 1)));
        let high = (last + 1 < SPAN_SAMPLES).then(|| (grid(k, last), grid(k, last + 1)));
        spans.push((
            if first == 0 { -limit(k) } else { grid(k, first) },
            if last + 1 == SPAN_SAMPLES { limit(k) } else { grid(k, last) },
        ));
        ends.push([low, high]);
    }
    for _ in 0..BISECTIONS {
        let open: Vec<(usize, usize)> =
            (0..all.len()).flat_map(|k| (0..2).map(move |e| (k, e))).filter(|&(k, e)| ends[k][e].is_some()).collect();
        if open.is_empty() {
            break;
        }
        let probes: Vec<Chord> = open
            .iter()
            .map(|&(k, e)| {
                let (a, b) = ends[k][e].unwrap_or((0.0, 0.0));
                chord(k, 0.5 * (a + b))
            })
            .collect();
        let verdict = any_pass(&probes)?;
        for (i, &(k, e)) in open.iter().enumerate() {
            if let Some((a, b)) = ends[k][e].as_mut() {
                let m = 0.5 * (*a + *b);
                if verdict[i] {
                    *a = m;
                } else {
                    *b = m;
                }
            }
        }
    }
    for k in 0..all.len() {
        if let Some((a, _)) = ends[k][0] {
            spans[k].0 = a;
        }
        if let Some((a, _)) = ends[k][1] {
            spans[k].1 = a;
        }
    }
    Ok(spans)
}

/// Finds every chord's passing parts: samples along each, then the changes
/// between passing and blocked bisected, all chords' rays traced together
/// each round. A chord whose samples all pass is passing end to end.
fn find_parts(probe: &Probe, chords: &mut [Chord]) -> Result<(), OpticsError> {
    let pass = |opd: &[Option<f64>], i: usize| opd[2 * i].is_some() && opd[2 * i + 1].is_some();
    let mut points = Vec::with_capacity(chords.len() * CHORD_SAMPLES * 2);
    for ch in chords.iter() {
        for k in 0..CHORD_SAMPLES {
            let (p, q) = ch.ends(ch.sample(k));
            points.push(p);
            points.push(q);
        }
    }
    let opd = probe.opd(&points)?;
    // per chord: the samples' verdicts, and the changes to bisect as
    // (chord, passing a, blocked a)
    let mut edges: Vec<(usize, f64, f64)> = Vec::new();
    let mut verdicts: Vec<Vec<bool>> = Vec::with_capacity(chords.len());
    for (c, ch) in chords.iter().enumerate() {
        let v: Vec<bool> = (0..CHORD_SAMPLES).map(|k| pass(&opd, c * CHORD_SAMPLES + k)).collect();
        for k in 0..CHORD_SAMPLES - 1 {
            if v[k] != v[k + 1] {
                let (a, b) = (ch.sample(k), ch.sample(k + 1));
                edges.push(if v[k] { (c, a, b) } else { (c, b, a) });
            }
        }
        verdicts.push(v);
    }
    for _ in 0..BISECTIONS {
        if edges.is_empty() {
            break;
        }
        let mut points = Vec::with_capacity(edges.len() * 2);
        for &(c, a, b) in &edges {
            let (p, q) = chords[c].ends(0.5 * (a + b));
            points.push(p);
            points.push(q);
        }
        let opd = probe.opd(&points)?;
        for (i, e) in edges.iter_mut().enumerate() {
            let m = 0.5 * (e.1 + e.2);
            if pass(&opd, i) {
                e.1 = m;
            } else {
                e.2 = m;
            }
        }
    }
    // the parts: runs of passing samples, widened to their bisected edges
    // (or the chord's ends)
    let mut by_chord: Vec<Vec<f64>> = vec![Vec::new(); chords.len()];
    for &(c, a, _) in &edges {
        by_chord[c].push(a);
    }
    for (c, ch) in chords.iter_mut().enumerate() {
        let v = &verdicts[c];
        // in order along the chord already (edges were found so)
        let bounds = std::mem::take(&mut by_chord[c]);
        // walk the samples: a part opens at the chord's start or at an
        // edge where blocked turns passing, and closes likewise
        let mut parts = Vec::new();
        let mut open = if v[0] { Some(-ch.half) } else { None };
        let mut next = bounds.into_iter();
        for k in 0..CHORD_SAMPLES - 1 {
            if v[k] != v[k + 1] {
                let at = next.next().unwrap_or(ch.sample(k));
                match open.take() {
                    Some(start) => parts.push((start, at)),
                    None => open = Some(at),
                }
            }
        }
        if let Some(start) = open {
            parts.push((start, ch.half));
        }
        ch.parts = parts.into_iter().filter(|(a, b)| b > a).collect();
    }
    Ok(())
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
