//! The render loop: every pixel in parallel (rayon), stratified pixel and
//! aperture samples, deterministic for a given seed.

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

/// Renders `scene`; `progress` is called with the number of finished rows.
pub fn render(scene: &Scene, opt: Options, progress: &(dyn Fn(usize) + Sync)) -> (Image, Stats) {
    let (w, h) = (scene.film.width as usize, scene.film.height as usize);
    let spp = opt.spp.max(1) as usize;
    let strata = (spp as f64).sqrt().floor().max(1.0) as usize;
    let done = AtomicUsize::new(0);
    let passed = AtomicUsize::new(0);
    let rows: Vec<Vec<DVec3>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut row = Vec::with_capacity(w);
            let mut row_passed = 0;
            for x in 0..w {
                let mut s = Sampler::new(opt.seed, (y * w + x) as u64);
                let mut sum = DVec3::ZERO;
                for k in 0..spp {
                    // stratified while k fills the strata x strata grid
                    let (jx, jy) = if k < strata * strata { stratified(k, strata, s.next2()) } else { s.next2() };
                    let (ox, oy) = match scene.film.filter {
                        FilterSpec::Box => (jx, jy),
                        FilterSpec::Tent => (0.5 + tent(jx), 0.5 + tent(jy)),
                    };
                    let a = if k < strata * strata {
                        // aperture strata decorrelated from the pixel's
                        stratified((k * 7 + 3) % (strata * strata), strata, s.next2())
                    } else {
                        s.next2()
                    };
                    let u = (x as f64 + ox) / w as f64;
                    let v = (y as f64 + oy) / h as f64;
                    if let Some((ray, weight)) = scene.camera.ray(u, v, a) {
                        if weight > 0.0 {
                            row_passed += 1;
                            sum += weight * radiance(scene, ray, &mut s);
                        }
                    }
                }
                row.push(sum / spp as f64);
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

/// Tent-distributed offset in [-1, 1] from a uniform.
fn tent(u: f64) -> f64 {
    let t = 2.0 * u;
    if t < 1.0 {
        t.sqrt() - 1.0
    } else {
        1.0 - (2.0 - t).sqrt()
    }
}
