//! The render loop: rows in parallel (rayon), camera samples made for a
//! group of pixels and traced through the camera as one batch, stratified
//! pixel and aperture samples decorrelated per pixel, deterministic for a
//! given seed.

#[cfg(doc)]
use crate::camera::Camera;
use crate::camera::{CameraSample, SpectralLane};
use crate::companions;
use crate::image::Image;
use crate::integrator::{radiance_with, FirstBounce};
use crate::rng::{stratified, Sampler};
use crate::scene::format::{CompanionsSpec, FilterSpec};
use crate::scene::{ColourMode, Scene};
use crate::spectrum::sampled::N;
use crate::spectrum::{cie, SampledSpectrum, SampledWavelengths};
use crate::splat::{splat_sample, Splats};
use crate::transport::{Rgb, Spectral};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Render settings that may override the scene's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the random streams.
    pub seed: u64,
}

/// What a render measured besides the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    /// Camera rays generated.
    pub camera_rays: usize,
    /// Camera rays that made it through the lens (all of them for pinhole
    /// and thin-lens cameras).
    pub camera_rays_passed: usize,
}

impl Stats {
    /// Fraction of camera rays that passed the lens.
    pub fn pass_rate(&self) -> f64 {
        self.camera_rays_passed as f64 / self.camera_rays.max(1) as f64
    }
}

/// Camera samples made and traced together: a group of pixels' samples go
/// to the camera as one batch (a real lens traces them with the batch
/// tracer), then each is followed into the scene.
const GROUP_SAMPLES: usize = 8192;

/// Rows rendered together before their splats are added, when a render
/// splats (a fixed number, so the image does not depend on the number of
/// threads; other renders take all rows at once).
const BAND_ROWS: usize = 64;

/// Renders `scene`; `progress` is called with the number of finished rows.
///
/// Each pixel has its own random stream (seeded by the render seed and the
/// pixel), so a render does not depend on the number of threads. The first
/// n^2 samples of a pixel (n = floor(sqrt(spp))) are stratified over the
/// pixel and, independently, over the aperture: the aperture strata are
/// visited in a random order drawn per pixel, so the lens position of a
/// sample is uniform and independent of its position in the pixel and the
/// estimator is unbiased at every sample count (docs/rendering.md).
///
/// A spectral scene ([`ColourMode::Spectral`]) gives each sample four
/// wavelengths (hero-wavelength sampling), the heroes stratified over the
/// pixel's samples in a random order of the pixel's own; the pixel sums
/// CIE XYZ and is converted to linear sRGB at the end. Through a
/// dispersive camera the four wavelengths of a sample leave the lens along
/// one scene ray from four film points, combined by multiple importance
/// sampling ([`Camera::rays_spectral`]); with the box filter each
/// wavelength's light goes to the pixel it lands in (`splat.rs`), rows
/// rendered in bands whose splats are added in row order, so the image does
/// not depend on the number of threads. Through a real lens the
/// companions are traced only for the samples bright enough for their
/// colour to matter (`companions.rs`); the others keep their hero alone.
/// An RGB scene draws exactly the random numbers it drew before spectra
/// existed.
pub fn render(scene: &Scene, opt: Options, progress: &(dyn Fn(usize) + Sync)) -> (Image, Stats) {
    let companions = match scene.film.companions {
        CompanionsSpec::Auto => Companions::Auto,
        CompanionsSpec::All => Companions::From(0.0),
    };
    render_with(scene, opt, progress, companions)
}

/// Which spectral samples trace their companion wavelengths through a real
/// lens with glasses (elsewhere they cost nothing and every sample has
/// them). [`render`] takes the scene's choice (`film.companions`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Companions {
    /// Those whose radiance, at the brightest of their four wavelengths,
    /// is at least a threshold set by a pilot (`companions.rs`).
    Auto,
    /// Those whose radiance at the brightest of their wavelengths is at
    /// least this (0: all of them; infinity: none, every sample keeps its
    /// hero alone). Any threshold gives the same image in expectation;
    /// it trades colour noise against time.
    From(f64),
}

