//! Wavefront statistics: RMS and peak-to-valley to the chief ray and to the
//! centroid, and the Strehl ratio, each an integral over the pupil disk
//! with the grid's area weights ([`super::pupil`]).

use super::opd::Wavefront;
use nalgebra::Complex;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The wavefront's statistics, in waves at its wavelength.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WavefrontStats {
    /// RMS about the mean (piston removed): Zemax's "RMS (to chief)".
    pub rms_to_chief: f64,
    /// Peak to valley of W as referenced to the chief ray.
    pub pv_to_chief: f64,
    /// RMS with piston and tilt removed (a least-squares plane in the
    /// normalised pupil coordinates): Zemax's "RMS (to centroid)".
    pub rms_to_centroid: f64,
    /// Peak to valley with piston and tilt removed.
    pub pv_to_centroid: f64,
    /// The mean of W over the pupil, waves.
    pub piston: f64,
    /// The least-squares tilt of W along px and py, waves per unit of the
    /// normalised pupil.
    pub tilt: (f64, f64),
    /// The Strehl ratio: the PSF's peak (wherever it lies) over the peak of
    /// the same pupil without aberration, in the Fraunhofer approximation
    /// over the normalised pupil: max over tilts (a, b) of
    /// |sum w exp(2 pi i (W - a px - b py))|^2 / (sum w)^2.
    pub strehl: f64,
}

/// The statistics of `w`.
///
/// The Strehl ratio's peak is the PSF's highest anywhere: a coarse image
/// of the pupil function's transform (padded twice) finds the brightest
/// pixel, from which Newton's method refines the tilt off the grid (a badly
/// aberrated image's brightest point need not lie near its least-squares
/// tilt).
pub fn stats(w: &Wavefront) -> WavefrontStats {
    let samples: Vec<((f64, f64), f64, f64)> = w.passing().collect();
    let mut s = stats_of(&samples);
    let start = brightest_tilt(w);
    let refined = strehl(&samples, start);
    if refined > s.strehl {
        s.strehl = refined;
    }
    s
}

/// The tilt (waves per unit of the normalised pupil) whose plane points at
/// the brightest pixel of the pupil function's transform, the grid padded
/// twice: a pixel is half a tilt step of 1 / 2 wave across the pupil.
fn brightest_tilt(w: &Wavefront) -> (f64, f64) {
    let n = w.grid.n;
    let m = 2 * n;
    let mut field = vec![Complex::new(0.0, 0.0); m * m];
    for (c, v) in w.grid.cells.iter().zip(&w.opd_waves) {
        if let Some(v) = v {
            field[c.row * m + c.column] = Complex::from_polar(c.area, TAU * v);
        }
    }
    super::psf::fft2(&mut field, m, rustfft::FftDirection::Forward);
    let best = (0..m * m).max_by(|&a, &b| field[a].norm_sqr().total_cmp(&field[b].norm_sqr())).unwrap_or(0);
    let (ky, kx) = (best / m, best % m);
    let signed = |k: usize| if k >= m / 2 { k as f64 - m as f64 } else { k as f64 };
    // the transform's index k is the tilt k / (m * 2 / n) waves per unit
    let step = n as f64 / (2.0 * m as f64);
    (signed(kx) * step, signed(ky) * step)
}

/// The statistics of samples (normalised pupil point, area weight, W in
/// waves); at least one sample with positive weight.
pub fn stats_of(samples: &[((f64, f64), f64, f64)]) -> WavefrontStats {
    let total: f64 = samples.iter().map(|s| s.1).sum();
    let mean = samples.iter().map(|s| s.1 * s.2).sum::<f64>() / total;
    let rms_to_chief = (samples.iter().map(|s| s.1 * (s.2 - mean).powi(2)).sum::<f64>() / total).sqrt();
    let (lo, hi) = samples.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s.2), hi.max(s.2)));
    // piston and tilt: weighted least squares W ~ c0 + c1 px + c2 py
    let plane = fit_plane(samples);
    let residual = |s: &((f64, f64), f64, f64)| s.2 - plane[0] - plane[1] * s.0 .0 - plane[2] * s.0 .1;
    let rms_to_centroid = (samples.iter().map(|s| s.1 * residual(s).powi(2)).sum::<f64>() / total).sqrt();
    let (rlo, rhi) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(residual(s)), hi.max(residual(s))));
    WavefrontStats {
        rms_to_chief,
        pv_to_chief: hi - lo,
        rms_to_centroid,
        pv_to_centroid: rhi - rlo,
        piston: mean,
        tilt: (plane[1], plane[2]),
        strehl: strehl(samples, (plane[1], plane[2])),
    }
}

