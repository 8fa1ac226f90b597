//! The pupil autocorrelation behind the MTF ([`super::mtf`]): the overlap
//! of the pupil with its copy shifted by s (normalised units, along a
//! direction) integrated by Gauss-Legendre quadrature in coordinates that
//! follow it, with the rays traced at each node's two ends, x +- s/2.
//!
//! The overlap is cut into chords along the shift: across it b = m + r
//! sin(phi) over the span where any pair of rays passes (found by sampling
//! chords and bisecting the first and last passing ones' edges, which also
//! takes the square-root ends of a rounded region); along each chord only
//! the part where both rays pass (samples, then bisection of every change
//! between passing and blocked). Vignetting's edges thus never cut through
//! the nodes: the integral converges as fast as the wavefront is smooth.

use super::mtf::Direction;
use super::opd::Probe;
use crate::analysis::quadrature::gauss_legendre;
use crate::error::OpticsError;
use nalgebra::Complex;
use std::f64::consts::{FRAC_PI_2, TAU};

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
pub(super) fn transfer(
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

/// Bisections of each change between passing and blocked along a chord,
/// and of each end of an overlap's span across the shift: an edge is then
/// placed within 2^-16 of the samples' spacing (below 2e-6 of the pupil's
/// radius), moving the integral by less than 1e-6 of the pupil's area,
/// far inside [`super::mtf::TOLERANCE`].
const BISECTIONS: usize = 16;

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
pub(super) fn across(probe: &Probe, all: &[(Direction, f64)]) -> Result<Vec<(f64, f64)>, OpticsError> {
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
