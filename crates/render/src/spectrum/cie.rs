//! Colour matching: the CIE 1931 2-degree observer, the CIE illuminants D65
//! and A, Planck's law, and spectra to XYZ and linear sRGB.
//!
//! Conventions (as pbrt-v4 uses them): a spectrum S(λ) has tristimulus
//! X = ∫ S x̄ dλ / ∫ ȳ dλ (likewise Y, Z), so a flat spectrum of 1 has
//! Y = 1. The integrals are over the tables' piecewise-linear functions,
//! 360-830 nm. Linear sRGB is the IEC 61966-2-1 matrix applied to XYZ,
//! balanced so that the D65 table itself maps to exactly (1, 1, 1) (the
//! table's white point differs from the matrix's rounded one in the fifth
//! digit).

use super::tables::{CMF_1931, D65, FIRST_NM, LAST_NM};
use glam::{DMat3, DVec3};
use std::sync::OnceLock;

/// Shortest wavelength a spectral render samples, nm.
pub const MIN_NM: f64 = FIRST_NM;
/// Longest wavelength a spectral render samples, nm.
pub const MAX_NM: f64 = LAST_NM;

/// The wavelengths a spectral render may sample through `glasses`, nm:
/// 360-830 nm, each glass extrapolated past its data where its formula has
/// an index there (the default, [`lens::glass::GlassRange::Extrapolate`]),
/// else (a table, a pole; or always under `Strict`) narrowed to its data;
/// empty when `lo >= hi`. With the warnings for the glasses extrapolated.
pub fn range_through_with<'a>(
    glasses: impl IntoIterator<Item = &'a lens::glass::Glass>,
    range: lens::glass::GlassRange,
) -> (f64, f64, Vec<lens::glass::RangeWarning>) {
    let glasses: Vec<&lens::glass::Glass> = glasses.into_iter().collect();
    let (mut lo, mut hi) = (MIN_NM, MAX_NM);
    for g in &glasses {
        if g.check_band(MIN_NM, MAX_NM, range).is_err() {
            (lo, hi) = (lo.max(g.range_nm[0]), hi.min(g.range_nm[1]));
        }
    }
    let mut warnings: Vec<lens::glass::RangeWarning> = Vec::new();
    for w in glasses.iter().flat_map(|g| [g.range_warning(lo), g.range_warning(hi)]).flatten() {
        if !warnings.contains(&w) {
            warnings.push(w);
        }
    }
    (lo, hi, warnings)
}

/// [`range_through_with`] extrapolating, without its warnings.
pub fn range_through<'a>(glasses: impl IntoIterator<Item = &'a lens::glass::Glass>) -> (f64, f64) {
    let (lo, hi, _) = range_through_with(glasses, lens::glass::GlassRange::Extrapolate);
    (lo, hi)
}

/// The CIE 1931 2-degree colour-matching functions (x̄, ȳ, z̄) at `nm`
/// (linear between the 1 nm table's entries; zero outside 360-830 nm).
pub fn cmf(nm: f64) -> DVec3 {
    if !(FIRST_NM..=LAST_NM).contains(&nm) {
        return DVec3::ZERO;
    }
    let x = nm - FIRST_NM;
    let i = (x as usize).min(CMF_1931.len() - 2);
    let f = x - i as f64;
    DVec3::from_array(CMF_1931[i]).lerp(DVec3::from_array(CMF_1931[i + 1]), f)
}

/// The CIE D65 illuminant's relative power at `nm` (100 at 560 nm; linear
/// between the 5 nm table's entries; zero outside 360-830 nm).
pub fn d65(nm: f64) -> f64 {
    d65_normalised_with(&D65, nm)
}

/// The CIE standard illuminant A at `nm`, relative power (100 at 560 nm):
/// its definition, Planck's law at 2848 K with c2 = 1.435e7 nm K (the
/// same curve as 2856 K with c2 = 1.4388e7 nm K).
pub fn illuminant_a(nm: f64) -> f64 {
    let c2: f64 = 1.435e7;
    let t = 2848.0;
    100.0 * (560.0 / nm).powi(5) * ((c2 / (t * 560.0)).exp() - 1.0) / ((c2 / (t * nm)).exp() - 1.0)
}

/// Planck's law: spectral radiance of a black body at `kelvin`, W / (m^2
/// sr nm), at wavelength `nm` (in vacuum).
pub fn planck(nm: f64, kelvin: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 299_792_458.0;
    const K: f64 = 1.380_649e-23;
    let l = nm * 1e-9;
    let x = H * C / (l * K * kelvin);
    // per metre of wavelength, then per nm
    2.0 * H * C * C / (l.powi(5) * x.exp_m1()) * 1e-9
}

/// ∫ f over 360-830 nm for a function sampled at the 1 nm nodes, by the
/// trapezoid rule (exact for the tables' piecewise-linear functions when f
/// is itself linear between nodes).
pub fn integrate(f: impl Fn(f64) -> f64) -> f64 {
    let n = CMF_1931.len();
    (0..n).map(|i| f(FIRST_NM + i as f64) * if i == 0 || i == n - 1 { 0.5 } else { 1.0 }).sum()
}

