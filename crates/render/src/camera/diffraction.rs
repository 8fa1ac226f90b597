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
//! λ N / 4 apart on the film (four to the rings' period). Each wavelength's PSF is spread onto the
//! film's pixels (bilinearly, the film's x mirrored as the camera maps
//! it), the wavelengths summed per channel by the sRGB share of their
//! colour, each wavelength's pattern normalised to 1: the film's light is
//! moved, never made or lost (except what crosses the frame's edge; the
//! kernel reaches no farther than the frame). The film is then convolved
//! with the kernel by FFT.
//!
//! Approximated: one PSF for the whole frame, that of the on-axis pupil
//! without the wavefront (the geometric image already holds the lens's
//! aberrations, and diffraction adds the aperture's pattern to it); the
//! pattern is cut off at `PUPIL / 4` samples (256 λ N on the film) from
//! the centre.

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

/// The working f-number of `cam`'s lens as focused: the exit pupil's
/// distance to the film over its diameter (paraxial); the lens's f-number
/// where it has no exit pupil.
pub fn working_f_number(cam: &RealLensCamera) -> f64 {
    let p = cam.prescription();
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
        if step >= 0.5 * pixel_mm[0].min(pixel_mm[1]) {
            // samples no denser than the pixels: the pattern interpolated
            // at each pixel's centre, as a density (per step^2)
            let area = pixel_mm[0] * pixel_mm[1] / (step * step);
            for (k, o) in one.iter_mut().enumerate() {
                let (c, r) = ((k % nx) as f64 - rx as f64, (k / nx) as f64 - ry as f64);
                // film x = -column, film y = row
                let (x, y) = (-c * pixel_mm[0], r * pixel_mm[1]);
                let (u, v) = (x / step + m as f64 / 2.0, y / step + m as f64 / 2.0);
                let (u0, v0) = (u.floor(), v.floor());
                let (fu, fv) = (u - u0, v - v0);
                let lim = |t: f64| t >= (m / 2 - q) as f64 && t < (m / 2 + q) as f64;
                let mut val = 0.0;
                for (dv, wv) in [(0.0, 1.0 - fv), (1.0, fv)] {
                    for (du, wu) in [(0.0, 1.0 - fu), (1.0, fu)] {
                        let (uu, vv) = (u0 + du, v0 + dv);
                        if lim(uu) && lim(vv) {
                            val += spectrum[vv as usize * m + uu as usize] * wu * wv;
                        }
                    }
                }
                *o = val * area;
            }
        } else {
            // many samples a pixel: each spread onto the pixels it lies
            // between
            for j in (m / 2 - q)..(m / 2 + q) {
                for i in (m / 2 - q)..(m / 2 + q) {
                    let v = spectrum[j * m + i];
                    if v <= 0.0 {
                        continue;
                    }
                    let x = (i as f64 - m as f64 / 2.0) * step;
                    let y = (j as f64 - m as f64 / 2.0) * step;
                    // film x mirrored (u = 0.5 - x / width), y down the rows
                    let (c, r) = (-x / pixel_mm[0] + rx as f64, y / pixel_mm[1] + ry as f64);
                    let (c0, r0) = (c.floor(), r.floor());
                    let (fc, fr) = (c - c0, r - r0);
                    for (dr, wr) in [(0.0, 1.0 - fr), (1.0, fr)] {
                        for (dc, wc) in [(0.0, 1.0 - fc), (1.0, fc)] {
                            let (cc, rr) = (c0 + dc, r0 + dr);
                            if cc >= 0.0 && rr >= 0.0 && (cc as usize) < nx && (rr as usize) < ny {
                                one[rr as usize * nx + cc as usize] += v * wr * wc;
                            }
                        }
                    }
                }
            }
        }
        // normalised by the whole pattern: what falls past the frame is lost
        if total > 0.0 {
            for (o, v) in rgb.iter_mut().zip(one) {
                *o += *weight * (v / total);
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
