//! Point spread functions from a field's wavefront: by FFT of the pupil
//! function (Fraunhofer), or by the Huygens sum over the reference sphere
//! onto the image plane (the right one for fast lenses, large fields and
//! image planes away from focus), each with its encircled energy.
//!
//! Both are normalised so that the same pupil without aberration peaks at
//! 1 (a PSF's values are then Strehl ratios); both sample the pupil
//! function P = A exp(2 pi i W) of the [`Wavefront`]'s grid, A the cell's
//! share of its area inside the pupil (uniform illumination of the
//! entrance pupil; the pupil's own distortion of that illumination is
//! left out).
//!
//! The FFT image's pixel is 1 / (Q nu_c) along each direction, nu_c the
//! direction's cutoff ([`super::mtf::cutoffs`]: lambda N_w / Q with the
//! working f-number of the real rim rays) and Q the padding (the FFT's
//! size over the pupil grid's); a tilt of the wavefront moves the image:
//! W = a px puts the peak at x = -2 a / nu_c. Image rows run along +y,
//! columns along +x, centred on the chief ray's image point.

use super::opd::Wavefront;
use nalgebra::{Complex, DMatrix};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// How a PSF was computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PsfMethod {
    /// The 2-D FFT of the zero-padded pupil function.
    Fft,
    /// The Huygens sum of spherical wavelets from the reference sphere.
    Huygens,
}

impl PsfMethod {
    /// `"fft"` or `"huygens"`.
    pub fn name(self) -> &'static str {
        match self {
            PsfMethod::Fft => "fft",
            PsfMethod::Huygens => "huygens",
        }
    }
}

/// A point spread function on a square grid of the image plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Psf {
    /// How it was computed.
    pub method: PsfMethod,
    /// Pixels across (and down).
    pub size: usize,
    /// Pixel spacing along x and y, mm.
    pub pixel_mm: (f64, f64),
    /// Intensity, row-major from -y (row 0) to +y, columns from -x; the
    /// chief ray's image point at (size / 2, size / 2). Normalised so the
    /// same pupil without aberration peaks at 1.
    pub intensity: Vec<f64>,
    /// The light of the whole image plane in the units of a pixel sum
    /// (Parseval: the same with or without aberration); a Huygens image
    /// holds less than this where its window is smaller than the PSF.
    pub total: f64,
}

impl Psf {
    /// The image-plane offset from the chief ray's image point (mm) of
    /// pixel (column, row).
    pub fn position(&self, column: usize, row: usize) -> (f64, f64) {
        let h = (self.size / 2) as f64;
        ((column as f64 - h) * self.pixel_mm.0, (row as f64 - h) * self.pixel_mm.1)
    }

    /// The largest pixel value (a grid's maximum: it may miss the true
    /// peak, which the Strehl ratio of [`super::stats`] finds off-grid).
    pub fn peak(&self) -> f64 {
        self.intensity.iter().fold(0.0, |m, v| m.max(*v))
    }

    /// The intensity-weighted centroid, mm from the chief ray's image
    /// point.
    pub fn centroid(&self) -> (f64, f64) {
        let (mut sx, mut sy, mut s) = (0.0, 0.0, 0.0);
        for row in 0..self.size {
            for col in 0..self.size {
                let v = self.intensity[row * self.size + col];
                let (x, y) = self.position(col, row);
                sx += v * x;
                sy += v * y;
                s += v;
            }
        }
        if s > 0.0 {
            (sx / s, sy / s)
        } else {
            (0.0, 0.0)
        }
    }

    /// The fraction of all the light within each radius of `radii_mm`
    /// about `centre` (mm from the chief ray's image point): encircled
    /// energy, each pixel split 4 x 4 for the circle's edge.
    pub fn encircled_energy(&self, centre: (f64, f64), radii_mm: &[f64]) -> Vec<f64> {
        let total = self.total;
        if total <= 0.0 {
            return vec![0.0; radii_mm.len()];
        }
        // every sub-pixel's distance and share, sorted by distance
        let mut parts: Vec<(f64, f64)> = Vec::with_capacity(self.intensity.len() * 16);
        for row in 0..self.size {
            for col in 0..self.size {
                let v = self.intensity[row * self.size + col] / 16.0;
                let (x, y) = self.position(col, row);
                for k in 0..16 {
                    let dx = ((k % 4) as f64 - 1.5) / 4.0 * self.pixel_mm.0;
                    let dy = ((k / 4) as f64 - 1.5) / 4.0 * self.pixel_mm.1;
                    parts.push(((x + dx - centre.0).hypot(y + dy - centre.1), v));
                }
            }
        }
        parts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = Vec::with_capacity(radii_mm.len());
        for &r in radii_mm {
            let n = parts.partition_point(|p| p.0 <= r);
            out.push(parts[..n].iter().map(|p| p.1).sum::<f64>() / total);
        }
        out
    }

