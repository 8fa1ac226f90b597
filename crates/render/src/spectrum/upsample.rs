//! RGB to spectrum: Jakob and Hanika's sigmoid-polynomial model ("A
//! Low-Dimensional Function Space for Efficient Spectral Upsampling",
//! Computer Graphics Forum 38(2), 2019).
//!
//! A reflectance is s(λ) = S(c0 t² + c1 t + c2), t = (λ - 360 nm) / 470 nm,
//! with the sigmoid S(x) = 1/2 + x / (2 sqrt(1 + x²)): smooth, bounded to
//! (0, 1), three numbers per colour. The coefficients are fitted so that
//! the spectrum, lit by D65 and seen by the CIE 1931 observer, has the
//! colour asked for: Gauss-Newton on the difference in CIELAB, walked from
//! mid grey to the colour in steps (the paper's continuation), each step
//! started from the last. Greys (r = g = b) are flat spectra, exactly.
//!
//! Emission of any brightness (pbrt-v4's illuminant model): RGB radiance
//! c with largest component m is 2 m s(λ) D65(λ), s fitted to c / (2 m),
//! D65 scaled to luminance 1; so white (1, 1, 1) is D65 itself.
//!
//! Round trip (colour → spectrum → colour) over the sRGB gamut: see
//! `tests` and docs/rendering.md.

use super::cie::{cmf, d65_normalised, rgb_to_xyz, y_integral, MAX_NM, MIN_NM};
use glam::{DMat3, DVec3};
use std::sync::OnceLock;

/// A reflectance spectrum in (0, 1) fitted to a linear sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RgbSpectrum {
    /// The same value at every wavelength (a grey).
    Flat(f64),
    /// S(c0 t² + c1 t + c2), t = (λ - 360) / 470.
    Sigmoid([f64; 3]),
}

impl RgbSpectrum {
    /// The reflectance at `nm`.
    #[inline]
    pub fn at(&self, nm: f64) -> f64 {
        self.at_t((nm - MIN_NM) / (MAX_NM - MIN_NM))
    }

    /// The reflectance at t = (λ - 360 nm) / 470 nm.
    #[inline]
    pub fn at_t(&self, t: f64) -> f64 {
        match *self {
            RgbSpectrum::Flat(v) => v,
            RgbSpectrum::Sigmoid(c) => sigmoid((c[0] * t + c[1]) * t + c[2]),
        }
    }

    /// Fits a reflectance to linear sRGB `rgb` (each component clamped to
    /// [0, 1]): the whole sRGB cube, its primaries included, round-trips
    /// to 1e-6 (a test); about 0.3 ms a colour.
    pub fn fit(rgb: DVec3) -> RgbSpectrum {
        let rgb = rgb.clamp(DVec3::ZERO, DVec3::ONE);
        if rgb.x == rgb.y && rgb.y == rgb.z {
            return RgbSpectrum::Flat(rgb.x);
        }
        let target = lab(rgb_to_xyz(rgb));
        let mut c = [0.0; 3];
        const STEPS: usize = 16;
        for k in 1..=STEPS {
            let f = k as f64 / STEPS as f64;
            let step = DVec3::splat(0.5).lerp(rgb, f);
            let goal = if k == STEPS { target } else { lab(rgb_to_xyz(step)) };
            c = gauss_newton(c, goal);
        }
        RgbSpectrum::Sigmoid(c)
    }

    /// The linear sRGB colour this reflectance has under D65.
    pub fn rgb(&self) -> DVec3 {
        super::cie::xyz_to_rgb(self.xyz())
    }

    /// Its tristimulus XYZ under D65 (luminance 1).
    pub fn xyz(&self) -> DVec3 {
        let w = weights();
        match *self {
            RgbSpectrum::Flat(v) => w.iter().fold(DVec3::ZERO, |a, (_, k)| a + *k) * v,
            RgbSpectrum::Sigmoid(c) => xyz_of(c),
        }
    }
}

