//! Error against run time: the same scene at growing sample counts, each
//! timed and compared with a high-sample reference rendered with another
//! seed.

use crate::image::Image;
use crate::renderer::{render, Options};
use crate::scene::Scene;
use std::time::Instant;

/// One render of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Samples per pixel.
    pub spp: u32,
    /// Wall time, seconds.
    pub seconds: f64,
    /// RMSE against the reference, linear radiance.
    pub rmse: f64,
    /// Fraction of camera rays through the lens.
    pub pass_rate: f64,
}

/// The sweep and its reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Its wall time, seconds.
    pub reference_seconds: f64,
    /// The reference image.
    pub reference: Image,
    /// One row per sample count.
    pub rows: Vec<Row>,
}

/// Renders `scene` at each of `spps` (seed `seed`) and at `reference_spp`
/// (seed `seed + 1`), and measures the error of each against the reference.
pub fn error_against_time(scene: &Scene, spps: &[u32], reference_spp: u32, seed: u64) -> Report {
    let t = Instant::now();
    let (reference, _) = render(scene, Options { spp: reference_spp, seed: seed.wrapping_add(1) }, &|_| {});
    let reference_seconds = t.elapsed().as_secs_f64();
    let rows = spps
        .iter()
        .map(|&spp| {
            let t = Instant::now();
            let (img, stats) = render(scene, Options { spp, seed }, &|_| {});
            Row { spp, seconds: t.elapsed().as_secs_f64(), rmse: img.rmse(&reference), pass_rate: stats.pass_rate() }
        })
        .collect();
    Report { reference_spp, reference_seconds, reference, rows }
}
