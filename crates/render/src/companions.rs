//! Which spectral samples trace their companion wavelengths through a real
//! lens.
//!
//! Through a dispersive lens each companion wavelength of a sample costs a
//! trace of its own: the scene ray traced back to the film at that
//! wavelength (`Camera::companions`), three a sample, where the hero's
//! trace is one. The render asks for them only for the samples whose
//! radiance is bright enough for their colour to matter; the others keep
//! their hero alone, its value over its density (as where a dispersive
//! material ends the companions). This is unbiased: which samples keep
//! their companions depends only on what a sample's four wavelengths share
//! (its scene path and the radiance it carries at all four, not on which
//! of them is the hero), so the weights with which each wavelength of a
//! path is counted still sum to one over the four ways of drawing it
//! (docs/rendering.md gives the estimator).
//!
//! The threshold trades the colour noise a lone hero adds (about its own
//! value squared, a wavelength alone being a saturated colour) against the
//! time its companions cost: for the RMSE alone a sample would keep them
//! when its value v (radiance at the brightest of its wavelengths) has
//! v² ≥ σ² r, with σ² the variance of one sample's value in a pixel (the
//! noise the render has anyway) and r the companions' cost relative to a
//! whole sample; the threshold is lower by the square root of
//! [`COLOUR_NOISE_WEIGHT`], because colour noise is seen against a pixel's
//! brightness, which the RMSE ignores. σ² comes from a pilot: a sparse
//! grid of pixels rendered with their own random streams, so the threshold
//! does not depend on the render's samples and the render stays unbiased
//! and deterministic. `film.companions: all` (`lens render --companions
//! all`) traces every sample's companions instead.

use crate::camera::lamp_light::Unseen;
use crate::camera::CameraSample;
use crate::integrator::radiance_with;
use crate::rng::Sampler;
use crate::scene::{ColourMode, Scene};
use crate::spectrum::SampledWavelengths;
use crate::transport::Spectral;
use rayon::prelude::*;

/// Samples per pilot pixel.
const PILOT_SPP: usize = 16;

/// The pilot's share of the render's samples, at most.
const PILOT_SHARE: f64 = 1.0 / 256.0;

/// Pilot pixels, at least (fewer where the image has fewer).
const PILOT_MIN_PIXELS: usize = 64;

/// The companions' cost relative to a whole sample: three lens traces
/// against one lens trace and a scene path (about 0.6 on the double Gauss
/// bokeh scene, less where the scene costs more).
const COMPANION_COST: f64 = 0.5;

/// How much more a lone hero's colour noise counts than the RMSE says: the
/// RMSE weighs an error by its size alone, but colour noise is seen against
/// the pixel's own brightness, so in a dim region it shows where the RMSE
/// barely counts it. The threshold is the RMSE's divided by the square root
/// of this. Measured on the cine prime portrait (string lights over diffuse
/// figures, 480 x 270 at 32 spp): the median pixel's colour noise is 12.9%
/// of its luminance, against 11.1% with every companion and 20% with the
/// RMSE's threshold. On the bokeh scene through a real lens the lamps'
/// light is traced from the lamps (`camera::lamp_light`) and camera paths
/// see only the dim card and background, so every sample traces them.
const COLOUR_NOISE_WEIGHT: f64 = 30.0;

/// Stream offset of the pilot's random numbers (apart from every pixel's).
const PILOT_STREAM: u64 = 0x5eed_9110_7000_0000;

