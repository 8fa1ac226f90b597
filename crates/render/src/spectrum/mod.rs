//! Spectra for rendering with colour from the glasses: the CIE observer and
//! illuminants ([`cie`]), RGB colours upsampled to smooth spectra
//! ([`upsample`]), light spectra ([`light`]), and the wavelengths a path
//! carries ([`sampled`]). docs/rendering.md explains the pipeline.

pub mod cie;
pub mod colour;
mod hero_density;
pub mod light;
pub mod sampled;
mod tables;
pub mod upsample;

pub use colour::Colour;
pub use light::{Illuminant, Radiance};
pub use sampled::{SampledSpectrum, SampledWavelengths, WavelengthRange};
pub use upsample::{RgbIlluminant, RgbSpectrum};
