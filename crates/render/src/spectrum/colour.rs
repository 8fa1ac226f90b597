//! A surface colour (reflectance) as a scene gives it: linear sRGB, with
//! its spectrum fitted the first time a spectral render asks for it, so an
//! RGB render never pays for the fit.

use super::upsample::RgbSpectrum;
use glam::DVec3;
use std::sync::OnceLock;

/// A reflectance: linear sRGB in [0, 1], and its spectrum on demand.
#[derive(Debug, Clone, PartialEq)]
pub struct Colour {
    rgb: DVec3,
    spectrum: OnceLock<RgbSpectrum>,
}

impl Colour {
    /// The colour `rgb`, each component clamped to [0, 1].
    pub fn new(rgb: DVec3) -> Self {
        Colour { rgb: rgb.clamp(DVec3::ZERO, DVec3::ONE), spectrum: OnceLock::new() }
    }

    /// Linear sRGB.
    #[inline]
    pub fn rgb(&self) -> DVec3 {
        self.rgb
    }

    /// The fitted reflectance spectrum (fitted on first use).
    #[inline]
    pub fn spectrum(&self) -> &RgbSpectrum {
        self.spectrum.get_or_init(|| RgbSpectrum::fit(self.rgb))
    }
}