/// The radiance (at a sample's brightest wavelength) from which a sample
/// of a render of `scene` at `spp` samples a pixel with seed `seed` traces
/// its companions: 0 (all of them) where companions cost no trace of their
/// own (no real lens with glasses, or an RGB render). A scene whose film
/// asks for every companion (`film.companions: all`) does not call this.
/// What is `unseen` is black where camera rays meet it (see
/// [`radiance_with`]).
pub(crate) fn threshold(scene: &Scene, seed: u64, spp: usize, unseen: &Unseen) -> f64 {
    let ColourMode::Spectral(range) = &scene.colour else { return 0.0 };
    if !scene.camera.companions_cost_a_trace() {
        return 0.0;
    }
    let (w, h) = (scene.film.width as usize, scene.film.height as usize);
    // a grid of pixels, every `stride`th in each direction: about
    // PILOT_SHARE of the render's samples
    let budget = (w * h) as f64 * spp as f64 * PILOT_SHARE / PILOT_SPP as f64;
    let target = budget.max(PILOT_MIN_PIXELS as f64).min((w * h) as f64);
    let stride = (((w * h) as f64 / target).sqrt().floor() as usize).max(1);
    let pixels: Vec<(usize, usize)> =
        (stride / 2..h).step_by(stride).flat_map(|y| (stride / 2..w).step_by(stride).map(move |x| (x, y))).collect();
    let variances: Vec<f64> = pixels
        .par_iter()
        .map(|&(x, y)| {
            let mut s = Sampler::new(seed ^ PILOT_STREAM, (y * w + x) as u64);
            let mut samples = Vec::with_capacity(PILOT_SPP);
            let mut colours: Vec<SampledWavelengths> = Vec::with_capacity(PILOT_SPP);
            for _ in 0..PILOT_SPP {
                let (jx, jy) = s.next2();
                let wl = range.sample_four(s.uniform());
                let mut sample = CameraSample::new(((x as f64 + jx) / w as f64, (y as f64 + jy) / h as f64), s.next2());
                sample.wavelength_nm = Some(wl.hero());
                samples.push(sample);
                colours.push(wl);
            }
            let mut lanes = Vec::new();
            scene.camera.heroes(&samples, &colours, &mut lanes);
            let ys: Vec<f64> = lanes
                .iter()
                .zip(&colours)
                .map(|(lane, wl)| match lane {
                    Some((ray, lane)) if lane[0].transmission > 0.0 && lane[0].density > 0.0 => {
                        let mut t = Spectral::new(*wl);
                        let l = radiance_with(scene, *ray, &mut t, &mut s, None, unseen);
                        l.max_element() * lane[0].transmission / lane[0].density
                    }
                    _ => 0.0,
                })
                .collect();
            let n = ys.len() as f64;
            let mean = ys.iter().sum::<f64>() / n;
            ys.iter().map(|y| (y - mean) * (y - mean)).sum::<f64>() / (n - 1.0)
        })
        .collect();
    let sigma2 = variances.iter().sum::<f64>() / variances.len().max(1) as f64;
    let tau = (sigma2 * COMPANION_COST / COLOUR_NOISE_WEIGHT).sqrt();
    if tau.is_finite() {
        tau
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn shipped(name: &str) -> Scene {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes");
        Scene::load(&dir.join(name)).unwrap()
    }

    /// On the shipped bokeh scene (lamps of radiance 34-60 seen through the
    /// double Gauss, a card and background that send under 0.01) with
    /// camera paths seeing the lamps, the pilot puts the threshold between
    /// the two: the samples that see a lamp trace their companions, the
    /// rest keep their hero; the same for another seed. With the lamps
    /// traced from the lamps (as a render does), below the background. An RGB render and a camera whose companions cost
    /// nothing get 0 (every sample keeps all four).
    #[test]
    fn the_pilot_puts_the_threshold_between_the_lamps_and_the_rest() {
        let bokeh = shipped("bokeh-double-gauss.json");
        assert!(matches!(bokeh.colour, ColourMode::Spectral(_)));
        for seed in [1, 2] {
            let tau = threshold(&bokeh, seed, 64, &Unseen::NONE);
            assert!(tau > 0.02 && tau < 30.0, "seed {seed}: threshold {tau}");
            // as rendered, the lamps' light is traced from the lamps and
            // camera paths see none of it: the dim rest is all there is,
            // and every sample traces its companions
            let lamps = crate::camera::lamp_light::LampLight::build(&bokeh, 64).unwrap();
            let tau = threshold(&bokeh, seed, 64, lamps.unseen());
            assert!(tau < 0.004, "seed {seed}: threshold {tau} with the lamps traced from the lamps");
        }
        let mut rgb = shipped("bokeh-double-gauss.json");
        rgb.colour = ColourMode::Rgb;
        assert_eq!(threshold(&rgb, 1, 64, &Unseen::NONE), 0.0);
        let thin = shipped("bokeh-thin-glass.json");
        assert!(matches!(thin.colour, ColourMode::Spectral(_)) && thin.camera.is_dispersive());
        assert_eq!(threshold(&thin, 1, 64, &Unseen::NONE), 0.0);
    }
}
