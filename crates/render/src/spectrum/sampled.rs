//! Hero-wavelength sampling (Wilkie, Nawaz, Droske, Weidlich and Hanika,
//! "Hero Wavelength Spectral Sampling", EGSR 2014): each camera path
//! carries four wavelengths, a hero drawn by the sampler and three more at
//! equal steps of the sampling distribution's CDF from it, and a value per
//! wavelength ([`SampledSpectrum`]).
//!
//! Wavelengths are drawn from a density designed for these four-point
//! rules (see [`WavelengthRange`]): with it, one path's four wavelengths
//! estimate the colour of white light within 2% (RMS over paths; 20% when
//! drawn in proportion to the length of the sRGB colour-matching
//! functions), so defocused white highlights carry almost no colour noise.
//!
//! Where only one wavelength can follow a path (a dispersive lens or
//! material sends each wavelength its own way), the three others are
//! terminated and the hero's density divided by four, so the estimate stays
//! unbiased (pbrt-v4's `TerminateSecondary`).

use super::cie::cmf;
use super::hero_density::HERO_DENSITY;
use super::tables::FIRST_NM;
use glam::DVec3;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign};
use std::sync::Arc;

/// Wavelengths per path.
pub const N: usize = 4;

/// Segments of the tabulated inverse CDF.
const SEGMENTS: usize = 1024;

/// The wavelength distribution over a range, nm: `HERO_DENSITY`
/// (tools/hero_density.py), restricted to the range. That density is chosen
/// so that a path's hero and companions, at quarter steps of its CDF, make
/// a four-point rule that is nearly exact for the colour of smooth spectra:
/// each path's estimate of white light (D65) is within 2.1% RMS of its
/// colour, of smooth colours under it within 5% (against 20% and 29%
/// drawing in proportion to the length of the sRGB colour-matching
/// functions, the density before). It is at least 1% of its peak
/// everywhere, so every wavelength of the range keeps a chance. Its inverse CDF is tabulated at 1,024 equal
/// steps of probability and linear between them, so a draw is a lookup and
/// the density is constant over each step: the exact density of the draws.
#[derive(Debug, Clone, PartialEq)]
pub struct WavelengthRange {
    /// Wavelength at CDF value k / 1024, k = 0..=1024.
    nm: Arc<[f64]>,
    /// The density over step k, 1/nm: `1 / (1024 (nm[k + 1] - nm[k]))`.
    pdf: Arc<[f64]>,
}

impl WavelengthRange {
    /// Wavelengths drawn over `lo..hi` nm (`lo < hi`).
    pub fn new(lo: f64, hi: f64) -> Self {
        let density = |l: f64| {
            let x = (l - FIRST_NM).clamp(0.0, (HERO_DENSITY.len() - 1) as f64);
            let i = (x as usize).min(HERO_DENSITY.len() - 2);
            HERO_DENSITY[i] + (x - i as f64) * (HERO_DENSITY[i + 1] - HERO_DENSITY[i])
        };
        // the CDF on a fine grid (trapezoids), then inverted at each step
        let n = 47_000;
        let at = |i: usize| lo + (hi - lo) * i as f64 / n as f64;
        let mut cdf = vec![0.0; n + 1];
        for i in 0..n {
            cdf[i + 1] = cdf[i] + 0.5 * (density(at(i)) + density(at(i + 1))) * (at(i + 1) - at(i));
        }
        let total = cdf[n];
        let nm = (0..=SEGMENTS)
            .map(|k| {
                let target = total * k as f64 / SEGMENTS as f64;
                let i = cdf.partition_point(|c| *c < target).clamp(1, n);
                let (c0, c1) = (cdf[i - 1], cdf[i]);
                let f = if c1 > c0 { (target - c0) / (c1 - c0) } else { 0.0 };
                (at(i - 1) + f * (at(i) - at(i - 1))).clamp(lo, hi)
            })
            .collect::<Vec<f64>>();
        let pdf: Vec<f64> = nm.windows(2).map(|p| 1.0 / (SEGMENTS as f64 * (p[1] - p[0]))).collect();
        WavelengthRange { nm: nm.into(), pdf: pdf.into() }
    }

