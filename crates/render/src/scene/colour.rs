//! What in a scene has colour beyond RGB: catalogue glasses, lights given
//! as spectra, and the colour mode a render takes from them (RGB, spectral
//! over the glasses' common range, or one wavelength).

use super::format::{FilmSpec, RadianceSpec, SpectralSpec};
use super::{v3, ColourMode, MAX_RADIANCE};
use crate::camera::Camera;
use crate::material::Material;
use crate::spectrum::{Illuminant, Radiance, WavelengthRange};
use crate::transport::Medium;
use glam::DVec3;
use lens::error::exact;
use std::sync::Arc;

/// A catalogue glass by `VENDOR:NAME`, with its index at the d line.
pub(super) fn find_glass(name: &str) -> Result<(Arc<lens::glass::PreparedIndex>, f64), String> {
    let g = lens::glass::Catalogs::shipped().find(name).map_err(|e| e.to_string())?;
    let nd = g.nd().map_err(|e| e.to_string())?;
    Ok((Arc::new(g.prepared()), nd))
}

/// A light's radiance from its spec; errors say what to change.
pub(super) fn radiance_of(spec: &RadianceSpec) -> Result<Radiance, String> {
    match spec {
        RadianceSpec::Rgb(c) => {
            if c.iter().all(|x| x.is_finite() && *x >= 0.0 && *x <= MAX_RADIANCE) {
                Ok(Radiance::rgb(v3(*c)))
            } else {
                Err(format!("{c:?}: give three numbers from 0 to {MAX_RADIANCE:e}"))
            }
        }
        RadianceSpec::Spectrum(s) => {
            if !(s.luminance.is_finite() && s.luminance >= 0.0 && s.luminance <= MAX_RADIANCE) {
                return Err(format!("luminance {}: give a luminance from 0 to {MAX_RADIANCE:e}", exact(s.luminance)));
            }
            match (s.blackbody_k, s.illuminant.as_deref()) {
                (Some(k), None) if k.is_finite() && (500.0..=100_000.0).contains(&k) => {
                    Ok(Radiance::blackbody(k, s.luminance))
                }
                (Some(k), None) => Err(format!("blackbody_k {}: give a temperature from 500 to 100000 K", exact(k))),
                (None, Some(name)) => match name.to_ascii_uppercase().as_str() {
                    "D65" => Ok(Radiance::illuminant(Illuminant::D65, s.luminance)),
                    "A" => Ok(Radiance::illuminant(Illuminant::A, s.luminance)),
                    _ => Err(format!("illuminant \"{name}\": the CIE illuminants known are \"D65\" and \"A\"")),
                },
                _ => Err("give either blackbody_k (kelvin) or illuminant (\"D65\" or \"A\")".into()),
            }
        }
    }
}

/// RGB or spectral, from the film's setting and what in the scene depends
/// on wavelength; a spectral render's range is 360-830 nm, each glass
/// extrapolated past its data where its formula allows (with a warning),
/// else, or under `range`'s strict choice, narrowed to its data
/// ([`crate::spectrum::cie::range_through_with`]). With the warnings.
pub(super) fn colour_mode(
    film: &FilmSpec,
    camera: &Camera,
    materials: &[Material],
    point_lights: &[(DVec3, Radiance)],
    range: lens::glass::GlassRange,
) -> Result<(ColourMode, Vec<lens::glass::RangeWarning>), (String, String)> {
    let material_glasses = materials.iter().filter_map(|m| match m {
        Material::Dielectric { medium: Medium { glass: Some(g), .. } } => Some(g.glass()),
        _ => None,
    });
    let glasses: Vec<&lens::glass::Glass> = camera.glasses().into_iter().chain(material_glasses).collect();
    if let Some(nm) = film.wavelength_nm {
        if !(crate::spectrum::cie::MIN_NM..=crate::spectrum::cie::MAX_NM).contains(&nm) {
            return Err((
                "film.wavelength_nm".into(),
                format!("{}: give a wavelength from 360 to 830 nm", lens::error::exact(nm)),
            ));
        }
        let mut warnings = Vec::new();
        for g in &glasses {
            g.index_with(nm, range).map_err(|e| ("film.wavelength_nm".to_string(), e.to_string()))?;
            warnings.extend(g.range_warning(nm).filter(|w| !warnings.contains(w)));
        }
        return Ok((ColourMode::Monochromatic(nm), warnings));
    }
    let (lo, hi, warnings) = crate::spectrum::cie::range_through_with(glasses.iter().copied(), range);
    let wavelength_dependent = camera.is_dispersive()
        || !glasses.is_empty()
        || materials.iter().any(|m| matches!(m, Material::Emissive { radiance } if radiance.is_spectral()))
        || point_lights.iter().any(|(_, r)| r.is_spectral());
    let spectral = match film.spectral {
        SpectralSpec::On => true,
        SpectralSpec::Off => false,
        SpectralSpec::Auto => wavelength_dependent,
    };
    if !spectral {
        return Ok((ColourMode::Rgb, Vec::new()));
    }
    if hi - lo < 100.0 || hi.is_nan() || lo.is_nan() {
        return Err((
            "film.spectral".into(),
            format!(
                "the glasses' data overlap only over {}-{} nm of the visible: a spectral render needs 100 nm or more; set \"spectral\": \"off\"",
                lens::error::num(lo),
                lens::error::num(hi)
            ),
        ));
    }
    Ok((ColourMode::Spectral(WavelengthRange::new(lo, hi)), warnings))
}