    /// The fraction of all the light within squares of half-width each of
    /// `half_widths_mm` about `centre`: ensquared energy.
    pub fn ensquared_energy(&self, centre: (f64, f64), half_widths_mm: &[f64]) -> Vec<f64> {
        let total = self.total;
        half_widths_mm
            .iter()
            .map(|&h| {
                let mut s = 0.0;
                for row in 0..self.size {
                    for col in 0..self.size {
                        let (x, y) = self.position(col, row);
                        // the share of the pixel inside the square, along each axis
                        let share = |c: f64, p: f64| ((c + 0.5 * p).min(h) - (c - 0.5 * p).max(-h)).max(0.0) / p;
                        let (fx, fy) = (share(x - centre.0, self.pixel_mm.0), share(y - centre.1, self.pixel_mm.1));
                        s += self.intensity[row * self.size + col] * fx * fy;
                    }
                }
                if total > 0.0 {
                    s / total
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// The pupil function of `w` on its grid: (column, row, A exp(2 pi i W)),
/// for the cells whose rays pass.
fn pupil(w: &Wavefront) -> Vec<(usize, usize, Complex<f64>)> {
    w.grid
        .cells
        .iter()
        .zip(&w.opd_waves)
        .filter_map(|(c, v)| v.map(|v| (c.column, c.row, Complex::from_polar(c.area, TAU * v))))
        .collect()
}

/// The FFT PSF of `w`, the pupil grid zero-padded `pad` times (at least 2),
/// with the direction cutoffs `cutoffs` = (tangential, sagittal), cycles/mm.
pub fn fft_psf(w: &Wavefront, cutoffs: (f64, f64), pad: usize) -> Psf {
    let pad = pad.max(2);
    let n = w.grid.n;
    let m = n * pad;
    let mut field = vec![Complex::new(0.0, 0.0); m * m];
    let p = pupil(w);
    let peak: f64 = p.iter().map(|c| c.2.norm()).sum();
    for &(col, row, v) in &p {
        field[row * m + col] = v;
    }
    // e^{+2 pi i jk / M}: the image of W = a px lies at x = -2 a / nu_c
    fft2(&mut field, m, n, rustfft::FftDirection::Inverse);
    // the pupil grid's first cell sits at -1 + 1/n, not at index 0's phase
    // centre: only a phase, gone in the intensity. fftshift to centre.
    let norm = 1.0 / (peak * peak);
    let mut intensity = vec![0.0; m * m];
    for row in 0..m {
        for col in 0..m {
            let (sr, sc) = ((row + m / 2) % m, (col + m / 2) % m);
            intensity[sr * m + sc] = field[row * m + col].norm_sqr() * norm;
        }
    }
    let (ct, cs) = cutoffs;
    let total = intensity.iter().sum();
    Psf {
        method: PsfMethod::Fft,
        size: m,
        pixel_mm: (1.0 / (pad as f64 * cs), 1.0 / (pad as f64 * ct)),
        intensity,
        total,
    }
}

/// The 2-D discrete Fourier transform (unnormalised, in `direction`) of
/// the m x m row-major array `field`, in place, where only its first
/// `rows` rows may be non-zero (a zero-padded pupil): those rows, then
/// every column, on all cores.
pub(crate) fn fft2(field: &mut [Complex<f64>], m: usize, rows: usize, direction: rustfft::FftDirection) {
    let fft = rustfft::FftPlanner::new().plan_fft(m, direction);
    let scratch = || vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
    let rows = rows.min(m);
    field[..rows * m].par_chunks_mut(m).for_each_init(scratch, |s, r| fft.process_with_scratch(r, s));
    let mut t = vec![Complex::new(0.0, 0.0); m * m];
    transpose(field, &mut t, m);
    t.par_chunks_mut(m).for_each_init(scratch, |s, r| fft.process_with_scratch(r, s));
    transpose(&t, field, m);
}

/// `out` = the transpose of the m x m matrix `a`, in tiles that stay in
/// the cache.
fn transpose(a: &[Complex<f64>], out: &mut [Complex<f64>], m: usize) {
    const TILE: usize = 16;
    out.par_chunks_mut(m * TILE).enumerate().for_each(|(band, rows)| {
        let r0 = band * TILE;
        for c0 in (0..m).step_by(TILE) {
            for (dr, row) in rows.chunks_mut(m).enumerate() {
                let r = r0 + dr;
                for c in c0..(c0 + TILE).min(m) {
                    row[c] = a[c * m + r];
                }
            }
        }
    });
}

/// The Huygens PSF of `w` on a `size` x `size` grid of the image plane with
/// pixels `pixel_mm` (x, y) about the chief ray's image point: each
/// passing cell's point on the reference sphere sends a wavelet A exp(2 pi
/// i W) exp(-2 pi i n' (|X - E| - R) / lambda) to each image point X.
/// `cutoffs` (tangential, sagittal; cycles/mm) scale the whole plane's
/// light ([`Psf::total`]): as an FFT image of these pixels would hold it,
/// (Q_x n)(Q_y n) sum A^2 / (sum A)^2 with Q = 1 / (pixel nu_c).
pub fn huygens_psf(w: &Wavefront, size: usize, pixel_mm: (f64, f64), cutoffs: (f64, f64)) -> Psf {
    let size = size.max(1);
    let c = w.chief_image;
    let k = TAU * w.image_index / w.wavelength_mm();
    let r = w.reference_radius.abs();
    let sources: Vec<(glam::DVec3, Complex<f64>)> = w
        .grid
        .cells
        .iter()
        .zip(w.opd_waves.iter().zip(&w.sphere_points))
        .filter_map(|(cell, (v, e))| Some((e.as_ref().copied()?, Complex::from_polar(cell.area, TAU * (*v)?))))
        .collect();
    let peak: f64 = sources.iter().map(|s| s.1.norm()).sum();
    let h = (size / 2) as f64;
    let intensity: Vec<f64> = (0..size * size)
        .into_par_iter()
        .map(|i| {
            let (col, row) = (i % size, i / size);
            let x = c + glam::DVec3::new((col as f64 - h) * pixel_mm.0, (row as f64 - h) * pixel_mm.1, 0.0);
            let u: Complex<f64> =
                sources.iter().map(|(e, a)| a * Complex::from_polar(1.0, -k * ((x - *e).length() - r))).sum();
            u.norm_sqr() / (peak * peak)
        })
        .collect();
    let n = w.grid.n as f64;
    let (qx, qy) = (1.0 / (pixel_mm.0 * cutoffs.1), 1.0 / (pixel_mm.1 * cutoffs.0));
    let power: f64 = sources.iter().map(|s| s.1.norm_sqr()).sum();
    let total = qx * n * qy * n * power / (peak * peak);
    Psf { method: PsfMethod::Huygens, size, pixel_mm, intensity, total }
}

/// The PSF of `w` on any grid of the image plane, by the matrix Fourier
/// transform of its pupil function (the FFT's Fraunhofer sum, evaluated at
/// chosen points): `size` x `size` pixels of `pixel_mm` (x, y) centred
/// `offset_mm` from `w`'s chief-ray image point, with `w`'s direction
/// cutoffs `cutoffs` = (tangential, sagittal), cycles/mm. Normalised as
/// [`fft_psf`]; on the FFT's own grid it is the FFT's image.
pub fn mft_psf(w: &Wavefront, cutoffs: (f64, f64), size: usize, pixel_mm: (f64, f64), offset_mm: (f64, f64)) -> Psf {
    let n = w.grid.n;
    let size = size.max(1);
    let (ct, cs) = cutoffs;
    let mut pupil_fn = DMatrix::<Complex<f64>>::zeros(n, n); // (row j, column i)
    let mut peak = 0.0;
    let mut power = 0.0;
    for (col, row, v) in pupil(w) {
        pupil_fn[(row, col)] = v;
        peak += v.norm();
        power += v.norm_sqr();
    }
    let h = (size / 2) as f64;
    let p = |i: usize| -1.0 + (i as f64 + 0.5) * 2.0 / n as f64;
    // e^{+i pi nu_c p x} along each direction (the FFT's kernel)
    let ex = DMatrix::from_fn(n, size, |i, k| {
        Complex::from_polar(1.0, std::f64::consts::PI * cs * p(i) * ((k as f64 - h) * pixel_mm.0 + offset_mm.0))
    });
    let ey = DMatrix::from_fn(size, n, |l, j| {
        Complex::from_polar(1.0, std::f64::consts::PI * ct * p(j) * ((l as f64 - h) * pixel_mm.1 + offset_mm.1))
    });
    let u = ey * (pupil_fn * ex); // (row y, column x)
    let norm = 1.0 / (peak * peak);
    let intensity = (0..size * size).map(|i| u[(i / size, i % size)].norm_sqr() * norm).collect();
    let (qx, qy) = (1.0 / (pixel_mm.0 * cs), 1.0 / (pixel_mm.1 * ct));
    let total = qx * n as f64 * qy * n as f64 * power * norm;
    Psf { method: PsfMethod::Fft, size, pixel_mm, intensity, total }
}

/// The polychromatic PSF: each wavelength's PSF (`parts`: its wavefront,
/// cutoffs and weight) by [`mft_psf`] on one grid (`size` x `size` pixels
/// of `pixel_mm`) centred on the chief-ray image point `centre` (global
/// frame, mm; the primary wavelength's), each normalised to its own
/// aberration-free peak, summed incoherently with the weights over their
/// sum.
pub fn polychromatic_psf(
    parts: &[(&Wavefront, (f64, f64), f64)],
    size: usize,
    pixel_mm: (f64, f64),
    centre: glam::DVec3,
) -> Psf {
    let weight: f64 = parts.iter().map(|p| p.2).sum();
    let mut intensity = vec![0.0; size * size];
    let mut total = 0.0;
    for &(w, cutoffs, wt) in parts {
        let d = centre - w.chief_image;
        let one = mft_psf(w, cutoffs, size, pixel_mm, (d.x, d.y));
        intensity.iter_mut().zip(&one.intensity).for_each(|(a, b)| *a += wt * b / weight);
        total += wt * one.total / weight;
    }
    Psf { method: PsfMethod::Fft, size, pixel_mm, intensity, total }
}