    /// The range, nm.
    pub fn nm(&self) -> [f64; 2] {
        [self.nm[0], self.nm[SEGMENTS]]
    }

    /// The wavelength at CDF value `u` in [0, 1), and its density, 1/nm.
    #[inline]
    pub fn sample(&self, u: f64) -> (f64, f64) {
        let x = u.clamp(0.0, 1.0) * SEGMENTS as f64;
        let k = (x as usize).min(SEGMENTS - 1);
        let (a, b) = (self.nm[k], self.nm[k + 1]);
        (a + (x - k as f64) * (b - a), self.pdf[k])
    }

    /// The density of [`Self::sample`] at `nm`, 1/nm (0 outside the range).
    pub fn pdf(&self, nm: f64) -> f64 {
        if !(nm >= self.nm[0] && nm <= self.nm[SEGMENTS]) {
            return 0.0;
        }
        let k = self.nm.partition_point(|x| *x <= nm).clamp(1, SEGMENTS) - 1;
        self.pdf[k]
    }

    /// A hero and three companions from the uniform `u`: the companions at
    /// steps of 1/4 of the CDF from the hero.
    #[inline]
    pub fn sample_four(&self, u: f64) -> SampledWavelengths {
        let mut nm = [0.0; N];
        let mut pdf = [0.0; N];
        for j in 0..N {
            // (u + j / N).fract() for u in [0, 1), without a call
            let v = u + j as f64 / N as f64;
            (nm[j], pdf[j]) = self.sample(if v >= 1.0 { v - 1.0 } else { v });
        }
        SampledWavelengths { nm, pdf, terminated: false }
    }
}

/// The wavelengths of one path and the densities they were drawn with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths, nm; the first is the hero.
    pub nm: [f64; N],
    /// Densities, 1/nm (each wavelength's marginal density).
    pub pdf: [f64; N],
    /// Whether only the hero follows the path.
    terminated: bool,
}

impl SampledWavelengths {
    /// One wavelength only, for a monochromatic render (density 1: its
    /// value is reported as is).
    pub fn single(nm: f64) -> Self {
        SampledWavelengths { nm: [nm; N], pdf: [1.0; N], terminated: true }
    }

    /// The hero wavelength, nm.
    pub fn hero(&self) -> f64 {
        self.nm[0]
    }

    /// Whether the companions have been terminated.
    #[inline]
    pub fn secondary_terminated(&self) -> bool {
        self.terminated
    }

    /// Ends the companions: only the hero follows the path from here, and
    /// the estimate is the hero's alone (its value over its density).
    pub fn terminate_secondary(&mut self) {
        self.terminated = true;
    }

    /// The XYZ estimate (times ∫ȳ) of the radiance `l` at these
    /// wavelengths: the average over the wavelengths of l x̄ / pdf, or the
    /// hero's alone once the others are terminated.
    pub fn xyz(&self, l: SampledSpectrum) -> DVec3 {
        if self.terminated {
            return cmf(self.nm[0]) * (l.0[0] / self.pdf[0]);
        }
        let mut sum = DVec3::ZERO;
        for j in 0..N {
            if l.0[j] != 0.0 {
                sum += cmf(self.nm[j]) * (l.0[j] / self.pdf[j]);
            }
        }
        sum / N as f64
    }
}

/// A value at each of a path's four wavelengths.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SampledSpectrum(pub [f64; N]);

impl SampledSpectrum {
    /// The same value at every wavelength.
    pub fn splat(v: f64) -> Self {
        SampledSpectrum([v; N])
    }

    /// The largest value.
    pub fn max_element(&self) -> f64 {
        self.0.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
}

impl Add for SampledSpectrum {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        SampledSpectrum(std::array::from_fn(|j| self.0[j] + o.0[j]))
    }
}

impl AddAssign for SampledSpectrum {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Mul for SampledSpectrum {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        SampledSpectrum(std::array::from_fn(|j| self.0[j] * o.0[j]))
    }
}

impl MulAssign for SampledSpectrum {
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl Mul<f64> for SampledSpectrum {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        SampledSpectrum(self.0.map(|v| v * k))
    }
}

