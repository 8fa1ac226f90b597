//! The flare's colour: the bands it is drawn at, each band's colour
//! weight, and the finer bands a ghost that dispersion spreads is drawn
//! at instead.

use super::WAVELENGTHS;
use crate::scene::ColourMode;
use crate::spectrum::cie;
use glam::DVec3;
use lens::coating::ReflectanceTable;
use lens::{Prescription, Tracer};
use rayon::prelude::*;
use std::sync::Arc;

/// The flare's wavelengths and each one's colour weight (linear sRGB per
/// unit radiance): [`WAVELENGTHS`] bands over 400-700 nm ([`bands`]); or
/// the one wavelength of a monochromatic render (grey, weight 1).
pub(super) fn wavelengths(colour: &ColourMode) -> (Vec<f64>, Vec<DVec3>) {
    if let ColourMode::Monochromatic(nm) = colour {
        return (vec![*nm], vec![DVec3::ONE]);
    }
    bands(WAVELENGTHS)
}

/// `n` equal bands over 400-700 nm: their midpoints and each one's colour
/// weight (linear sRGB per unit radiance), each channel scaled so that a
/// flat spectrum of 1 gives the colour of the colour matching functions
/// summed over every nanometre of the range (normalised to luminance 1):
/// the same white for any number of bands, so that a ghost drawn at finer
/// bands changes colour only where its spectrum does.
fn bands(n: usize) -> (Vec<f64>, Vec<DVec3>) {
    let band = 300.0 / n as f64;
    let nms: Vec<f64> = (0..n).map(|k| 400.0 + (k as f64 + 0.5) * band).collect();
    let rgb = |nms: &[f64]| -> Vec<DVec3> {
        let y: f64 = nms.iter().map(|&nm| cie::cmf(nm).y).sum();
        nms.iter().map(|&nm| cie::xyz_to_rgb(cie::cmf(nm) / y)).collect()
    };
    let every: Vec<f64> = (0..300).map(|k| 400.5 + k as f64).collect();
    let white: DVec3 = rgb(&every).iter().sum();
    let colours = rgb(&nms);
    let sum: DVec3 = colours.iter().sum();
    let scale = white / sum;
    (nms, colours.into_iter().map(|c| c * scale).collect())
}

/// Bands each of the flare's wavelengths is cut into where a ghost's
/// copies at those wavelengths lie apart ([`dispersed`]): its colours then
/// run along it as a spectrum does, not in [`WAVELENGTHS`] steps. Odd, so
/// that the middle one is the band's own wavelength (its image is drawn
/// already): each such ghost costs `WAVELENGTHS * (FINE - 1)` images more.
pub const FINE: usize = 3;
const _: () = assert!(FINE % 2 == 1);

/// The [`FINE`] bands of each flare band (their midpoints and colours)
/// with the lens at each and its coatings' reflectance table.
pub(super) struct FineBands {
    pub(super) nms: Vec<f64>,
    pub(super) colours: Vec<DVec3>,
    pub(super) lenses: Vec<Prescription>,
    pub(super) tables: Vec<Arc<ReflectanceTable>>,
}

impl FineBands {
    /// `fine` (odd) bands in each of the flare's, through `p`.
    pub(super) fn new(p: &Prescription, fine: usize) -> Self {
        let (nms, colours) = bands(WAVELENGTHS * fine);
        let lenses: Vec<Prescription> =
            nms.iter().map(|&nm| p.at_wavelength(nm).unwrap_or_else(|_| p.clone())).collect();
        let tables = lenses.par_iter().map(|l| Arc::new(Tracer::forward(l).reflectance_table())).collect();
        FineBands { nms, colours, lenses, tables }
    }
}

