//! Companion wavelengths splatted to the pixel they land in.
//!
//! Through a dispersive lens a sample's four wavelengths leave along one
//! scene ray from four film points (`Camera::rays_spectral`); on the double
//! Gauss 13% of the companions land in another pixel than their hero. Each
//! wavelength's light is added to the pixel its own film point lies in, so
//! no wavelength of a path is lost. With the box filter every pixel's
//! samples cover the film uniformly (spp per pixel area everywhere), so the
//! film-wide density of a film point is the same for every wavelength and
//! the balance heuristic over the four possible heroes weighs by the
//! pupil densities alone. docs/rendering.md gives the estimator.

use crate::camera::SpectralLane;
use crate::spectrum::sampled::N;
use crate::spectrum::{cie, SampledSpectrum, SampledWavelengths};
use glam::DVec3;

/// Rows above and below a row whose splats are kept densely.
const REACH: usize = 2;

/// The XYZ a row's samples add to other pixels: densely for the rows within
/// [`REACH`] of it, as a list beyond.
pub(crate) struct Splats {
    /// The row the samples belong to.
    y: usize,
    /// Image width and height, pixels.
    w: usize,
    h: usize,
    /// Rows `y - REACH ..= y + REACH` (clipped to the image), `w` each.
    near: Vec<DVec3>,
    /// The first row of `near`.
    first: usize,
    /// Pixel index and XYZ, for pixels farther away.
    far: Vec<(usize, DVec3)>,
}

impl Splats {
    /// An empty set for the samples of row `y` of a `w` x `h` image.
    pub(crate) fn new(y: usize, w: usize, h: usize) -> Self {
        let first = y.saturating_sub(REACH);
        let last = (y + REACH).min(h.saturating_sub(1));
        Splats { y, w, h, near: vec![DVec3::ZERO; (last + 1 - first) * w], first, far: Vec::new() }
    }

    /// Adds `xyz` to pixel (`px`, `py`).
    fn add(&mut self, px: usize, py: usize, xyz: DVec3) {
        if py >= self.first && py <= self.y + REACH {
            self.near[(py - self.first) * self.w + px] += xyz;
        } else {
            self.far.push((py * self.w + px, xyz));
        }
    }

    /// Adds the splats to `film` (linear sRGB, `w * h` pixels), each XYZ
    /// times `scale` and converted.
    pub(crate) fn merge_into(self, film: &mut [DVec3], scale: f64) {
        let start = self.first * self.w;
        for (p, xyz) in film[start..start + self.near.len()].iter_mut().zip(&self.near) {
            if *xyz != DVec3::ZERO {
                *p += cie::xyz_to_rgb(*xyz * scale);
            }
        }
        for (i, xyz) in self.far {
            if i < self.w * self.h {
                film[i] += cie::xyz_to_rgb(xyz * scale);
            }
        }
    }
}

