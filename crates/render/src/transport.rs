//! What a path carries: three RGB channels, or a value at each of its
//! wavelengths. The integrator, materials and lights are written once over
//! [`Transport`]; an RGB render monomorphises to the plain RGB code and
//! pays nothing for spectra.

use crate::spectrum::cie::{self, MAX_NM, MIN_NM};
use crate::spectrum::sampled::N;
use crate::spectrum::{Colour, Radiance, SampledSpectrum, SampledWavelengths};
use glam::DVec3;
use lens::glass::PreparedIndex;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign};
use std::sync::Arc;

/// The channels a path carries.
pub trait Channels:
    Copy + Add<Output = Self> + AddAssign + Mul<Output = Self> + MulAssign + Mul<f64, Output = Self> + MulAssign<f64>
where
    Self: Div<f64, Output = Self>,
{
    /// All zero.
    const ZERO: Self;
    /// All one.
    const ONE: Self;
    /// The largest channel.
    fn max_channel(&self) -> f64;
    /// `self` (1 - t) + `o` t.
    fn mix(self, o: Self, t: f64) -> Self {
        self * (1.0 - t) + o * t
    }
}

impl Channels for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    const ONE: Self = DVec3::ONE;
    fn max_channel(&self) -> f64 {
        self.max_element()
    }
}

impl Channels for SampledSpectrum {
    const ZERO: Self = SampledSpectrum([0.0; N]);
    const ONE: Self = SampledSpectrum([1.0; N]);
    fn max_channel(&self) -> f64 {
        self.max_element()
    }
}

/// A refracting medium: a constant index, or a catalogue glass.
#[derive(Debug, Clone, PartialEq)]
pub struct Medium {
    /// The index an RGB render uses: the constant, or the glass's index at
    /// the d line (587.56 nm).
    pub ior: f64,
    /// The glass, when its index depends on wavelength.
    pub glass: Option<Arc<PreparedIndex>>,
}

/// How a path's channels are evaluated.
pub trait Transport {
    /// The channels.
    type Value: Channels;
    /// A surface colour.
    fn reflectance(&self, c: &Colour) -> Self::Value;
    /// An emitted radiance.
    fn radiance(&self, r: &Radiance) -> Self::Value;
    /// Linear sRGB radiance from an image (an environment map).
    fn rgb_radiance(&self, rgb: DVec3) -> Self::Value;
    /// The index of `m` along this path. A glass sends each wavelength its
    /// own way: the path keeps its hero wavelength only.
    fn ior(&mut self, m: &Medium) -> f64;
}

/// Three linear sRGB channels.
#[derive(Debug, Clone, Copy, Default)]
pub struct Rgb;

impl Transport for Rgb {
    type Value = DVec3;
    #[inline]
    fn reflectance(&self, c: &Colour) -> DVec3 {
        c.rgb()
    }
    #[inline]
    fn radiance(&self, r: &Radiance) -> DVec3 {
        r.to_rgb()
    }
    #[inline]
    fn rgb_radiance(&self, rgb: DVec3) -> DVec3 {
        rgb
    }
    #[inline]
    fn ior(&mut self, m: &Medium) -> f64 {
        m.ior
    }
}

/// A value at each of the path's wavelengths.
#[derive(Debug, Clone, Copy)]
pub struct Spectral {
    /// The wavelengths and their densities.
    pub wavelengths: SampledWavelengths,
    /// Per wavelength: its place in the fitted spectra's range, (λ - 360)
    /// / 470, and D65 there (luminance 1): computed once per path, used at
    /// every surface and light it meets.
    t: [f64; N],
    d65: [f64; N],
}

impl Spectral {
    /// A path carrying `wavelengths`.
    pub fn new(wavelengths: SampledWavelengths) -> Self {
        let nm = wavelengths.nm;
        let table = cie::d65_normalised_table();
        let (mut t, mut d65) = ([0.0; N], [0.0; N]);
        for j in 0..N {
            t[j] = (nm[j] - MIN_NM) / (MAX_NM - MIN_NM);
            d65[j] = cie::d65_normalised_with(table, nm[j]);
        }
        Spectral { wavelengths, t, d65 }
    }

    /// How many wavelengths are live: four, or the hero alone.
    #[inline]
    fn lanes(&self) -> usize {
        if self.wavelengths.secondary_terminated() {
            1
        } else {
            N
        }
    }

    /// `f(j)` for each live wavelength j, 0 for the others.
    #[inline]
    fn per_lane(&self, f: impl Fn(usize) -> f64) -> SampledSpectrum {
        let mut v = [0.0; N];
        for (j, vj) in v.iter_mut().enumerate().take(self.lanes()) {
            *vj = f(j);
        }
        SampledSpectrum(v)
    }
}

impl Transport for Spectral {
    type Value = SampledSpectrum;
    #[inline]
    fn reflectance(&self, c: &Colour) -> SampledSpectrum {
        let s = c.spectrum();
        self.per_lane(|j| s.at_t(self.t[j]))
    }
    #[inline]
    fn radiance(&self, r: &Radiance) -> SampledSpectrum {
        match r.rgb_illuminant() {
            Some(e) => self.per_lane(|j| e.scale * e.shape.at_t(self.t[j]) * self.d65[j]),
            None => self.per_lane(|j| r.at(self.wavelengths.nm[j])),
        }
    }
    fn rgb_radiance(&self, rgb: DVec3) -> SampledSpectrum {
        let e = crate::spectrum::upsample::illuminant_from_table(rgb);
        self.per_lane(|j| e.scale * e.shape.at_t(self.t[j]) * self.d65[j])
    }
    fn ior(&mut self, m: &Medium) -> f64 {
        match &m.glass {
            None => m.ior,
            Some(g) => {
                self.wavelengths.terminate_secondary();
                // the render's range lies inside every glass's data
                g.index(self.wavelengths.hero()).unwrap_or(m.ior)
            }
        }
    }
}
