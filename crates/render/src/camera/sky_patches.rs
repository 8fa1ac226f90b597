//! The bright parts of an environment image (a sun, a window, street
//! lights in a night panorama) as light sources traced into a real lens
//! (`lamp_light/`): the texels at least [`BRIGHT`] times the image's mean
//! radiance, grouped into patches of touching texels (the [`MAX_PATCHES`]
//! most powerful traced, any others left to camera paths), each sampled by
//! its texels' power.

use crate::envmap::{cdf_step, direction};
use crate::image::Image;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// A texel is bright from this many times the image's mean radiance
/// (luminance over the sphere).
pub const BRIGHT: f64 = 16.0;

/// Patches traced from the sky, at most (the most powerful).
pub const MAX_PATCHES: usize = 16;

/// Texels probed per patch, at most (their corners, spread over the patch).
const MAX_PROBE_TEXELS: usize = 64;

/// The texel (column, row) of an equirectangular image `w` x `h` that
/// direction `d` (scene frame, unit) looks up: longitude from +z toward
/// +x, latitude from +y down. The one mapping of the environment
/// background and everything that partitions it.
pub fn texel_of(d: DVec3, w: usize, h: usize) -> (usize, usize) {
    let u = 0.5 + d.x.atan2(d.z) / TAU;
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    (((u * w as f64) as usize).min(w - 1), ((v * h as f64) as usize).min(h - 1))
}

/// One patch of bright texels.
#[derive(Debug, Clone)]
pub struct SkyPatch {
    w: usize,
    h: usize,
    /// Texel indices (row-major) and the cumulative probability of
    /// choosing each (in proportion to its luminance times its solid
    /// angle), the last 1.
    texels: Vec<usize>,
    cdf: Vec<f64>,
    /// The patch's power-weighted mean direction (scene frame, unit).
    pub centre: DVec3,
}

/// The bright patches of `img`: the [`MAX_PATCHES`] most powerful.
pub fn find(img: &Image) -> Vec<SkyPatch> {
    let (w, h) = (img.width, img.height);
    let lum = |k: usize| {
        let p = img.pixels[k];
        (0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z).max(0.0)
    };
    let sin = |y: usize| (PI * (y as f64 + 0.5) / h as f64).sin();
    let total: f64 = (0..w * h).map(|k| lum(k) * sin(k / w)).sum();
    let weight: f64 = (0..h).map(|y| sin(y) * w as f64).sum();
    let mean = total / weight.max(f64::MIN_POSITIVE);
    if !(mean > 0.0 && mean.is_finite()) {
        return Vec::new();
    }
    let bright: Vec<bool> = (0..w * h).map(|k| lum(k) >= BRIGHT * mean).collect();
    // touching bright texels (eight neighbours, longitude wrapping)
    let mut seen = vec![false; w * h];
    let mut groups: Vec<(f64, Vec<usize>)> = Vec::new();
    for start in 0..w * h {
        if !bright[start] || seen[start] {
            continue;
        }
        let (mut stack, mut members, mut power) = (vec![start], Vec::new(), 0.0);
        seen[start] = true;
        while let Some(k) = stack.pop() {
            members.push(k);
            power += lum(k) * sin(k / w);
            let (x, y) = ((k % w) as isize, (k / w) as isize);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let ny = y + dy;
                    if ny < 0 || ny >= h as isize {
                        continue;
                    }
                    let nx = (x + dx).rem_euclid(w as isize);
                    let n = ny as usize * w + nx as usize;
                    if bright[n] && !seen[n] {
                        seen[n] = true;
                        stack.push(n);
                    }
                }
            }
        }
        members.sort_unstable();
        groups.push((power, members));
    }
    groups.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1[0].cmp(&b.1[0])));
    groups.truncate(MAX_PATCHES);
    groups
        .into_iter()
        .map(|(power, texels)| {
            let mut acc = 0.0;
            let mut centre = DVec3::ZERO;
            let cdf = texels
                .iter()
                .map(|&k| {
                    let p = lum(k) * sin(k / w);
                    centre += direction(((k % w) as f64 + 0.5) / w as f64, ((k / w) as f64 + 0.5) / h as f64) * p;
                    acc += p / power;
                    acc
                })
                .collect::<Vec<f64>>();
            SkyPatch { w, h, texels, cdf, centre: centre.normalize_or(DVec3::Z) }
        })
        .collect()
}

impl SkyPatch {
    /// The patch's texels (row-major indices into the image).
    pub fn texels(&self) -> &[usize] {
        &self.texels
    }

    /// A direction (scene frame) drawn from the patch with the uniforms
    /// `u`: a texel by its power, uniform in its longitude and latitude;
    /// and its density per steradian.
    pub fn sample(&self, u: (f64, f64)) -> Option<(DVec3, f64)> {
        let (i, p, fx) = cdf_step(&self.cdf, u.0);
        let k = self.texels[i];
        let (x, y) = (k % self.w, k / self.w);
        let (uu, vv) = ((x as f64 + fx) / self.w as f64, (y as f64 + u.1) / self.h as f64);
        let st = (vv * PI).sin();
        let pdf = p * (self.w * self.h) as f64 / (TAU * PI * st);
        (st > 0.0 && pdf > 0.0).then(|| (direction(uu, vv), pdf))
    }

    /// Directions (scene frame) that probe where the patch's light can
    /// pass: its centre first, then the corners of up to
    /// [`MAX_PROBE_TEXELS`] of its texels spread over it.
    pub fn probe_directions(&self) -> Vec<DVec3> {
        let mut out = vec![self.centre];
        let step = self.texels.len().div_ceil(MAX_PROBE_TEXELS).max(1);
        for &k in self.texels.iter().step_by(step) {
            let (x, y) = ((k % self.w) as f64, (k / self.w) as f64);
            for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)] {
                out.push(direction((x + dx) / self.w as f64, (y + dy) / self.h as f64));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two bright spots (a sun of 2 x 2 texels, a lamp of one) on a dim
    /// sky make two patches, the sun first; draws land in their texels,
    /// with densities that integrate to one over the patch.
    #[test]
    fn bright_texels_make_patches_sampled_by_power() {
        let (w, h) = (64, 32);
        let mut pixels = vec![DVec3::splat(0.1); w * h];
        for k in [10 * w + 20, 10 * w + 21, 11 * w + 20, 11 * w + 21] {
            pixels[k] = DVec3::splat(1000.0);
        }
        pixels[20 * w + 63] = DVec3::splat(500.0);
        let img = Image { width: w, height: h, pixels };
        let patches = find(&img);
        assert_eq!(patches.len(), 2);
        assert_eq!(patches[1].texels, vec![20 * w + 63]);
        assert_eq!(patches[0].texels, vec![10 * w + 20, 10 * w + 21, 11 * w + 20, 11 * w + 21]);
        let n = 64;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let u = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                let (d, pdf) = patches[0].sample(u).unwrap();
                let (x, y) = texel_of(d, w, h);
                assert!(patches[0].texels.contains(&(y * w + x)), "{u:?} -> texel {x}, {y}");
                // 1 / pdf averages to the patch's solid angle
                integral += 1.0 / pdf / (n * n) as f64;
            }
        }
        let solid: f64 = patches[0]
            .texels
            .iter()
            .map(|&k| {
                let y = (k / w) as f64;
                TAU / w as f64 * (((y / h as f64) * PI).cos() - (((y + 1.0) / h as f64) * PI).cos())
            })
            .sum();
        assert!((integral / solid - 1.0).abs() < 1e-3, "{integral} vs {solid}");
    }
}
