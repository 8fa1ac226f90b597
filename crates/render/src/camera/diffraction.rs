//! Diffraction at the aperture (`film.diffraction`): the film convolved
//! with the Fraunhofer pattern of the lens's exit pupil, per colour.
//!
//! The pupil function is the stop's shape (circle, blades, or mask; its
//! amplitude the square root of the mask's transmission), sampled on a
//! [`PUPIL`] x [`PUPIL`] grid with the pupil's diameter across a quarter of it
//! (4 x 4 points a sample on its edges, so a polygon's edges are not
//! stair-cased into spurious spikes), and its power spectrum |F|^2 is the
//! point spread function: at wavelength λ and working f-number N (the
//! exit pupil's distance to the film over its diameter), its samples lie
//! λ N / 4 apart on the film (four to the rings' period). Each wavelength's PSF is put on the
//! film's pixels as the light that falls in each (the samples joined by a
//! Catmull-Rom spline integrated over the pixel; the film's x mirrored as
//! the camera maps it), the wavelengths summed per channel by the sRGB share of their
//! colour, each wavelength's pattern normalised to 1: the film's light is
//! moved, never made or lost (except what crosses the frame's edge; the
//! kernel reaches no farther than the frame). The film is then convolved
//! with the kernel by FFT.
//!
//! Approximated: one PSF for the whole frame, that of the on-axis pupil
//! without the wavefront (the geometric image already holds the lens's
//! aberrations, and diffraction adds the aperture's pattern to it); the
//! pattern is cut off at `PUPIL / 4` samples (128 λ N on the film) from
//! the centre. The error against each field's wave PSF is measured in
//! `tests/diffraction_error.rs` (docs/rendering.md, "Diffraction at the
//! aperture").

use super::aperture::Aperture;
use super::real_lens::RealLensCamera;
use crate::scene::ColourMode;
use crate::spectrum::cie;
use glam::DVec3;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// Samples across the pupil grid (the pupil's diameter spans a quarter).
pub const PUPIL: usize = 2048;
/// Wavelengths of a colour render's PSF (midpoints of equal bands over
/// 400-700 nm).
pub const WAVELENGTHS: usize = 8;

/// A convolution kernel on the film's pixels: `rgb[(dy + cy) * nx + dx +
/// cx]` is the share of a pixel's light moved `dx` columns right and `dy`
/// rows down.
#[derive(Debug, Clone)]
pub struct Kernel {
    pub nx: usize,
    pub ny: usize,
    pub cx: usize,
    pub cy: usize,
    pub rgb: Vec<DVec3>,
}

/// The power spectrum of the pupil `aperture` (unit scale), `PUPIL`
/// squared samples, the zero frequency at the centre.
fn pupil_spectrum(aperture: &Aperture) -> Vec<f64> {
    let m = PUPIL;
    let radius = m as f64 / 8.0;
    const SUB: usize = 4;
    let rows: Vec<Vec<Complex64>> = (0..m)
        .into_par_iter()
        .map(|j| {
            (0..m)
                .map(|i| {
                    let (x, y) =
                        ((i as f64 + 0.5 - m as f64 / 2.0) / radius, (j as f64 + 0.5 - m as f64 / 2.0) / radius);
                    if x * x + y * y > 2.05 {
                        return Complex64::new(0.0, 0.0);
                    }
                    let mut t = 0.0;
                    for b in 0..SUB {
                        for a in 0..SUB {
                            let (u, v) = (
                                x + ((a as f64 + 0.5) / SUB as f64 - 0.5) / radius,
                                y + ((b as f64 + 0.5) / SUB as f64 - 0.5) / radius,
                            );
                            t += aperture.transmission(u, v).max(0.0).sqrt();
                        }
                    }
                    Complex64::new(t / (SUB * SUB) as f64, 0.0)
                })
                .collect()
        })
        .collect();
    let mut grid: Vec<Complex64> = rows.into_iter().flatten().collect();
    fft2(&mut grid, m, m, false);
    // shifted so the zero frequency sits at (m/2, m/2)
    let mut out = vec![0.0; m * m];
    for j in 0..m {
        for i in 0..m {
            out[((j + m / 2) % m) * m + (i + m / 2) % m] = grid[j * m + i].norm_sqr();
        }
    }
    out
}

/// The diffraction kernel of `cam`'s aperture on a film of `w` x `h`
/// pixels, for the render's colour mode.
pub fn kernel(cam: &RealLensCamera, colour: &ColourMode, w: usize, h: usize) -> Kernel {
    let [sw, sh] = cam.sensor_mm();
    let n = working_f_number(cam);
    kernel_for(cam.aperture(), n, [sw / w as f64, sh / h as f64], [w, h], colour)
}