impl MulAssign<f64> for SampledSpectrum {
    fn mul_assign(&mut self, k: f64) {
        *self = *self * k;
    }
}

impl Div<f64> for SampledSpectrum {
    type Output = Self;
    fn div(self, k: f64) -> Self {
        SampledSpectrum(self.0.map(|v| v / k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::cie::{d65, illuminant_a, xyz_to_rgb};

    #[test]
    fn the_density_integrates_to_one_and_is_the_designed_one() {
        let r = WavelengthRange::new(360.0, 830.0);
        let n = 47_000;
        let total: f64 = (0..n).map(|i| r.pdf(360.0 + (i as f64 + 0.5) * 470.0 / n as f64) * 470.0 / n as f64).sum();
        // (a midpoint sum across the table's steps: exact but for the steps
        // the grid straddles)
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        // the table follows the density it tabulates to 1% where it is
        // smooth
        let w = |l: f64| HERO_DENSITY[(l - FIRST_NM) as usize];
        for (a, b) in [(450.0, 550.0), (520.0, 610.0), (600.0, 650.0)] {
            let (ra, rb) = (r.pdf(a) / r.pdf(b), w(a) / w(b));
            assert!((ra / rb - 1.0).abs() < 0.01, "{a}/{b}: {ra} vs {rb}");
        }
        // and the floor keeps the far ends alive
        assert!(HERO_DENSITY.iter().all(|d| *d >= 0.01 - 1e-9));
        assert!(r.pdf(365.0) > 0.0 && r.pdf(825.0) > 0.0);
    }

    /// The RMS over paths of one path's linear-sRGB error for the spectrum
    /// `s`, relative to the length of its true value.
    fn four_point_error(r: &WavelengthRange, s: impl Fn(f64) -> f64) -> f64 {
        let [lo, hi] = r.nm();
        let n = 20_000;
        let h = (hi - lo) / n as f64;
        let truth = xyz_to_rgb((0..n).map(|i| lo + (i as f64 + 0.5) * h).map(|l| cmf(l) * s(l) * h).sum::<DVec3>());
        let paths = 4096;
        let mse = (0..paths)
            .map(|k| {
                let w = r.sample_four((k as f64 + 0.5) / paths as f64);
                let l = SampledSpectrum(w.nm.map(&s));
                (xyz_to_rgb(w.xyz(l)) - truth).length_squared()
            })
            .sum::<f64>()
            / paths as f64;
        (mse / truth.length_squared()).sqrt()
    }

    #[test]
    fn four_wavelengths_give_the_colour_of_white_light_within_three_percent() {
        // the designed density's purpose: the colour noise of each path
        // (2.1% for D65, 7% for illuminant A over 360-830 nm; drawing in
        // proportion to the sRGB functions' length, 20% for D65)
        for (lo, hi) in [(360.0, 830.0), (370.0, 830.0), (400.0, 700.0)] {
            let r = WavelengthRange::new(lo, hi);
            let white = four_point_error(&r, d65);
            assert!(white < 0.027, "D65 over {lo}-{hi} nm: {white}");
            let a = four_point_error(&r, illuminant_a);
            assert!(a < 0.08, "illuminant A over {lo}-{hi} nm: {a}");
        }
    }

    #[test]
    fn a_truncated_range_stays_inside() {
        let r = WavelengthRange::new(400.0, 700.0);
        for i in 0..100 {
            let (l, p) = r.sample(i as f64 / 100.0);
            assert_eq!(p, r.pdf(l));
            assert!((400.0..=700.0).contains(&l));
        }
        assert_eq!(r.pdf(399.0), 0.0);
    }

    #[test]
    fn terminating_keeps_the_hero_unbiased() {
        let r = WavelengthRange::new(360.0, 830.0);
        let mut w = r.sample_four(0.3);
        let flat = SampledSpectrum::splat(1.0);
        let hero_alone = cmf(w.hero()) / w.pdf[0];
        w.terminate_secondary();
        assert!(w.secondary_terminated());
        assert!((w.xyz(flat) - hero_alone).length() < 1e-12);
    }
}
