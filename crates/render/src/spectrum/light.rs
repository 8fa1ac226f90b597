//! Emitted radiance (area lights, point-light intensity, backgrounds),
//! given as linear sRGB or as a spectrum: a black body at a temperature, or
//! the CIE illuminants D65 and A. A spectrum is scaled to the luminance Y
//! asked for, so `{"illuminant": "D65", "luminance": 2}` is as bright as
//! RGB [2, 2, 2]. An RGB render uses the spectrum's sRGB colour (negative
//! components, outside the gamut, clamped to 0).

use super::cie::{d65_normalised, illuminant_a, planck, spectrum_to_xyz, xyz_to_rgb};
use super::upsample::RgbIlluminant;
use glam::DVec3;
use std::sync::OnceLock;

/// What a light emits.
#[derive(Debug, Clone, PartialEq)]
pub struct Radiance {
    rgb: DVec3,
    kind: Kind,
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// RGB, upsampled on first spectral use.
    Rgb(OnceLock<RgbIlluminant>),
    /// `scale` × Planck(λ, kelvin).
    Blackbody { kelvin: f64, scale: f64 },
    /// `scale` × D65(λ).
    D65 { scale: f64 },
    /// `scale` × A(λ).
    A { scale: f64 },
}

/// A named CIE illuminant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Illuminant {
    /// Daylight, 6504 K.
    D65,
    /// Incandescent (tungsten), 2856 K.
    A,
}

impl Radiance {
    /// Linear sRGB radiance (components >= 0).
    pub fn rgb(rgb: DVec3) -> Self {
        Radiance { rgb, kind: Kind::Rgb(OnceLock::new()) }
    }

    /// A black body at `kelvin`, scaled to luminance `luminance`.
    pub fn blackbody(kelvin: f64, luminance: f64) -> Self {
        let y = spectrum_to_xyz(|l| planck(l, kelvin)).y;
        let scale = luminance / y;
        Self::spectral(Kind::Blackbody { kelvin, scale })
    }

    /// A CIE illuminant scaled to luminance `luminance`.
    pub fn illuminant(which: Illuminant, luminance: f64) -> Self {
        match which {
            Illuminant::D65 => Self::spectral(Kind::D65 { scale: luminance }),
            Illuminant::A => {
                let y = spectrum_to_xyz(illuminant_a).y;
                Self::spectral(Kind::A { scale: luminance / y })
            }
        }
    }

    fn spectral(kind: Kind) -> Self {
        let mut r = Radiance { rgb: DVec3::ZERO, kind };
        r.rgb = xyz_to_rgb(spectrum_to_xyz(|l| r.at(l))).max(DVec3::ZERO);
        r
    }

    /// Whether it was given as a spectrum (a scene with one renders
    /// spectrally).
    pub fn is_spectral(&self) -> bool {
        !matches!(self.kind, Kind::Rgb(_))
    }

    /// Linear sRGB, for RGB renders.
    #[inline]
    pub fn to_rgb(&self) -> DVec3 {
        self.rgb
    }

    /// Whether it emits nothing.
    pub fn is_black(&self) -> bool {
        self.rgb == DVec3::ZERO
    }

    /// The radiance at `nm`.
    #[inline]
    pub fn at(&self, nm: f64) -> f64 {
        match &self.kind {
            Kind::Rgb(fit) => fit.get_or_init(|| RgbIlluminant::fit(self.rgb)).at(nm),
            Kind::Blackbody { kelvin, scale } => scale * planck(nm, *kelvin),
            Kind::D65 { scale } => scale * d65_normalised(nm),
            Kind::A { scale } => scale * illuminant_a(nm),
        }
    }

    /// The fitted illuminant of an RGB radiance (fitted on first use);
    /// `None` for one given as a spectrum.
    #[inline]
    pub fn rgb_illuminant(&self) -> Option<&RgbIlluminant> {
        match &self.kind {
            Kind::Rgb(fit) => Some(fit.get_or_init(|| RgbIlluminant::fit(self.rgb))),
            _ => None,
        }
    }

    /// Multiplied by `k` >= 0 (an environment's intensity).
    pub fn scaled(&self, k: f64) -> Self {
        let kind = match &self.kind {
            Kind::Rgb(_) => return Radiance::rgb(self.rgb * k),
            Kind::Blackbody { kelvin, scale } => Kind::Blackbody { kelvin: *kelvin, scale: scale * k },
            Kind::D65 { scale } => Kind::D65 { scale: scale * k },
            Kind::A { scale } => Kind::A { scale: scale * k },
        };
        Radiance { rgb: self.rgb * k, kind }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectral_lights_have_the_luminance_asked_for() {
        for r in [
            Radiance::blackbody(3200.0, 2.0),
            Radiance::illuminant(Illuminant::A, 2.0),
            Radiance::illuminant(Illuminant::D65, 2.0),
        ] {
            let y = spectrum_to_xyz(|l| r.at(l)).y;
            assert!((y - 2.0).abs() < 1e-12, "{r:?}: Y = {y}");
        }
        // D65 is RGB white
        let w = Radiance::illuminant(Illuminant::D65, 1.0).to_rgb();
        assert!((w - DVec3::ONE).abs().max_element() < 1e-12);
        // tungsten is orange: red above blue
        let a = Radiance::illuminant(Illuminant::A, 1.0).to_rgb();
        assert!(a.x > a.y && a.y > a.z, "{a}");
    }
}