/// [`render`] with the choice of which samples trace their companions.
pub fn render_with(
    scene: &Scene,
    opt: Options,
    progress: &(dyn Fn(usize) + Sync),
    companions: Companions,
) -> (Image, Stats) {
    let (w, h) = (scene.film.width as usize, scene.film.height as usize);
    let spp = opt.spp.max(1) as usize;
    let strata = (spp as f64).sqrt().floor().max(1.0) as usize;
    let done = AtomicUsize::new(0);
    let passed = AtomicUsize::new(0);
    let group = (GROUP_SAMPLES / spp).max(1);
    // through a dispersive lens with the box filter, companion wavelengths
    // go to the pixel they land in (`splat`): rows are rendered in bands,
    // each band's splats added in row order once it is done, so the image
    // does not depend on the number of threads
    let splatting = matches!(scene.colour, ColourMode::Spectral(_))
        && scene.camera.is_dispersive()
        && scene.film.filter == FilterSpec::Box;
    // through a real lens with glasses, the radiance (at the brightest of
    // its wavelengths) from which a sample traces its companions
    // (`companions.rs`)
    let companions_from = match companions {
        Companions::Auto => companions::threshold(scene, opt.seed, spp),
        Companions::From(v) => v,
    };
    let mut film: Vec<DVec3> = vec![DVec3::ZERO; w * h];
    let band_rows = if splatting { BAND_ROWS } else { h.max(1) };
    for band in (0..h).step_by(band_rows) {
        let rows: Vec<(Vec<DVec3>, Option<Splats>)> = (band..(band + band_rows).min(h))
            .into_par_iter()
            .map(|y| {
                let mut splats = splatting.then(|| Splats::new(y, w, h));
                let mut row = Vec::with_capacity(w);
                let mut row_passed = 0;
                let mut samples = Vec::with_capacity(group.min(w) * spp);
                let mut rays = Vec::with_capacity(samples.capacity());
                let mut order: Vec<usize> = Vec::with_capacity(strata * strata);
                let mut colours: Vec<SampledWavelengths> = Vec::with_capacity(samples.capacity());
                let mut lambda_order: Vec<usize> = Vec::new();
                let (mut light_order, mut bsdf_order) = (Vec::new(), Vec::new());
                let mut firsts: Vec<FirstBounce> = Vec::with_capacity(samples.capacity());
                let mut lanes = Vec::new();
                let mut radiances: Vec<SampledSpectrum> = Vec::new();
                let mut traced: Vec<bool> = Vec::new();
                let mut selected: Vec<usize> = Vec::new();
                for x0 in (0..w).step_by(group) {
                    let xs = x0..(x0 + group).min(w);
                    let mut samplers: Vec<Sampler> =
                        xs.clone().map(|x| Sampler::new(opt.seed, (y * w + x) as u64)).collect();
                    samples.clear();
                    colours.clear();
                    firsts.clear();
                    for (x, s) in xs.clone().zip(&mut samplers) {
                        // the aperture strata in a random order of this pixel's own
                        shuffle_strata(&mut order, strata, s);
                        for k in 0..spp {
                            let stratified_k = k < order.len();
                            let (jx, jy) = if stratified_k { stratified(k, strata, s.next2()) } else { s.next2() };
                            let (ox, oy) = match scene.film.filter {
                                FilterSpec::Box => (jx, jy),
                                FilterSpec::Tent => (0.5 + tent(jx), 0.5 + tent(jy)),
                            };
                            let a = from_stratum(&order, k, strata, s);
                            let film = ((x as f64 + ox) / w as f64, (y as f64 + oy) / h as f64);
                            samples.push(CameraSample::new(film, a));
                        }
                        // the first bounce's light and direction: strata of
                        // their own, each in a random order of the pixel's
                        shuffle_strata(&mut light_order, strata, s);
                        shuffle_strata(&mut bsdf_order, strata, s);
                        for k in 0..spp {
                            let light = from_stratum(&light_order, k, strata, s);
                            firsts.push(FirstBounce { light, bsdf: from_stratum(&bsdf_order, k, strata, s) });
                        }
                        let start = colours.len();
                        push_wavelengths(scene, spp, s, &mut lambda_order, &mut colours);
                        let first = samples.len() - spp;
                        for (sample, wl) in samples[first..].iter_mut().zip(&colours[start..]) {
                            sample.wavelength_nm = Some(wl.hero());
                        }
                    }
                    if let ColourMode::Spectral(_) = scene.colour {
                        // a camera whose rays do not depend on wavelength sends
                        // all four along one ray with its plain weight
                        let dispersive = scene.camera.is_dispersive();
                        let deferred = dispersive && scene.camera.companions_cost_a_trace();
                        if dispersive {
                            scene.camera.heroes(&samples, &colours, &mut lanes);
                        } else {
                            scene.camera.rays(&samples, &mut rays);
                        }
                        // the paths' radiance first (each sample's wavelengths
                        // kept with it: the scene may have ended the companions),
                        // then, through a real lens, the companions of the paths
                        // bright enough to need them (`companions.rs`)
                        radiances.clear();
                        radiances.resize(samples.len(), SampledSpectrum([0.0; N]));
                        traced.clear();
                        traced.resize(samples.len(), false);
                        for (i, s) in samplers.iter_mut().enumerate() {
                            for k in i * spp..(i + 1) * spp {
                                let ray = if dispersive {
                                    match &lanes[k] {
                                        Some((ray, lane)) if lane[0].transmission > 0.0 => *ray,
                                        _ => continue,
                                    }
                                } else {
                                    match rays[k] {
                                        Some((ray, w)) if w > 0.0 => ray,
                                        _ => continue,
                                    }
                                };
                                row_passed += 1;
                                let mut t = Spectral::new(colours[k]);
                                radiances[k] = radiance_with(scene, ray, &mut t, s, Some(firsts[k]));
                                colours[k] = t.wavelengths;
                                traced[k] = true;
                            }
                        }
                        if deferred {
                            selected.clear();
                            for k in 0..samples.len() {
                                let wl = &mut colours[k];
                                if !traced[k] || wl.secondary_terminated() {
                                    continue;
                                }
                                if radiances[k].max_element() >= companions_from {
                                    selected.push(k);
                                } else {
                                    wl.terminate_secondary();
                                }
                            }
                            scene.camera.companions(&colours, &mut lanes, &selected);
                        }
                        for i in 0..xs.len() {
                            let x = x0 + i;
                            let mut sum = DVec3::ZERO;
                            for k in (i * spp..(i + 1) * spp).filter(|&k| traced[k]) {
                                let (wl, l) = (&colours[k], radiances[k]);
                                sum += if dispersive {
                                    let Some((_, lane)) = &lanes[k] else { continue };
                                    match splats.as_mut() {
                                        Some(sp) => splat_sample(wl, l, lane, (x, y), sp),
                                        None => {
                                            let pixel = |film: (f64, f64)| {
                                                pixel_density(scene.film.filter, film, (x, y), (w, h))
                                            };
                                            combine(wl, l, lane, pixel)
                                        }
                                    }
                                } else {
                                    let Some((_, weight)) = rays[k] else { continue };
                                    wl.xyz(l) * weight
                                };
                            }
                            row.push(cie::xyz_to_rgb(sum / (spp as f64 * cie::y_integral())));
                        }
                        continue;
                    }
                    scene.camera.rays(&samples, &mut rays);
                    for (i, s) in samplers.iter_mut().enumerate() {
                        let mut sum = DVec3::ZERO;
                        for k in i * spp..(i + 1) * spp {
                            let Some((ray, weight)) = rays[k] else { continue };
                            if weight <= 0.0 {
                                continue;
                            }
                            row_passed += 1;
                            let first = Some(firsts[k]);
                            sum += weight
                                * match scene.colour {
                                    ColourMode::Monochromatic(nm) => {
                                        let mut t = Spectral::new(SampledWavelengths::single(nm));
                                        DVec3::splat(radiance_with(scene, ray, &mut t, s, first).0[0])
                                    }
                                    _ => radiance_with(scene, ray, &mut Rgb, s, first),
                                };
                        }
                        row.push(sum / spp as f64);
                    }
                }
                passed.fetch_add(row_passed, Ordering::Relaxed);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1);
                (row, splats)
            })
            .collect();
        // each row's own values, then the band's splats (which may reach rows
        // of other bands), in row order
        let mut band_splats = Vec::new();
        for (y, (row, sp)) in (band..).zip(rows) {
            for (p, v) in film[y * w..(y + 1) * w].iter_mut().zip(row) {
                *p += v;
            }
            band_splats.extend(sp);
        }
        let scale = 1.0 / (spp as f64 * cie::y_integral());
        for sp in band_splats {
            sp.merge_into(&mut film, scale);
        }
    }
    let camera_rays = w * h * spp;
    let stats = Stats { camera_rays, camera_rays_passed: passed.load(Ordering::Relaxed) };
    (Image { width: w, height: h, pixels: film }, stats)
}

