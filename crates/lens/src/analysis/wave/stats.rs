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
/// tilt); the higher of that and the peak found from the least-squares
/// tilt is kept.
pub fn stats(w: &Wavefront) -> WavefrontStats {
    let samples: Vec<((f64, f64), f64, f64)> = w.passing().collect();
    let pupil = PupilFunction::of(w);
    let mut s = moments(&samples);
    s.strehl = pupil.strehl(s.tilt).max(pupil.strehl(brightest_tilt(w, &pupil)));
    s
}

/// The tilt (waves per unit of the normalised pupil) whose plane points at
/// the brightest pixel of the pupil function's transform, the grid padded
/// twice: a pixel is half a tilt step of 1 / 2 wave across the pupil.
///
/// The transform by rows (only the pupil's n rows: the padding's are
/// zero), then by columns in blocks, each block keeping its brightest
/// pixel: the padded image is never held whole.
fn brightest_tilt(w: &Wavefront, pupil: &PupilFunction) -> (f64, f64) {
    let n = w.grid.n;
    let m = 2 * n;
    let zero = Complex::new(0.0, 0.0);
    let forward = rustfft::FftPlanner::new().plan_fft_forward(m);
    let scratch = || vec![zero; forward.get_inplace_scratch_len()];
    let mut rows = vec![zero; n * m];
    for (row, values) in rows.chunks_mut(m).enumerate() {
        for (column, v) in values[..n].iter_mut().enumerate() {
            *v = pupil.whole(column, row);
        }
    }
    for &((column, row), _, v) in &pupil.rim {
        rows[row * m + column] = v;
    }
    rows.par_chunks_mut(m).for_each_init(scratch, |s, r| forward.process_with_scratch(r, s));
    // (|F|^2, kx, ky) of each block of columns' brightest pixel
    const BLOCK: usize = 8;
    let blocks: Vec<(f64, usize, usize)> = (0..m.div_ceil(BLOCK))
        .into_par_iter()
        .map_init(
            || (scratch(), vec![zero; m]),
            |(s, column), b| {
                let mut best = (-1.0, 0, 0);
                for kx in b * BLOCK..((b + 1) * BLOCK).min(m) {
                    for (row, v) in column[..n].iter_mut().enumerate() {
                        *v = rows[row * m + kx];
                    }
                    column[n..].fill(zero);
                    forward.process_with_scratch(column, s);
                    for (ky, v) in column.iter().enumerate() {
                        if v.norm_sqr() > best.0 {
                            best = (v.norm_sqr(), kx, ky);
                        }
                    }
                }
                best
            },
        )
        .collect();
    let (_, kx, ky) = blocks.into_iter().fold((-1.0, 0, 0), |a, b| if b.0 > a.0 { b } else { a });
    let signed = |k: usize| if k >= m / 2 { k as f64 - m as f64 } else { k as f64 };
    // the transform's index k is the tilt k / (m * 2 / n) waves per unit
    let step = n as f64 / (2.0 * m as f64);
    (signed(kx) * step, signed(ky) * step)
}

/// The statistics of samples (normalised pupil point, area weight, W in
/// waves); at least one sample with positive weight. The Strehl ratio's
/// peak is searched from the least-squares tilt only.
pub fn stats_of(samples: &[((f64, f64), f64, f64)]) -> WavefrontStats {
    let mut s = moments(samples);
    s.strehl = PupilFunction::scattered(samples).strehl(s.tilt);
    s
}

/// The RMS wavefront error of `w` with piston and tilt removed (Zemax's
/// "RMS (to centroid)"), waves: [`WavefrontStats::rms_to_centroid`]
/// without the Strehl ratio's transform.
pub fn rms_to_centroid(w: &Wavefront) -> f64 {
    let samples: Vec<((f64, f64), f64, f64)> = w.passing().collect();
    moments(&samples).rms_to_centroid
}

