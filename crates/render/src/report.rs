//! Error against run time: the same scene at growing sample counts, each
//! timed and compared with a reference of at least 16 times as many samples
//! rendered with other seeds. The reference is rendered as two halves with
//! different seeds: their difference measures its own noise, which is
//! stated beside the errors (an error near it is the reference's, not the
//! render's).

use crate::image::Image;
use crate::renderer::{render, Options};
use crate::scene::Scene;
use std::time::Instant;

/// One render of the sweep.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Row {
    /// Samples per pixel.
    pub spp: u32,
    /// Wall time, seconds.
    pub seconds: f64,
    /// RMSE against the reference, in the image's linear radiance.
    pub rmse: f64,
    /// The RMSE over the reference's mean pixel value: a fraction, 0.01 is
    /// 1% of the image's mean brightness.
    pub relative_rmse: f64,
    /// Fraction of camera rays that passed the lens (1 for pinhole and
    /// thin-lens cameras).
    pub rays_through_lens: f64,
}

/// The sweep and its reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Samples per pixel of the reference.
    pub reference_spp: u32,
    /// Its wall time, seconds.
    pub reference_seconds: f64,
    /// The reference's own noise: the RMSE of the mean of its two halves
    /// against the truth, estimated from their difference (linear radiance).
    pub reference_noise: f64,
    /// The reference's mean pixel value (all channels), what relative
    /// errors divide by.
    pub reference_mean: f64,
    /// The reference image.
    pub reference: Image,
    /// One row per sample count.
    pub rows: Vec<Row>,
}

/// The sample counts of a sweep up to `spp`: the powers of two below it and
/// `spp` itself (5 gives 1, 2, 4, 5).
pub fn sweep(spp: u32) -> Vec<u32> {
    let spp = spp.max(1);
    let mut v: Vec<u32> = (0..32).map(|k| 1u32 << k).take_while(|k| *k < spp).collect();
    v.push(spp);
    v
}

/// Renders `scene` at each of `spps` (seed `seed`) and a reference of
/// `reference_spp` samples as two halves (seeds `seed + 1`, `seed + 2`),
/// and measures the error of each against the reference. `progress` is
/// called with the rows finished over all the renders (the reference's
/// halves first), out of `(spps.len() + 2) * height`.
pub fn error_against_time(
    scene: &Scene,
    spps: &[u32],
    reference_spp: u32,
    seed: u64,
    progress: &(dyn Fn(usize) + Sync),
) -> Report {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let step = |_: usize| progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
    let half = (reference_spp / 2).max(1);
    let t = Instant::now();
    let (a, _) = render(scene, Options { spp: half, seed: seed.wrapping_add(1) }, &step);
    let (b, _) = render(scene, Options { spp: half, seed: seed.wrapping_add(2) }, &step);
    let reference_seconds = t.elapsed().as_secs_f64();
    // the mean of the halves; its noise is half the halves' RMS difference
    let reference = Image {
        width: a.width,
        height: a.height,
        pixels: a.pixels.iter().zip(&b.pixels).map(|(p, q)| (*p + *q) * 0.5).collect(),
    };
    let reference_noise = a.rmse(&b) / 2.0;
    let n = (reference.pixels.len() * 3).max(1) as f64;
    let reference_mean = reference.pixels.iter().map(|p| p.x + p.y + p.z).sum::<f64>() / n;
    let rows = spps
        .iter()
        .map(|&spp| {
            let t = Instant::now();
            let (img, stats) = render(scene, Options { spp, seed }, &step);
            let rmse = img.rmse(&reference);
            Row {
                spp,
                seconds: t.elapsed().as_secs_f64(),
                rmse,
                relative_rmse: if reference_mean > 0.0 { rmse / reference_mean } else { 0.0 },
                rays_through_lens: stats.pass_rate(),
            }
        })
        .collect();
    Report { reference_spp: 2 * half, reference_seconds, reference_noise, reference_mean, reference, rows }
}

#[cfg(test)]
mod tests {
    use super::sweep;

    #[test]
    fn the_sweep_includes_the_count_asked_for() {
        assert_eq!(sweep(5), vec![1, 2, 4, 5]);
        assert_eq!(sweep(8), vec![1, 2, 4, 8]);
        assert_eq!(sweep(1), vec![1]);
        assert_eq!(sweep(1 << 20).len(), 21);
    }
}
