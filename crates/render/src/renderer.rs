//! The render loop: rows in parallel (rayon), camera samples made for a
//! group of pixels and traced through the camera as one batch, stratified
//! pixel and aperture samples decorrelated per pixel, deterministic for a
//! given seed.

use crate::camera::CameraSample;
use crate::image::Image;
use crate::integrator::radiance;
use crate::rng::{stratified, Sampler};
use crate::scene::format::FilterSpec;
use crate::scene::Scene;
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

/// Renders `scene`; `progress` is called with the number of finished rows.
///
/// Each pixel has its own random stream (seeded by the render seed and the
/// pixel), so a render does not depend on the number of threads. The first
/// n^2 samples of a pixel (n = floor(sqrt(spp))) are stratified over the
/// pixel and, independently, over the aperture: the aperture strata are
/// visited in a random order drawn per pixel, so the lens position of a
/// sample is uniform and independent of its position in the pixel and the
/// estimator is unbiased at every sample count (docs/rendering.md).
pub fn render(scene: &Scene, opt: Options, progress: &(dyn Fn(usize) + Sync)) -> (Image, Stats) {
    let (w, h) = (scene.film.width as usize, scene.film.height as usize);
    let spp = opt.spp.max(1) as usize;
    let strata = (spp as f64).sqrt().floor().max(1.0) as usize;
    let done = AtomicUsize::new(0);
    let passed = AtomicUsize::new(0);
    let group = (GROUP_SAMPLES / spp).max(1);
    let rows: Vec<Vec<DVec3>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut row = Vec::with_capacity(w);
            let mut row_passed = 0;
            let mut samples = Vec::with_capacity(group.min(w) * spp);
            let mut rays = Vec::with_capacity(samples.capacity());
            let mut order: Vec<usize> = Vec::with_capacity(strata * strata);
            for x0 in (0..w).step_by(group) {
                let xs = x0..(x0 + group).min(w);
                let mut samplers: Vec<Sampler> =
                    xs.clone().map(|x| Sampler::new(opt.seed, (y * w + x) as u64)).collect();
                samples.clear();
                for (x, s) in xs.clone().zip(&mut samplers) {
                    // the aperture strata in a random order of this pixel's own
                    order.clear();
                    order.extend(0..strata * strata);
                    shuffle(&mut order, s);
                    for k in 0..spp {
                        let stratified_k = k < order.len();
                        let (jx, jy) = if stratified_k { stratified(k, strata, s.next2()) } else { s.next2() };
                        let (ox, oy) = match scene.film.filter {
                            FilterSpec::Box => (jx, jy),
                            FilterSpec::Tent => (0.5 + tent(jx), 0.5 + tent(jy)),
                        };
                        let a = match order.get(k) {
                            Some(&o) => stratified(o, strata, s.next2()),
                            None => s.next2(),
                        };
                        let film = ((x as f64 + ox) / w as f64, (y as f64 + oy) / h as f64);
                        samples.push(CameraSample { film, aperture: a });
                    }
                }
                scene.camera.rays(&samples, &mut rays);
                for (i, s) in samplers.iter_mut().enumerate() {
                    let mut sum = DVec3::ZERO;
                    for (ray, weight) in rays[i * spp..(i + 1) * spp].iter().flatten() {
                        if *weight > 0.0 {
                            row_passed += 1;
                            sum += *weight * radiance(scene, *ray, s);
                        }
                    }
                    row.push(sum / spp as f64);
                }
            }
            passed.fetch_add(row_passed, Ordering::Relaxed);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            row
        })
        .collect();
    let camera_rays = w * h * spp;
    let stats = Stats { camera_rays, camera_rays_passed: passed.load(Ordering::Relaxed) };
    (Image { width: w, height: h, pixels: rows.concat() }, stats)
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