/// The weighted least-squares plane c0 + c1 px + c2 py through the samples.
fn fit_plane(samples: &[((f64, f64), f64, f64)]) -> [f64; 3] {
    let mut a = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for &((x, y), wt, v) in samples {
        let r = nalgebra::Vector3::new(1.0, x, y);
        a += r * r.transpose() * wt;
        b += r * (wt * v);
    }
    match a.try_inverse() {
        Some(inv) => {
            let c = inv * b;
            [c[0], c[1], c[2]]
        }
        // too few samples to fix a tilt (a line of them): piston only
        None => [b[0] / a[(0, 0)], 0.0, 0.0],
    }
}

/// The Strehl ratio of the samples: the largest |S(a, b)|^2 / (sum w)^2
/// over tilts, S(a, b) = sum w exp(2 pi i (W - a x - b y)), by Newton's
/// method from the least-squares tilt `start` (damped: every step must
/// raise the peak).
fn strehl(samples: &[((f64, f64), f64, f64)], start: (f64, f64)) -> f64 {
    let total: f64 = samples.iter().map(|s| s.1).sum();
    // |S|^2 and its gradient and Hessian in (a, b)
    let eval = |a: f64, b: f64| {
        let zero = Complex::new(0.0, 0.0);
        let i = Complex::new(0.0, 1.0);
        // S and its derivatives, summed over chunks on all cores
        let [s, sa, sb, saa, sab, sbb] = samples
            .par_chunks(4096)
            .map(|chunk| {
                let mut acc = [zero; 6];
                for &((x, y), wt, w) in chunk {
                    let e = Complex::from_polar(wt, TAU * (w - a * x - b * y));
                    acc[0] += e;
                    // d/da of exp(i phi) is -2 pi i x exp(i phi)
                    acc[1] += e * i * (-TAU * x);
                    acc[2] += e * i * (-TAU * y);
                    acc[3] += e * (-TAU * TAU * x * x);
                    acc[4] += e * (-TAU * TAU * x * y);
                    acc[5] += e * (-TAU * TAU * y * y);
                }
                acc
            })
            .reduce(
                || [zero; 6],
                |mut p, q| {
                    p.iter_mut().zip(q).for_each(|(p, q)| *p += q);
                    p
                },
            );
        // Re(conj(p) q)
        let dot = |p: Complex<f64>, q: Complex<f64>| (p.conj() * q).re;
        let f = s.norm_sqr();
        let g = [2.0 * dot(s, sa), 2.0 * dot(s, sb)];
        let hab = 2.0 * (dot(sa, sb) + dot(s, sab));
        let h = [[2.0 * (sa.norm_sqr() + dot(s, saa)), hab], [hab, 2.0 * (sb.norm_sqr() + dot(s, sbb))]];
        (f, g, h)
    };
    let (mut a, mut b) = start;
    let (mut f, mut g, mut h) = eval(a, b);
    for _ in 0..50 {
        let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
        // Newton where the Hessian is negative definite, else uphill
        let mut d = if h[0][0] < 0.0 && det > 0.0 {
            [-(h[1][1] * g[0] - h[0][1] * g[1]) / det, -(-h[1][0] * g[0] + h[0][0] * g[1]) / det]
        } else {
            let len = (g[0] * g[0] + g[1] * g[1]).sqrt().max(f64::MIN_POSITIVE);
            [0.05 * g[0] / len, 0.05 * g[1] / len]
        };
        let mut moved = false;
        for _ in 0..40 {
            let (f2, g2, h2) = eval(a + d[0], b + d[1]);
            if f2 >= f {
                (a, b, f, g, h) = (a + d[0], b + d[1], f2, g2, h2);
                moved = true;
                break;
            }
            d = [d[0] * 0.5, d[1] * 0.5];
        }
        if !moved || d[0].abs().max(d[1].abs()) < 1e-12 {
            break;
        }
    }
    (f / (total * total)).min(1.0)
}