/// The working f-number of `cam`'s lens as focused: see
/// [`working_f_number_of`].
pub fn working_f_number(cam: &RealLensCamera) -> f64 {
    working_f_number_of(cam.prescription())
}

/// The working f-number of `p` with its film where its last thickness puts
/// it: the paraxial exit pupil's distance to the film over its diameter;
/// the lens's f-number where it has no exit pupil, 8 where it has no
/// first-order properties.
pub fn working_f_number_of(p: &lens::Prescription) -> f64 {
    match lens::paraxial::FirstOrder::of(p) {
        Ok(f) => match f.exit_pupil {
            Some(xp) if xp.diameter > 0.0 => {
                let film = p.last_vertex_z() + p.film_distance();
                ((film - xp.z) / xp.diameter).abs()
            }
            _ => f.f_number,
        },
        Err(_) => 8.0,
    }
}

/// The kernel of `aperture` at working f-number `n` on pixels `pixel_mm`
/// (width, height) wide, for `colour` (see the module).
pub fn kernel_for(
    aperture: &Aperture,
    n: f64,
    pixel_mm: [f64; 2],
    frame_px: [usize; 2],
    colour: &ColourMode,
) -> Kernel {
    let spectrum = pupil_spectrum(aperture);
    let m = PUPIL;
    let bands: Vec<(f64, DVec3)> = match colour {
        ColourMode::Monochromatic(nm) => vec![(*nm, DVec3::ONE)],
        _ => {
            let band = 300.0 / WAVELENGTHS as f64;
            (0..WAVELENGTHS)
                .map(|k| {
                    let nm = 400.0 + (k as f64 + 0.5) * band;
                    (nm, cie::xyz_to_rgb(cie::cmf(nm)).max(DVec3::ZERO))
                })
                .collect()
        }
    };
    // the kernel's reach: the grid's half width at the longest wavelength
    let longest = bands.iter().map(|b| b.0).fold(0.0, f64::max);
    let step_max = longest * 1e-6 * n / 4.0;
    let reach = (m as f64 / 4.0) * step_max;
    // no farther than the frame (`frame_px`): light cannot move farther on it
    let rx = ((reach / pixel_mm[0]).ceil() as usize + 1).min(frame_px[0]);
    let ry = ((reach / pixel_mm[1]).ceil() as usize + 1).min(frame_px[1]);
    let (nx, ny) = (2 * rx + 1, 2 * ry + 1);
    let mut rgb = vec![DVec3::ZERO; nx * ny];
    for (nm, weight) in &bands {
        let step = nm * 1e-6 * n / 4.0;
        let mut one = vec![0.0; nx * ny];
        // the central half of the spectrum's grid (its outer part is the
        // pupil's own sampling, not the pattern)
        let q = m / 4;
        let total: f64 = ((m / 2 - q)..(m / 2 + q))
            .flat_map(|j| ((m / 2 - q)..(m / 2 + q)).map(move |i| (i, j)))
            .map(|(i, j)| spectrum[j * m + i])
            .sum();
        // the pattern between its samples is a Catmull-Rom spline (the
        // samples are twice as dense as the pattern needs): each sample's
        // basis function integrated over the pixels it covers, separably,
        // so the kernel holds each pixel's light (not the pattern at its
        // centre, nor smeared by a spread to the neighbours); film x =
        // -column, film y = row
        let samples: Vec<usize> = ((m / 2 - q)..(m / 2 + q)).collect();
        let shares = |centre: fn(f64) -> f64, pixel: f64, r: usize, count: usize| -> Vec<(usize, Vec<f64>)> {
            samples
                .iter()
                .map(|&i| {
                    spline_shares(centre((i as f64 - m as f64 / 2.0) * step / pixel) + r as f64, step / pixel, count)
                })
                .collect()
        };
        let wx = shares(|u| -u, pixel_mm[0], rx, nx);
        let wy = shares(|v| v, pixel_mm[1], ry, ny);
        // each sample row spread across the columns, then the rows down
        let rows: Vec<Vec<f64>> = samples
            .par_iter()
            .map(|&j| {
                let mut row = vec![0.0; nx];
                for (&i, (k0, w)) in samples.iter().zip(&wx) {
                    let v = spectrum[j * m + i];
                    if v > 0.0 {
                        for (t, wk) in w.iter().enumerate() {
                            row[k0 + t] += v * wk;
                        }
                    }
                }
                row
            })
            .collect();
        for (row, (l0, w)) in rows.iter().zip(&wy) {
            for (t, wl) in w.iter().enumerate() {
                let out = &mut one[(l0 + t) * nx..(l0 + t + 1) * nx];
                for (o, r) in out.iter_mut().zip(row) {
                    *o += r * wl;
                }
            }
        }
        // normalised by the whole pattern: what falls past the frame is
        // lost; the spline's undershoot in the dark rings (a few 1e-6 of
        // the peak) left out
        if total > 0.0 {
            for (o, v) in rgb.iter_mut().zip(one) {
                *o += *weight * (v.max(0.0) / total);
            }
        }
    }
    // each channel's weights sum to 1 over the wavelengths
    let weights: DVec3 = bands.iter().map(|b| b.1).sum();
    for v in &mut rgb {
        *v /= weights.max(DVec3::splat(1e-300));
    }
    Kernel { nx, ny, cx: rx, cy: ry, rgb }
}