/// The sigmoid S(x) = 1/2 + x / (2 sqrt(1 + x²)).
#[inline]
pub fn sigmoid(x: f64) -> f64 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// Per 1 nm node: t, and the weight x̄ D65 / ∫ȳ (trapezoid) of XYZ.
fn weights() -> &'static [(f64, DVec3)] {
    static W: OnceLock<Vec<(f64, DVec3)>> = OnceLock::new();
    W.get_or_init(|| {
        let n = (MAX_NM - MIN_NM) as usize + 1;
        let norm = 1.0 / y_integral();
        (0..n)
            .map(|i| {
                let nm = MIN_NM + i as f64;
                let end = if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
                ((nm - MIN_NM) / (MAX_NM - MIN_NM), cmf(nm) * d65_normalised(nm) * end * norm)
            })
            .collect()
    })
}

fn xyz_of(c: [f64; 3]) -> DVec3 {
    weights().iter().fold(DVec3::ZERO, |a, (t, w)| a + *w * sigmoid((c[0] * t + c[1]) * t + c[2]))
}

/// CIELAB of `xyz` against the D65 white of luminance 1.
fn lab(xyz: DVec3) -> DVec3 {
    let w = rgb_to_xyz(DVec3::ONE);
    let f = |t: f64| {
        let d: f64 = 6.0 / 29.0;
        if t > d * d * d {
            t.cbrt()
        } else {
            t / (3.0 * d * d) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (f(xyz.x / w.x), f(xyz.y / w.y), f(xyz.z / w.z));
    DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
}

/// Gauss-Newton from `c` toward the CIELAB colour `goal`; finite-difference
/// Jacobian, steps halved while they do not reduce the residual.
fn gauss_newton(mut c: [f64; 3], goal: DVec3) -> [f64; 3] {
    let residual = |c: [f64; 3]| lab(xyz_of(c)) - goal;
    let mut r = residual(c);
    for _ in 0..40 {
        if r.length() < 1e-9 {
            break;
        }
        let h = 1e-6;
        let mut cols = [DVec3::ZERO; 3];
        for (k, col) in cols.iter_mut().enumerate() {
            let mut d = c;
            d[k] += h;
            *col = (residual(d) - r) / h;
        }
        let j = DMat3::from_cols(cols[0], cols[1], cols[2]);
        if j.determinant().abs() < 1e-300 {
            break;
        }
        let delta = j.inverse() * -r;
        let mut lambda = 1.0;
        let mut improved = false;
        while lambda > 1e-4 {
            let trial = [c[0] + lambda * delta.x, c[1] + lambda * delta.y, c[2] + lambda * delta.z];
            let rt = residual(trial);
            if rt.length() < r.length() && trial.iter().all(|x| x.is_finite()) {
                (c, r, improved) = (trial, rt, true);
                break;
            }
            lambda *= 0.5;
        }
        if !improved {
            break;
        }
    }
    c
}

/// The emission spectrum of linear sRGB radiance `rgb` (any brightness):
/// `scale` × `shape`(λ) × D65(λ) / Y(D65).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbIlluminant {
    /// Twice the largest component.
    pub scale: f64,
    /// The fitted shape, in (0, 1).
    pub shape: RgbSpectrum,
}

impl RgbIlluminant {
    /// Fits `rgb` (components >= 0).
    pub fn fit(rgb: DVec3) -> RgbIlluminant {
        let m = rgb.max_element();
        if m.is_nan() || m <= 0.0 {
            return RgbIlluminant { scale: 0.0, shape: RgbSpectrum::Flat(0.0) };
        }
        let scale = 2.0 * m;
        RgbIlluminant { scale, shape: RgbSpectrum::fit(rgb / scale) }
    }

    /// The radiance at `nm`.
    #[inline]
    pub fn at(&self, nm: f64) -> f64 {
        self.scale * self.shape.at(nm) * d65_normalised(nm)
    }
}

/// Entries across each side of the illuminant table.
const TABLE: usize = 32;

/// RGB radiance to spectrum through a table (for images, whose every pixel
/// would otherwise need a fit): an illuminant's fitted colour always has
/// largest component 1/2, so the table is two-dimensional for each choice
/// of largest channel: the other two as fractions of it on a 32 x 32 grid,
/// coefficients interpolated bilinearly. Built on first use (3,072 fits,
/// each started from its neighbour's solution).
pub fn illuminant_from_table(rgb: DVec3) -> RgbIlluminant {
    let m = rgb.max_element();
    if m.is_nan() || m <= 0.0 {
        return RgbIlluminant { scale: 0.0, shape: RgbSpectrum::Flat(0.0) };
    }
    let l = if rgb.x == m {
        0
    } else if rgb.y == m {
        1
    } else {
        2
    };
    let (a, b) = others(rgb / m, l);
    let f = |v: f64| {
        let x = v.clamp(0.0, 1.0) * (TABLE - 1) as f64;
        let i = (x as usize).min(TABLE - 2);
        (i, x - i as f64)
    };
    let ((i, fx), (j, fy)) = (f(a), f(b));
    let t = &table()[l];
    let at = |i: usize, j: usize| t[j * TABLE + i];
    let mut c = [0.0; 3];
    for (k, ck) in c.iter_mut().enumerate() {
        let lo = at(i, j)[k] * (1.0 - fx) + at(i + 1, j)[k] * fx;
        let hi = at(i, j + 1)[k] * (1.0 - fx) + at(i + 1, j + 1)[k] * fx;
        *ck = lo * (1.0 - fy) + hi * fy;
    }
    RgbIlluminant { scale: 2.0 * m, shape: RgbSpectrum::Sigmoid(c) }
}

/// The two channels other than `l`, in order.
fn others(c: DVec3, l: usize) -> (f64, f64) {
    match l {
        0 => (c.y, c.z),
        1 => (c.x, c.z),
        _ => (c.x, c.y),
    }
}

/// The colour with channel `l` at `top` and the others `a`, `b`.
fn with_others(top: f64, a: f64, b: f64, l: usize) -> DVec3 {
    match l {
        0 => DVec3::new(top, a, b),
        1 => DVec3::new(a, top, b),
        _ => DVec3::new(a, b, top),
    }
}

type Table = [Vec<[f64; 3]>; 3];

fn table() -> &'static Table {
    static T: OnceLock<Table> = OnceLock::new();
    T.get_or_init(|| {
        std::array::from_fn(|l| {
            let mut t = vec![[0.0; 3]; TABLE * TABLE];
            // from the grey corner (both fractions 1: flat 1/2, all
            // coefficients 0) outward, each entry from its neighbour's
            for j in (0..TABLE).rev() {
                for i in (0..TABLE).rev() {
                    if i == TABLE - 1 && j == TABLE - 1 {
                        continue;
                    }
                    let start = if i + 1 < TABLE { t[j * TABLE + i + 1] } else { t[(j + 1) * TABLE + i] };
                    let step = 1.0 / (TABLE - 1) as f64;
                    let rgb = with_others(0.5, 0.5 * i as f64 * step, 0.5 * j as f64 * step, l);
                    let goal = lab(rgb_to_xyz(rgb));
                    let c = gauss_newton(start, goal);
                    t[j * TABLE + i] = if (lab(xyz_of(c)) - goal).length() < 1e-3 {
                        c
                    } else {
                        match RgbSpectrum::fit(rgb) {
                            RgbSpectrum::Sigmoid(c) => c,
                            RgbSpectrum::Flat(_) => [0.0; 3],
                        }
                    };
                }
            }
            t
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::cie::xyz_to_rgb;

    #[test]
    fn greys_round_trip_exactly() {
        for g in [0.0, 0.18, 0.5, 0.8, 1.0] {
            let s = RgbSpectrum::fit(DVec3::splat(g));
            let back = s.rgb();
            assert!((back - DVec3::splat(g)).abs().max_element() < 1e-12, "{g}: {back}");
        }
    }

    #[test]
    fn colours_inside_the_gamut_round_trip() {
        // a grid over the sRGB cube away from its most saturated corners
        let mut worst: f64 = 0.0;
        for r in [0.05, 0.3, 0.6, 0.9] {
            for g in [0.05, 0.3, 0.6, 0.9] {
                for b in [0.05, 0.3, 0.6, 0.9] {
                    let c = DVec3::new(r, g, b);
                    let back = RgbSpectrum::fit(c).rgb();
                    worst = worst.max((back - c).abs().max_element());
                }
            }
        }
        assert!(worst < 1e-6, "worst round-trip error {worst}");
    }

    #[test]
    fn the_illuminant_table_is_close_to_the_fit() {
        let mut worst: f64 = 0.0;
        for c in [DVec3::new(3.0, 1.0, 0.2), DVec3::new(0.1, 0.5, 0.45), DVec3::new(0.7, 0.7, 1.4), DVec3::ONE] {
            let e = illuminant_from_table(c);
            let back = xyz_to_rgb(crate::spectrum::cie::spectrum_to_xyz(|l| e.at(l)));
            worst = worst.max(((back - c) / c.max_element()).abs().max_element());
        }
        assert!(worst < 2e-3, "worst relative error {worst}");
    }

    /// The round trip over the whole sRGB cube (11^3 colours, the corners
    /// included): the numbers docs/rendering.md quotes.
    #[test]
    fn the_round_trip_over_the_srgb_cube() {
        let (mut worst_rgb, mut worst_de, mut sum_de, mut n, mut exact) = (0.0f64, 0.0f64, 0.0, 0, 0);
        for r in 0..=10 {
            for g in 0..=10 {
                for b in 0..=10 {
                    let c = DVec3::new(r as f64, g as f64, b as f64) / 10.0;
                    let back = RgbSpectrum::fit(c).rgb();
                    let de = (lab(rgb_to_xyz(back)) - lab(rgb_to_xyz(c))).length();
                    worst_rgb = worst_rgb.max((back - c).abs().max_element());
                    worst_de = worst_de.max(de);
                    sum_de += de;
                    n += 1;
                    exact += usize::from(de < 1e-6);
                }
            }
        }
        eprintln!(
            "sRGB cube round trip: {exact} of {n} within dE 1e-6, mean dE {:.1e}, worst dE {worst_de:.1e}, worst linear-RGB error {worst_rgb:.1e}",
            sum_de / n as f64
        );
        // the model reaches the whole sRGB gamut, its corners included
        assert!(exact == n && worst_rgb < 1e-6, "{exact} of {n}, worst {worst_rgb}");
    }

    #[test]
    fn white_light_is_d65() {
        let e = RgbIlluminant::fit(DVec3::ONE);
        for nm in [400.0, 555.0, 700.0] {
            assert!((e.at(nm) - d65_normalised(nm)).abs() < 1e-15);
        }
        let back = xyz_to_rgb(crate::spectrum::cie::spectrum_to_xyz(|l| e.at(l)));
        assert!((back - DVec3::ONE).abs().max_element() < 1e-12);
    }
}

#[cfg(test)]
mod timing {
    #[test]
    #[ignore]
    fn fit_time() {
        let t = std::time::Instant::now();
        let mut n = 0;
        for i in 0..10 {
            for j in 0..10 {
                let c = glam::DVec3::new(0.05 + 0.09 * i as f64, 0.9 - 0.08 * j as f64, 0.4);
                let _ = super::RgbSpectrum::fit(c);
                n += 1;
            }
        }
        eprintln!("{} us per fit", t.elapsed().as_secs_f64() * 1e6 / n as f64);
    }
}