/// The statistics of samples but the Strehl ratio (left 0).
fn moments(samples: &[((f64, f64), f64, f64)]) -> WavefrontStats {
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
        strehl: 0.0,
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

/// The pupil function P = A exp(2 pi i W) of a wavefront, laid out for the
/// Strehl search: the whole cells of its grid as an n x n array (zero where
/// a cell is not whole or its ray is blocked), whose sum against a tilt's
/// phase separates into rows and columns, and the rim cells (sampled at
/// their centroids) as a list.
struct PupilFunction {
    n: usize,
    /// Column (x) and row (y) centres of the grid's cells.
    centres: Vec<f64>,
    /// Row-major n x n values of the whole cells, real and imaginary
    /// parts apart (so the row sums run on vector lanes).
    whole_re: Vec<f64>,
    whole_im: Vec<f64>,
    /// Per row, the columns from the first to the last whole cell.
    spans: Vec<(usize, usize)>,
    /// The other passing samples.
    rim: Vec<RimSample>,
    /// The sum of the area weights.
    total: f64,
}

/// A passing cell the disk's rim cuts (or a scattered sample): (column,
/// row) on the grid, its normalised pupil point, and P there.
type RimSample = ((usize, usize), (f64, f64), Complex<f64>);

/// S and its five derivatives in the tilt (see [`PupilFunction::sums`]).
type Sums = [Complex<f64>; 6];

impl PupilFunction {
    /// The pupil function of `w`'s passing cells.
    fn of(w: &Wavefront) -> Self {
        let n = w.grid.n;
        let h = 2.0 / n as f64;
        // as the grid computes a whole cell's centre
        let centres: Vec<f64> = (0..n)
            .map(|k| {
                let a = -1.0 + k as f64 * h;
                0.5 * (a + (a + h))
            })
            .collect();
        let (mut whole_re, mut whole_im) = (vec![0.0; n * n], vec![0.0; n * n]);
        let mut spans = vec![(0, 0); n];
        let mut rim = Vec::new();
        let mut total = 0.0;
        for (c, v) in w.grid.cells.iter().zip(&w.opd_waves) {
            let Some(v) = v else { continue };
            let p = Complex::from_polar(c.area, TAU * v);
            total += c.area;
            if c.centre == (centres[c.column], centres[c.row]) {
                whole_re[c.row * n + c.column] = p.re;
                whole_im[c.row * n + c.column] = p.im;
                let span = &mut spans[c.row];
                *span = if span.1 == 0 { (c.column, c.column + 1) } else { (span.0, c.column + 1) };
            } else {
                rim.push(((c.column, c.row), c.centre, p));
            }
        }
        PupilFunction { n, centres, whole_re, whole_im, spans, rim, total }
    }

    /// P at the whole cell (column, row).
    fn whole(&self, column: usize, row: usize) -> Complex<f64> {
        Complex::new(self.whole_re[row * self.n + column], self.whole_im[row * self.n + column])
    }

    /// The pupil function of scattered samples (point, weight, W).
    fn scattered(samples: &[((f64, f64), f64, f64)]) -> Self {
        PupilFunction {
            n: 0,
            centres: Vec::new(),
            whole_re: Vec::new(),
            whole_im: Vec::new(),
            spans: Vec::new(),
            rim: samples.iter().map(|&(at, wt, w)| ((0, 0), at, Complex::from_polar(wt, TAU * w))).collect(),
            total: samples.iter().map(|s| s.1).sum(),
        }
    }

    /// S(a, b) = sum P exp(-2 pi i (a x + b y)) and its first and second
    /// derivatives in (a, b): [S, S_a, S_b, S_aa, S_ab, S_bb]. The whole
    /// cells by rows (the column phases made once), blocks of rows on all
    /// cores, summed in order.
    fn sums(&self, a: f64, b: f64) -> Sums {
        let zero = Complex::new(0.0, 0.0);
        let i = Complex::new(0.0, 1.0);
        let n = self.n;
        let (ex_re, ex_im): (Vec<f64>, Vec<f64>) = self
            .centres
            .iter()
            .map(|x| {
                let (sin, cos) = (-TAU * a * x).sin_cos();
                (cos, sin)
            })
            .unzip();
        const BLOCK: usize = 16;
        let blocks: Vec<Sums> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|k| {
                let mut acc = [zero; 6];
                for row in k * BLOCK..((k + 1) * BLOCK).min(n) {
                    let (c0, c1) = self.spans[row];
                    if c1 == 0 {
                        continue;
                    }
                    let cells = row * n + c0..row * n + c1;
                    // the row's sums of P e^{-2 pi i a x} times 1, x, x^2
                    let mut r = [0.0; 6];
                    for ((((pr, pi), er), ei), x) in self.whole_re[cells.clone()]
                        .iter()
                        .zip(&self.whole_im[cells])
                        .zip(&ex_re[c0..c1])
                        .zip(&ex_im[c0..c1])
                        .zip(&self.centres[c0..c1])
                    {
                        let (tr, ti) = (pr * er - pi * ei, pr * ei + pi * er);
                        r[0] += tr;
                        r[1] += ti;
                        r[2] += tr * x;
                        r[3] += ti * x;
                        r[4] += tr * (x * x);
                        r[5] += ti * (x * x);
                    }
                    let (r0, r1, r2) = (Complex::new(r[0], r[1]), Complex::new(r[2], r[3]), Complex::new(r[4], r[5]));
                    let y = self.centres[row];
                    let ey = Complex::from_polar(1.0, -TAU * b * y);
                    let (r0, r1, r2) = (r0 * ey, r1 * ey, r2 * ey);
                    acc[0] += r0;
                    // d/da of exp(-2 pi i a x) is -2 pi i x exp(..)
                    acc[1] += r1 * i * -TAU;
                    acc[2] += r0 * i * (-TAU * y);
                    acc[3] += r2 * (-TAU * TAU);
                    acc[4] += r1 * (-TAU * TAU * y);
                    acc[5] += r0 * (-TAU * TAU * y * y);
                }
                acc
            })
            .collect();
        let mut acc = [zero; 6];
        for block in blocks {
            acc.iter_mut().zip(block).for_each(|(p, q)| *p += q);
        }
        for &(_, (x, y), p) in &self.rim {
            let e = p * Complex::from_polar(1.0, -TAU * (a * x + b * y));
            acc[0] += e;
            acc[1] += e * i * (-TAU * x);
            acc[2] += e * i * (-TAU * y);
            acc[3] += e * (-TAU * TAU * x * x);
            acc[4] += e * (-TAU * TAU * x * y);
            acc[5] += e * (-TAU * TAU * y * y);
        }
        acc
    }

    /// The Strehl ratio: the largest |S(a, b)|^2 / (sum A)^2 over tilts,
    /// by Newton's method from the tilt `start` (damped: every step must
    /// raise the peak).
    fn strehl(&self, start: (f64, f64)) -> f64 {
        let total = self.total;
        // |S|^2 and its gradient and Hessian in (a, b)
        let eval = |a: f64, b: f64| {
            let [s, sa, sb, saa, sab, sbb] = self.sums(a, b);
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
            if !moved || d[0].abs().max(d[1].abs()) < 1e-10 {
                break;
            }
        }
        (f / (total * total)).min(1.0)
    }
}