/// The shares of a Catmull-Rom basis function (support two samples each
/// way) whose samples are `s` pixels apart, centred at `u` (pixel k spans
/// k - 1/2 to k + 1/2), over pixels `0..n`: the first pixel and the shares
/// from it (summing to 1 where none is cut off; the lobes slightly
/// negative).
fn spline_shares(u: f64, s: f64, n: usize) -> (usize, Vec<f64>) {
    // the basis's integral from its left end to t samples from its centre
    let cdf = |t: f64| {
        let a = t.abs().min(2.0);
        let inner = |x: f64| x * (1.0 + x * x * (-2.5 / 3.0 + 0.375 * x));
        let outer = |x: f64| x * (2.0 + x * (-2.0 + x * (2.5 / 3.0 - 0.125 * x)));
        let g = if a <= 1.0 { inner(a) } else { inner(1.0) + outer(a) - outer(1.0) };
        0.5 + g.copysign(t)
    };
    let lo = (u - 2.0 * s - 0.5).floor().max(0.0) as usize;
    let hi = ((u + 2.0 * s + 0.5).ceil().max(0.0) as usize).min(n);
    if lo >= hi {
        return (0, Vec::new());
    }
    let w = (lo..hi).map(|k| cdf((k as f64 + 0.5 - u) / s) - cdf((k as f64 - 0.5 - u) / s)).collect();
    (lo, w)
}

/// `film` (w x h, row-major) convolved with `k` by FFT, per channel; light
/// moved past the frame's edge is lost.
pub fn convolve(film: &mut [DVec3], w: usize, h: usize, k: &Kernel) {
    let fw = (w + k.nx).next_power_of_two();
    let fh = (h + k.ny).next_power_of_two();
    let channel = |c: usize| -> Vec<f64> {
        let get = |v: &DVec3| [v.x, v.y, v.z][c];
        let mut a = vec![Complex64::new(0.0, 0.0); fw * fh];
        for y in 0..h {
            for x in 0..w {
                a[y * fw + x] = Complex64::new(get(&film[y * w + x]), 0.0);
            }
        }
        let mut b = vec![Complex64::new(0.0, 0.0); fw * fh];
        for j in 0..k.ny {
            for i in 0..k.nx {
                let (dx, dy) = (i as isize - k.cx as isize, j as isize - k.cy as isize);
                let (x, y) = (dx.rem_euclid(fw as isize) as usize, dy.rem_euclid(fh as isize) as usize);
                b[y * fw + x] = Complex64::new(get(&k.rgb[j * k.nx + i]), 0.0);
            }
        }
        fft2(&mut a, fw, fh, false);
        fft2(&mut b, fw, fh, false);
        for (x, y) in a.iter_mut().zip(&b) {
            *x *= y;
        }
        fft2(&mut a, fw, fh, true);
        let scale = 1.0 / (fw * fh) as f64;
        (0..w * h).map(|q| a[(q / w) * fw + q % w].re * scale).collect()
    };
    let out: Vec<Vec<f64>> = (0..3).into_par_iter().map(channel).collect();
    for (q, v) in film.iter_mut().enumerate() {
        *v = DVec3::new(out[0][q], out[1][q], out[2][q]);
    }
}

/// A 2-D FFT in place (rows then columns) of `a`, `w` x `h` row-major;
/// `inverse` unscaled.
fn fft2(a: &mut [Complex64], w: usize, h: usize, inverse: bool) {
    let mut planner = FftPlanner::new();
    let (fr, fc) = if inverse {
        (planner.plan_fft_inverse(w), planner.plan_fft_inverse(h))
    } else {
        (planner.plan_fft_forward(w), planner.plan_fft_forward(h))
    };
    a.par_chunks_mut(w).for_each(|row| fr.process(row));
    let mut t = vec![Complex64::new(0.0, 0.0); w * h];
    for y in 0..h {
        for x in 0..w {
            t[x * h + y] = a[y * w + x];
        }
    }
    t.par_chunks_mut(h).for_each(|col| fc.process(col));
    for y in 0..h {
        for x in 0..w {
            a[y * w + x] = t[x * h + y];
        }
    }
}