/// The constants the conversions need, computed once.
struct Constants {
    /// ∫ ȳ dλ.
    y_integral: f64,
    /// Y of the D65 table (∫ D65 ȳ / ∫ ȳ).
    d65_luminance: f64,
    /// XYZ to balanced linear sRGB.
    xyz_to_rgb: DMat3,
    /// Its inverse.
    rgb_to_xyz: DMat3,
}

fn constants() -> &'static Constants {
    static C: OnceLock<Constants> = OnceLock::new();
    C.get_or_init(|| {
        let y_integral = integrate(|l| cmf(l).y);
        let white = DVec3::new(
            integrate(|l| d65(l) * cmf(l).x),
            integrate(|l| d65(l) * cmf(l).y),
            integrate(|l| d65(l) * cmf(l).z),
        ) / y_integral;
        let d65_luminance = white.y;
        // IEC 61966-2-1 (sRGB), rows
        let m = DMat3::from_cols_array(&[
            3.240_454_2,
            -0.969_266_0,
            0.055_643_4,
            -1.537_138_5,
            1.875_010_8,
            -0.204_025_9,
            -0.498_531_4,
            0.041_556_0,
            1.057_225_2,
        ]);
        let balance = m * (white / d65_luminance);
        let xyz_to_rgb = DMat3::from_diagonal(balance.recip()) * m;
        Constants { y_integral, d65_luminance, xyz_to_rgb, rgb_to_xyz: xyz_to_rgb.inverse() }
    })
}

/// ∫ ȳ dλ over 360-830 nm (106.86 nm).
pub fn y_integral() -> f64 {
    constants().y_integral
}

/// D65 scaled to luminance Y = 1: the spectrum of RGB white (1, 1, 1).
#[inline]
pub fn d65_normalised(nm: f64) -> f64 {
    d65_normalised_with(d65_normalised_table(), nm)
}

/// The D65 table scaled to luminance 1 (computed once).
pub fn d65_normalised_table() -> &'static [f64; 95] {
    static T: OnceLock<[f64; 95]> = OnceLock::new();
    T.get_or_init(|| D65.map(|v| v / constants().d65_luminance))
}

/// A 5 nm D65 table (as given, or normalised: [`d65_normalised_table`])
/// at `nm`, linear between entries, zero outside 360-830 nm: the table is
/// fetched once for several wavelengths.
#[inline]
pub fn d65_normalised_with(table: &[f64; 95], nm: f64) -> f64 {
    if !(FIRST_NM..=LAST_NM).contains(&nm) {
        return 0.0;
    }
    let x = (nm - FIRST_NM) / 5.0;
    let i = (x as usize).min(table.len() - 2);
    let f = x - i as f64;
    table[i] + (table[i + 1] - table[i]) * f
}

/// Linear sRGB (balanced to the D65 table) of tristimulus `xyz`.
pub fn xyz_to_rgb(xyz: DVec3) -> DVec3 {
    constants().xyz_to_rgb * xyz
}

/// Tristimulus XYZ of linear sRGB `rgb` (the inverse of [`xyz_to_rgb`]).
pub fn rgb_to_xyz(rgb: DVec3) -> DVec3 {
    constants().rgb_to_xyz * rgb
}

/// XYZ of a spectrum given as a function of wavelength (nm).
pub fn spectrum_to_xyz(s: impl Fn(f64) -> f64) -> DVec3 {
    let c = constants();
    DVec3::new(integrate(|l| s(l) * cmf(l).x), integrate(|l| s(l) * cmf(l).y), integrate(|l| s(l) * cmf(l).z))
        / c.y_integral
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn y_integral_is_the_cie_value() {
        // pbrt-v4's CIE_Y_integral (1 nm sum) is 106.856895
        assert_relative_eq!(y_integral(), 106.856895, max_relative = 1e-5);
    }

    #[test]
    fn d65_is_white_and_equal_energy_is_near_white() {
        let w = xyz_to_rgb(spectrum_to_xyz(d65_normalised));
        assert_relative_eq!(w.x, 1.0, epsilon = 1e-12);
        assert_relative_eq!(w.y, 1.0, epsilon = 1e-12);
        assert_relative_eq!(w.z, 1.0, epsilon = 1e-12);
        // the D65 white point: x = 0.3127, y = 0.3290
        let xyz = spectrum_to_xyz(d65);
        let s = xyz.x + xyz.y + xyz.z;
        assert_relative_eq!(xyz.x / s, 0.3127, epsilon = 2e-4);
        assert_relative_eq!(xyz.y / s, 0.3290, epsilon = 2e-4);
    }

    #[test]
    fn illuminant_a_has_its_chromaticity() {
        // CIE A: x = 0.44757, y = 0.40745
        let xyz = spectrum_to_xyz(illuminant_a);
        let s = xyz.x + xyz.y + xyz.z;
        assert_relative_eq!(xyz.x / s, 0.44757, epsilon = 2e-4);
        assert_relative_eq!(xyz.y / s, 0.40745, epsilon = 2e-4);
    }

    #[test]
    fn planck_peaks_by_wien() {
        // Wien: λ_max = 2.897771955e6 nm K / T
        let t = 5000.0;
        let peak = 2.897_771_955e6 / t;
        assert!(planck(peak, t) > planck(peak - 2.0, t) && planck(peak, t) > planck(peak + 2.0, t));
    }
}
