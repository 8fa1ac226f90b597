//! Wave optics: the wavefront error of a field over the pupil (optical
//! path difference to the reference sphere), its statistics and Zernike
//! fits, built on the batch tracer's optical path lengths
//! (docs/analyses.md, "Wavefront").
//!
//! - [`pupil`]: the area-weighted square grid every wave analysis samples.
//! - [`opd`]: the wavefront of one field and wavelength ([`opd::wavefront`]).
//! - [`stats`]: RMS and peak-to-valley to the chief ray and to the
//!   centroid, and the Strehl ratio.
//! - [`zernike`]: Fringe and Standard Zernike polynomials and fits.
//! - [`mtf`]: the diffraction MTF by the pupil autocorrelation.
//! - [`psf`]: FFT, Huygens and matrix-Fourier PSFs; [`field_psf`]: a
//!   field's PSF with its Strehl ratio and energy curves.

mod autocorrelation;
pub mod field_psf;
pub mod mtf;
pub mod opd;
pub mod psf;
pub mod pupil;
pub mod stats;
pub mod zernike;

pub use opd::{wavefront, wavefront_auto, Wavefront};
pub use stats::{stats, WavefrontStats};

/// The pupil grid width the wave analyses use unless asked otherwise (or
/// the wavefront needs more: [`opd::wavefront_auto`]).
pub const DEFAULT_GRID: usize = 64;

/// The finest grid [`opd::wavefront_auto`] goes to on its own.
pub const MAX_AUTO_GRID: usize = 1024;