/// Whether a ghost's images at neighbouring flare wavelengths (`images`,
/// each on one grid, `None` where the path does not exist) lie apart:
/// squared (which weighs the bright parts: a caustic's line rather than
/// the glow around it) and normalised to 1, less than [`OVERLAP`] in
/// common (the sum over pixels of the smaller). Dispersion moves a small
/// ghost, a thin caustic or one focused near the film by more than its
/// width between bands 75 nm apart; drawn at those wavelengths alone it
/// would be [`WAVELENGTHS`] coloured copies. A large ghost moved by a
/// fraction of its size keeps most in common.
pub(super) fn dispersed(images: &[Option<Vec<f64>>]) -> bool {
    let unit = |img: &Vec<f64>| -> Option<Vec<f64>> {
        let total: f64 = img.iter().map(|v| v * v).sum();
        (total > 0.0).then(|| img.iter().map(|v| v * v / total).collect())
    };
    let units: Vec<Option<Vec<f64>>> = images.iter().map(|i| i.as_ref().and_then(unit)).collect();
    units.windows(2).any(|w| match (&w[0], &w[1]) {
        (Some(a), Some(b)) => a.iter().zip(b).map(|(x, y)| x.min(*y)).sum::<f64>() < OVERLAP,
        _ => false,
    })
}

/// What two neighbouring bands' images of a ghost (squared, each
/// normalised to 1) must have in common for it to be drawn at those bands
/// alone: at 0.5 a caustic line split in four stayed so.
pub const OVERLAP: f64 = 0.7;

/// `values` (at the increasing wavelengths `nms`) at `nm`: linear between
/// them, the end value beyond them.
pub(super) fn interpolate(nms: &[f64], values: &[f64], nm: f64) -> f64 {
    let k = nms.partition_point(|&x| x < nm);
    if k == 0 {
        return values[0];
    }
    if k == nms.len() {
        return values[nms.len() - 1];
    }
    let f = (nm - nms[k - 1]) / (nms[k] - nms[k - 1]);
    values[k - 1] + f * (values[k] - values[k - 1])
}

#[cfg(test)]
mod tests {
    use super::super::luminance;
    use super::*;
    use lens::ghost::FilmGrid;

    /// The bands of a flat spectrum of 1 add up to the same white of
    /// luminance 1, four of them or twelve or three hundred.
    #[test]
    fn a_flat_spectrum_is_the_same_white() {
        let white: DVec3 = bands(300).1.iter().sum();
        assert!((luminance(white) - 1.0).abs() < 1e-3, "{white}");
        for n in [WAVELENGTHS, WAVELENGTHS * FINE] {
            let (nms, colours) = bands(n);
            assert_eq!(nms.len(), n);
            let sum: DVec3 = colours.iter().sum();
            assert!((sum - white).abs().max_element() < 1e-12, "{n} bands: {sum} vs {white}");
        }
    }

    /// Linear between the wavelengths, the end values beyond them.
    #[test]
    fn interpolation_is_linear_and_held_at_the_ends() {
        let (nms, v) = ([437.5, 512.5, 587.5], [1.0, 3.0, 2.0]);
        assert_eq!(interpolate(&nms, &v, 400.0), 1.0);
        assert_eq!(interpolate(&nms, &v, 437.5), 1.0);
        assert!((interpolate(&nms, &v, 475.0) - 2.0).abs() < 1e-12);
        assert!((interpolate(&nms, &v, 550.0) - 2.5).abs() < 1e-12);
        assert_eq!(interpolate(&nms, &v, 700.0), 2.0);
    }

    /// Copies of a disc with less than [`OVERLAP`] of their light in
    /// common are dispersed; overlapping copies, or a band with no image,
    /// are not.
    #[test]
    fn copies_apart_are_dispersed() {
        let grid = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 0.02, nx: 200, ny: 200 };
        // a disc of radius 0.5 mm about (x, 0)
        let disc = |x: f64| -> Option<Vec<f64>> {
            Some(
                (0..200 * 200)
                    .map(|q| {
                        let c = grid.centre_of(q);
                        f64::from(u8::from((c[0] - x).powi(2) + c[1] * c[1] <= 0.25))
                    })
                    .collect(),
            )
        };
        // discs 1.2 radii apart share 28% of their area, 0.2 radii 87%
        assert!(dispersed(&[disc(0.0), disc(0.6), disc(1.2)]));
        assert!(!dispersed(&[disc(0.0), disc(0.1), disc(0.2)]));
        assert!(!dispersed(&[disc(0.0), None, disc(1.5)]));
        assert!(!dispersed(&[disc(0.0)]));
    }
}
