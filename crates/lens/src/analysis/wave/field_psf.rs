//! The PSF of one field with the figures read from it: the wavefront and
//! its Strehl ratio, the image (FFT, Huygens, or the polychromatic sum of
//! FFT images on one grid), its centroid, and the encircled and ensquared
//! energy about the centroid beside the geometric encircled energy of the
//! same field's spot: what `lens psf` prints and the Python package's
//! `lens.psf` returns.

use super::mtf::cutoffs;
use super::psf::{fft_psf, huygens_psf, polychromatic_psf, Psf, PsfMethod};
use super::{stats, wavefront, wavefront_auto, Wavefront, WavefrontStats};
use crate::analysis::fan::ImagePlane;
use crate::analysis::pattern::Pattern;
use crate::analysis::spot::{spot_polychromatic, spot_traced};
use crate::analysis::Launcher;
use crate::error::OpticsError;
use crate::model::Prescription;

/// How to compute a field's PSF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PsfOptions {
    /// FFT or Huygens.
    pub method: PsfMethod,
    /// Samples per lambda N_w on the image plane (the FFT's padding Q), 2
    /// to 64.
    pub pad: usize,
    /// The Huygens image's pixels across, 8 to 1024.
    pub pixels: usize,
    /// The pupil grid (`None`: the default, finer where the wavefront
    /// needs it).
    pub grid: Option<usize>,
    /// Sum the prescription's wavelengths with their weights (FFT only).
    pub polychromatic: bool,
}

impl Default for PsfOptions {
    fn default() -> Self {
        PsfOptions { method: PsfMethod::Fft, pad: 4, pixels: 64, grid: None, polychromatic: false }
    }
}

/// A field's PSF and what is read from it.
#[derive(Debug, Clone)]
pub struct FieldPsf {
    /// The wavefront at the wavelength traced.
    pub wavefront: Wavefront,
    /// Its statistics (the Strehl ratio among them).
    pub stats: WavefrontStats,
    /// The image.
    pub psf: Psf,
    /// The image's intensity-weighted centroid, mm from the chief ray's
    /// image point.
    pub centroid: (f64, f64),
    /// Radii (and half-widths) of the energy curves, mm: 60 steps out to
    /// 0.45 of the image's width.
    pub radii_mm: Vec<f64>,
    /// Encircled energy about the centroid at each radius.
    pub encircled: Vec<f64>,
    /// Ensquared energy at each half-width.
    pub ensquared: Vec<f64>,
    /// The geometric encircled energy of the field's spot (48 Gauss rings)
    /// about its centroid.
    pub geometric_encircled: Vec<f64>,
    /// The (nm, weight) pairs summed, for a polychromatic PSF.
    pub wavelengths: Option<Vec<(f64, f64)>>,
}

/// The PSF of `launcher`'s field through `traced` (the prescription at the
/// wavelength analysed; `p` at its primary gives the image plane) on
/// `plane`, as `options` says.
pub fn field_psf(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
    options: &PsfOptions,
) -> Result<FieldPsf, OpticsError> {
    if !(2..=64).contains(&options.pad) {
        return Err(OpticsError::BadInput {
            name: "PSF padding (samples per lambda N_w)",
            value: options.pad as f64,
            expected: "2 to 64",
        });
    }
    if !(8..=1024).contains(&options.pixels) {
        return Err(OpticsError::BadInput {
            name: "Huygens PSF pixels across",
            value: options.pixels as f64,
            expected: "8 to 1024",
        });
    }
    if options.polychromatic && options.method == PsfMethod::Huygens {
        return Err(OpticsError::BadInput {
            name: "polychromatic Huygens PSF",
            value: 1.0,
            expected: "the FFT method: the polychromatic PSF sums FFT (Fraunhofer) images on one grid",
        });
    }
    let w = match options.grid {
        Some(n) => wavefront(p, traced, launcher, n, plane)?,
        None => wavefront_auto(p, traced, launcher, plane)?,
    };
    let s = stats(&w);
    let (ct, cs) = cutoffs(p, traced, launcher, w.image_z)?;
    let pad = options.pad as f64;
    let waves: Option<Vec<(f64, f64)>> =
        options.polychromatic.then(|| p.wavelengths_nm().iter().copied().zip(p.wavelength_weights()).collect());
    let psf = match (&waves, options.method) {
        (Some(waves), _) => {
            let mut parts = Vec::new();
            for &(nm, weight) in waves {
                let at = p.at_wavelength(nm)?;
                // each wavelength on the primary's grid: its own wavefront
                // fine enough for it
                let wl = wavefront(p, &at, launcher, w.grid.n, plane)
                    .or_else(|_| wavefront_auto(p, &at, launcher, plane))?;
                let c = cutoffs(p, &at, launcher, w.image_z)?;
                parts.push((wl, c, weight));
            }
            let refs: Vec<_> = parts.iter().map(|(wl, c, weight)| (wl, *c, *weight)).collect();
            polychromatic_psf(&refs, options.pad * w.grid.n, (1.0 / (pad * cs), 1.0 / (pad * ct)), w.chief_image)
        }
        (None, PsfMethod::Fft) => fft_psf(&w, (ct, cs), options.pad),
        (None, PsfMethod::Huygens) => huygens_psf(&w, options.pixels, (1.0 / (pad * cs), 1.0 / (pad * ct)), (ct, cs)),
    };
    let centroid = psf.centroid();
    // encircled energy out to most of the image's half-width
    let reach = 0.45 * psf.size as f64 * psf.pixel_mm.0.min(psf.pixel_mm.1);
    let radii: Vec<f64> = (1..=60).map(|k| reach * k as f64 / 60.0).collect();
    let encircled = psf.encircled_energy(centroid, &radii);
    let ensquared = psf.ensquared_energy(centroid, &radii);
    let spot = match &waves {
        Some(waves) => spot_polychromatic(p, launcher, Pattern::Gauss, 48, plane, waves)?,
        None => spot_traced(p, traced, launcher, Pattern::Gauss, 48, plane)?,
    };
    let geometric_encircled = spot.encircled_energy(&radii);
    Ok(FieldPsf {
        wavefront: w,
        stats: s,
        psf,
        centroid,
        radii_mm: radii,
        encircled,
        ensquared,
        geometric_encircled,
        wavelengths: waves,
    })
}