/// One spectral camera sample of pixel (`x`, `y`) through a dispersive
/// lens, box filter: each wavelength's XYZ, `l x̄ T / (p(λ) Σ_m q_m)` (`T`
/// its transmission, `p` its wavelength density, `q_m` the pupil density
/// with which the camera would have drawn the scene ray with wavelength `m`
/// as the hero), goes to the pixels its film point may lie in: the hero's
/// to the pixel of its film point; a companion's over the pixels that the
/// cell its hero was drawn in (`cell`: centre and half-size, film u, v),
/// moved by the companion's offset from the hero, overlaps, each the share
/// it overlaps. That is where the companion's film point lies on average
/// over the hero's draw within its cell (exactly, where the offset does not
/// change across the cell); a point splat sends each companion to one
/// pixel or the next at random, and a pixel got a random mix of
/// wavelengths (colour speckle, docs/rendering.md). The returned value is
/// for (`x`, `y`) itself, `splats` has the others (off the film: nowhere).
/// Where the scene ended the companions, the hero alone, here.
pub(crate) fn splat_sample(
    wl: &SampledWavelengths,
    l: SampledSpectrum,
    lanes: &[SpectralLane; N],
    (x, y): (usize, usize),
    cell: ((f64, f64), (f64, f64)),
    splats: &mut Splats,
) -> DVec3 {
    if wl.secondary_terminated() {
        let lane = &lanes[0];
        return if lane.density > 0.0 {
            cie::cmf(wl.nm[0]) * (l.0[0] * lane.transmission / (wl.pdf[0] * lane.density))
        } else {
            DVec3::ZERO
        };
    }
    let total: f64 = lanes.iter().map(|m| m.density).sum();
    if !(total > 0.0 && total.is_finite()) {
        return DVec3::ZERO;
    }
    let (w, h) = (splats.w as f64, splats.h as f64);
    let mut own = DVec3::ZERO;
    let mut put = |px: f64, py: f64, xyz: DVec3| {
        if !(px >= 0.0 && py >= 0.0 && px < w && py < h) {
            return;
        }
        let (px, py) = (px as usize, py as usize);
        if (px, py) == (x, y) {
            own += xyz;
        } else {
            splats.add(px, py, xyz);
        }
    };
    let ((cu, cv), (hu, hv)) = cell;
    for (j, lane) in lanes.iter().enumerate() {
        let f = l.0[j] * lane.transmission;
        if lane.density <= 0.0 || f == 0.0 {
            continue;
        }
        let xyz = cie::cmf(wl.nm[j]) * (f / (wl.pdf[j] * total));
        if j == 0 || !(hu > 0.0 && hv > 0.0) {
            put((lane.film.0 * w).floor(), (lane.film.1 * h).floor(), xyz);
            continue;
        }
        // the hero's cell moved by this lane's offset, in pixels
        let (du, dv) = (lane.film.0 - lanes[0].film.0, lane.film.1 - lanes[0].film.1);
        let (u0, u1) = ((cu + du - hu) * w, (cu + du + hu) * w);
        let (v0, v1) = ((cv + dv - hv) * h, (cv + dv + hv) * h);
        if !(u0.is_finite() && u1.is_finite() && v0.is_finite() && v1.is_finite()) {
            continue;
        }
        let area = (u1 - u0) * (v1 - v0);
        // the cell is at most a pixel wide: two columns and two rows at most
        let (pu, pv) = (u0.floor(), v0.floor());
        for (qu, a) in [(pu, (u1.min(pu + 1.0) - u0).max(0.0)), (pu + 1.0, (u1 - (pu + 1.0)).max(0.0))] {
            for (qv, b) in [(pv, (v1.min(pv + 1.0) - v0).max(0.0)), (pv + 1.0, (v1 - (pv + 1.0)).max(0.0))] {
                let share = a * b / area;
                if share > 0.0 {
                    put(qu, qv, xyz * share);
                }
            }
        }
    }
    own
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sample whose companions land in three other pixels (one far
    /// away, one off the film) gives each wavelength's light to its own
    /// pixel: what the pixel keeps plus what it sends is the whole of what
    /// the four lanes carry on the film.
    #[test]
    fn each_wavelength_goes_to_its_own_pixel() {
        let (w, h) = (10, 10);
        let wl = crate::spectrum::WavelengthRange::new(360.0, 830.0).sample_four(0.3);
        let film = |x: f64, y: f64| ((x + 0.5) / w as f64, (y + 0.5) / h as f64);
        let lane = |film: (f64, f64), density: f64| SpectralLane { film, transmission: 0.9, density };
        let lanes =
            [lane(film(4.0, 4.0), 2.0), lane(film(5.0, 4.0), 1.0), lane(film(4.0, 9.0), 1.5), lane((1.2, 0.5), 1.0)];
        let l = SampledSpectrum([1.0, 2.0, 3.0, 4.0]);
        let mut splats = Splats::new(4, w, h);
        // the hero drawn in a quarter-pixel cell around its film point
        let cell = (film(4.0, 4.0), (0.125 / w as f64, 0.125 / h as f64));
        let own = splat_sample(&wl, l, &lanes, (4, 4), cell, &mut splats);
        let total = 5.5;
        let part = |j: usize| cie::cmf(wl.nm[j]) * (l.0[j] * 0.9 / (wl.pdf[j] * total));
        assert!((own - part(0)).length() < 1e-12 * own.length());
        let mut img = vec![DVec3::ZERO; w * h];
        splats.merge_into(&mut img, 1.0);
        assert!((img[4 * w + 5] - cie::xyz_to_rgb(part(1))).length() < 1e-12);
        assert!((img[9 * w + 4] - cie::xyz_to_rgb(part(2))).length() < 1e-12);
        // the fourth lane left the film: nowhere
        let elsewhere: DVec3 = img.iter().copied().sum::<DVec3>() - img[4 * w + 5] - img[9 * w + 4];
        assert!(elsewhere.length() < 1e-12);
    }

    /// A companion half a pixel to the right of its hero, whose cell spans
    /// the pixel, goes half to the hero's pixel and half to the next: what
    /// its film point gives on average over the hero's draw in that cell.
    #[test]
    fn a_companion_goes_where_its_film_point_lies_on_average() {
        let (w, h) = (10, 10);
        let wl = crate::spectrum::WavelengthRange::new(360.0, 830.0).sample_four(0.3);
        let lane = |film: (f64, f64)| SpectralLane { film, transmission: 1.0, density: 1.0 };
        let hero = (0.45, 0.45);
        let lanes = [lane(hero), lane((0.50, 0.45)), lane(hero), lane(hero)];
        let l = SampledSpectrum([0.0, 1.0, 0.0, 0.0]);
        let mut splats = Splats::new(4, w, h);
        let cell = ((0.45, 0.45), (0.05, 0.05));
        let own = splat_sample(&wl, l, &lanes, (4, 4), cell, &mut splats);
        let mut img = vec![DVec3::ZERO; w * h];
        splats.merge_into(&mut img, 1.0);
        let next = img[4 * w + 5];
        let own = cie::xyz_to_rgb(own);
        assert!((own - next).length() < 1e-12 * own.length(), "{own} against {next}");
        let whole = cie::xyz_to_rgb(cie::cmf(wl.nm[1]) * (1.0 / (wl.pdf[1] * 4.0)));
        assert!((own + next - whole).length() < 1e-12 * whole.length());
    }
}
