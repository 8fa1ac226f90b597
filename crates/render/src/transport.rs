//! What a path carries: three RGB channels, or a value at each of its
//! wavelengths. The integrator, materials and lights are written once over
//! [`Transport`]; an RGB render monomorphises to the plain RGB code and
//! pays nothing for spectra.

use crate::spectrum::{Colour, Radiance, SampledSpectrum, SampledWavelengths};
use glam::DVec3;
use lens::glass::Glass;
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
    const ZERO: Self = SampledSpectrum([0.0; 4]);
    const ONE: Self = SampledSpectrum([1.0; 4]);
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
    pub glass: Option<Arc<Glass>>,
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
}

impl Transport for Spectral {
    type Value = SampledSpectrum;
    #[inline]
    fn reflectance(&self, c: &Colour) -> SampledSpectrum {
        let s = c.spectrum();
        SampledSpectrum::of(&self.wavelengths, |l| s.at(l))
    }
    #[inline]
    fn radiance(&self, r: &Radiance) -> SampledSpectrum {
        SampledSpectrum::of(&self.wavelengths, |l| r.at(l))
    }
    fn rgb_radiance(&self, rgb: DVec3) -> SampledSpectrum {
        let e = crate::spectrum::upsample::illuminant_from_table(rgb);
        SampledSpectrum::of(&self.wavelengths, |l| e.at(l))
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