/// The XYZ estimate (times ∫ȳ) of one spectral camera sample: its
/// radiance `l` at each of its wavelengths, combined by the balance
/// heuristic over the densities with which the camera would have drawn the
/// same scene ray with each wavelength as the hero (each lane's camera
/// density times the pixel filter's density at that lane's film point;
/// Wilkie et al. 2014). Where the scene has ended the companions (a
/// dispersive material), the hero alone.
fn combine(
    wl: &SampledWavelengths,
    l: SampledSpectrum,
    lanes: &[SpectralLane; N],
    pixel: impl Fn((f64, f64)) -> f64,
) -> DVec3 {
    let mut pix = [0.0; N];
    for j in 0..N {
        if lanes[j].density > 0.0 {
            pix[j] = pixel(lanes[j].film);
        }
    }
    if wl.secondary_terminated() {
        let (lane, p) = (&lanes[0], pix[0] * lanes[0].density);
        return if p > 0.0 {
            cie::cmf(wl.nm[0]) * (l.0[0] * lane.transmission * pix[0] / (wl.pdf[0] * p))
        } else {
            DVec3::ZERO
        };
    }
    let mut total = 0.0;
    for m in 0..N {
        total += pix[m] * lanes[m].density;
    }
    if total.is_nan() || total <= 0.0 {
        return DVec3::ZERO;
    }
    let mut xyz = DVec3::ZERO;
    for j in 0..N {
        let f = l.0[j] * lanes[j].transmission * pix[j];
        if f != 0.0 {
            xyz += cie::cmf(wl.nm[j]) * (f / wl.pdf[j]);
        }
    }
    xyz / total
}

