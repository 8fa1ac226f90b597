//! Importance sampling of an environment image: directions drawn in
//! proportion to each pixel's luminance times the solid angle it covers
//! (sin θ of its row in the latitude-longitude layout), so a sun in a sky
//! image is found by light sampling rather than by chance. The layout is
//! the background's: u = 1/2 + atan2(x, z) / 2π, v = acos(y) / π.

use crate::image::Image;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// The sampling tables of one environment image.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSampler {
    width: usize,
    height: usize,
    /// Cumulative weight of the rows, the last 1.
    rows: Vec<f64>,
    /// Per row, the cumulative weight of its pixels, the last 1.
    cols: Vec<f64>,
    /// Each pixel's probability.
    prob: Vec<f64>,
}

impl EnvSampler {
    /// The tables of `img`; `None` when it is black.
    pub fn new(img: &Image) -> Option<EnvSampler> {
        let (w, h) = (img.width, img.height);
        let weight = |x: usize, y: usize| {
            let p = img.pixels[y * w + x];
            let lum = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
            lum.max(0.0) * (PI * (y as f64 + 0.5) / h as f64).sin()
        };
        let mut prob = vec![0.0; w * h];
        let mut cols = vec![0.0; w * h];
        let mut row_sums = vec![0.0; h];
        for y in 0..h {
            let mut acc = 0.0;
            for x in 0..w {
                let v = weight(x, y);
                prob[y * w + x] = v;
                acc += v;
                cols[y * w + x] = acc;
            }
            row_sums[y] = acc;
            if acc > 0.0 {
                for c in &mut cols[y * w..(y + 1) * w] {
                    *c /= acc;
                }
            }
        }
        let total: f64 = row_sums.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut acc = 0.0;
        let rows = row_sums
            .iter()
            .map(|r| {
                acc += r / total;
                acc
            })
            .collect();
        for p in &mut prob {
            *p /= total;
        }
        Some(EnvSampler { width: w, height: h, rows, cols, prob })
    }

    /// A direction drawn from the uniforms `u` and its density per solid
    /// angle.
    pub fn sample(&self, u: (f64, f64)) -> Option<(DVec3, f64)> {
        let (w, h) = (self.width, self.height);
        let (y, _, fy) = cdf_step(&self.rows, u.0);
        let (x, _, fx) = cdf_step(&self.cols[y * w..(y + 1) * w], u.1);
        let (uu, vv) = ((x as f64 + fx) / w as f64, (y as f64 + fy) / h as f64);
        let st = (vv * PI).sin();
        if st <= 0.0 {
            return None;
        }
        let d = direction(uu, vv);
        let pdf = self.prob[y * w + x] * (w * h) as f64 / (TAU * PI * st);
        (pdf > 0.0).then_some((d, pdf))
    }

    /// The density per solid angle with which [`Self::sample`] draws `d`.
    pub fn pdf(&self, d: DVec3) -> f64 {
        let (w, h) = (self.width, self.height);
        let (x, y) = crate::camera::sky_patches::texel_of(d, w, h);
        let v = d.y.clamp(-1.0, 1.0).acos() / PI;
        let st = (v * PI).sin();
        if st <= 0.0 {
            return 0.0;
        }
        self.prob[y * w + x] * (w * h) as f64 / (TAU * PI * st)
    }
}

/// The step of the cumulative distribution `cdf` (non-decreasing, the
/// last 1, not empty) that uniform `u` falls in: its index, its
/// probability, and where `u` lies within it (0 to 1).
pub fn cdf_step(cdf: &[f64], u: f64) -> (usize, f64, f64) {
    let i = cdf.partition_point(|c| *c <= u).min(cdf.len() - 1);
    let below = if i == 0 { 0.0 } else { cdf[i - 1] };
    let p = cdf[i] - below;
    (i, p, ((u - below) / p.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0))
}

/// The direction (scene frame, unit) at equirectangular image coordinates
/// (u, v) in [0, 1]: longitude from +z toward +x, latitude from +y down
/// (the inverse of `camera::sky_patches::texel_of`'s mapping).
pub fn direction(u: f64, v: f64) -> DVec3 {
    let (theta, phi) = (v * PI, (u - 0.5) * TAU);
    DVec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_density_integrates_to_one_and_matches_the_draws() {
        // a bright patch in a dim sky
        let (w, h) = (32, 16);
        let mut pixels = vec![DVec3::splat(0.1); w * h];
        pixels[5 * w + 20] = DVec3::splat(50.0);
        let s = EnvSampler::new(&Image { width: w, height: h, pixels }).unwrap();
        // ∫ pdf dω by a fine sum over the sphere
        let n = 400;
        let mut total = 0.0;
        for i in 0..n {
            for j in 0..2 * n {
                let theta = (i as f64 + 0.5) / n as f64 * PI;
                let phi = (j as f64 + 0.5) / (2 * n) as f64 * TAU - PI;
                let d = DVec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos());
                total += s.pdf(d) * theta.sin() * (PI / n as f64) * (TAU / (2 * n) as f64);
            }
        }
        assert!((total - 1.0).abs() < 0.01, "{total}");
        // the draws' own density is the one reported
        for k in 0..200 {
            let u = ((k as f64 + 0.5) / 200.0, (k as f64 * 0.618_034).fract());
            if let Some((d, pdf)) = s.sample(u) {
                assert!((s.pdf(d) / pdf - 1.0).abs() < 1e-9, "{k}");
            }
        }
    }
}