/// The density of the pixel filter for film point `film` (u, v in [0, 1])
/// in pixel `(x, y)` of a `(w, h)` image, per pixel area: the box filter's
/// 1 inside the pixel, the tent's product of triangles over two pixels.
fn pixel_density(filter: FilterSpec, film: (f64, f64), (x, y): (usize, usize), (w, h): (usize, usize)) -> f64 {
    let ox = film.0 * w as f64 - x as f64;
    let oy = film.1 * h as f64 - y as f64;
    match filter {
        FilterSpec::Box => {
            if (0.0..1.0).contains(&ox) && (0.0..1.0).contains(&oy) {
                1.0
            } else {
                0.0
            }
        }
        FilterSpec::Tent => (1.0 - (ox - 0.5).abs()).max(0.0) * (1.0 - (oy - 0.5).abs()).max(0.0),
    }
}

/// Appends the wavelengths of a pixel's `spp` samples to `out` (nothing
/// for an RGB render): heroes stratified over the sampling distribution's
/// CDF, the strata in a random order drawn from the pixel's stream.
fn push_wavelengths(
    scene: &Scene,
    spp: usize,
    s: &mut Sampler,
    order: &mut Vec<usize>,
    out: &mut Vec<SampledWavelengths>,
) {
    match &scene.colour {
        ColourMode::Rgb => {}
        ColourMode::Monochromatic(nm) => out.extend(std::iter::repeat_n(SampledWavelengths::single(*nm), spp)),
        ColourMode::Spectral(range) => {
            order.clear();
            order.extend(0..spp);
            shuffle(order, s);
            out.extend(order.iter().map(|&k| range.sample_four((k as f64 + s.uniform()) / spp as f64)));
        }
    }
}

/// The `strata` x `strata` cells in a random order of the pixel's stream.
fn shuffle_strata(order: &mut Vec<usize>, strata: usize, s: &mut Sampler) {
    order.clear();
    order.extend(0..strata * strata);
    shuffle(order, s);
}

/// Sample `k`'s two uniforms: jittered in cell `order[k]`, or plain beyond
/// the strata.
fn from_stratum(order: &[usize], k: usize, strata: usize, s: &mut Sampler) -> (f64, f64) {
    match order.get(k) {
        Some(&o) => stratified(o, strata, s.next2()),
        None => s.next2(),
    }
}

/// Shuffles `v` uniformly (Fisher-Yates) with the pixel's stream.
fn shuffle(v: &mut [usize], s: &mut Sampler) {
    for i in (1..v.len()).rev() {
        let j = ((s.uniform() * (i + 1) as f64) as usize).min(i);
        v.swap(i, j);
    }
}

/// Tent-distributed offset in [-1, 1] from a uniform.
fn tent(u: f64) -> f64 {
    let t = 2.0 * u;
    if t < 1.0 {
        t.sqrt() - 1.0
    } else {
        1.0 - (2.0 - t).sqrt()
    }
}
