//! Exit-pupil bounds of the real-lens camera: for each film position, a
//! region of the rear vertex plane that contains every point a passing
//! ray can be aimed at, and a uniform way to draw targets from it. The
//! tighter the region, the more camera rays pass (pbrt-v4's bounding boxes
//! pass about 70%).
//!
//! - A round stop: the lens and stop are symmetric about the axis, so the
//!   bounds depend on the film radius alone; they are made for film points
//!   on +x in 96 radial bins and rotated to each film point's azimuth. A
//!   bin's region is a star-shaped polygon about the centroid of the
//!   passing probes: its boundary is found along 256 directions by
//!   bisection (to 1/4096 of the region's box) for the bin's two edge radii
//!   and its middle, and grown for the film radii between them (a quarter
//!   of their spread), for the boundary between directions (the largest of
//!   three neighbours, over the cosine of half the angle between them) and
//!   by half a percent. Targets are drawn from its triangles by an alias
//!   table. Where the region is not star-shaped (a probe that passes lies
//!   outside the polygon, or the centre does not pass), a set of cells
//!   takes over: a 32 x 32 grid over the region's box, the cells that
//!   passing probes reach (grown by one cell), those on the edge split
//!   8 x 8 and kept only where a passing probe lies within one sub-cell.
//!   Probes go as batches through the lens crate's batch tracer, the bins
//!   in parallel.
//! - A shaped stop (polygon, mask): rotating the bounds would turn the
//!   shape against the lens, so the shape itself bounds. Per radial bin,
//!   the map from rear-plane target to stop point is fitted by an affine
//!   map (least squares over the bin's passing probes); for each of 64
//!   slices of the film point's azimuth over the shape's period of symmetry,
//!   the round stop's polygon is clipped by the shape turned to the slice
//!   (grown for the turns within it and for the fit's worst residual) and
//!   mapped back, all in the frame of a film point on +x. Where the round
//!   stop's bounds are not star-shaped, the shape alone, mapped back, is
//!   drawn from.
//!
//! Either way the density of targets over the rear plane is known exactly
//! (uniform over the region), so the estimator is unbiased as long as the
//! region contains every passing target, which the growth margins see to.
//!
//! A frame sequence's focus pull shares one set of bounds over its films:
//! the probes go from film points at the ends and middle of the pull (each
//! a "film radius" of the bin, so the growth for the radii between them
//! covers the films between them too), in the coordinates of the middle
//! film; a film elsewhere sees a target scaled about its film point by
//! [`pupil_scale`], which keeps the ray's point in the paraxial exit pupil.
//!
//! A lens with glasses passes a slightly different region at each
//! wavelength: a probe counts as passing when it passes at the primary
//! wavelength or at either end of the range a spectral render samples, so
//! the region holds them all. (A shaped stop's map from rear plane to stop
//! is fitted at the primary wavelength; its margin is the fit's residual.)

mod cells;
mod fan;
mod shape;
mod shared;
mod star;

pub use fan::Fan;
pub(crate) use shared::bounded_ends;
pub use shared::SharedPupil;

use super::aperture::Aperture;
use cells::cells_bin;
use lens::{DVec3, Prescription, RayBatch, Tracer};
use rayon::prelude::*;
use shape::stop_bin;
use star::star_bin;

/// A point of the rear plane or the stop, mm.
pub(super) type Point = (f64, f64);
/// A film point probed: its distance from the axis (on +x) and the film's
/// z, mm (a frame sequence bounds several film positions at once).
pub(super) type FilmPoint = (f64, f64);
/// A box: x min, x max, y min, y max, mm.
pub(super) type Bounds = [f64; 4];

/// Radial bins of the bounds.
const BINS: usize = 96;
/// Probes across the rear element when finding a bin's box.
const COARSE: usize = 32;
/// Cells across a bin's box.
pub(super) const CELLS: usize = 32;
/// Sub-cells across an edge cell.
pub(super) const SUB: usize = 8;
/// Film radii probed per bin (its two edges and its middle).
const RADII: usize = 3;

/// The bounds of one radial bin.
#[derive(Debug, Clone)]
pub enum PupilBounds {
    /// No ray passes from this film radius.
    Empty,
    /// Cells of the rear vertex plane for a film point on +x, of two
    /// sizes: whole grid cells and the sub-cells of the region's edge. A
    /// size is chosen in proportion to its share of the area, then a cell
    /// of that size uniformly (no search).
    Cells {
        /// Lower-left corners of the whole cells, mm.
        whole: Vec<[f64; 2]>,
        /// Side of the whole cells, mm.
        whole_side: f64,
        /// Lower-left corners of the edge sub-cells, mm.
        sub: Vec<[f64; 2]>,
        /// Side of the sub-cells, mm.
        sub_side: f64,
    },
    /// A star-shaped polygon for a film point on +x (round stop).
    Star(Fan),
    /// For a shaped stop: for each of `buckets.len()` slices of the film
    /// point's azimuth over the shape's period of symmetry, the round-stop
    /// polygon clipped by the stop's shape mapped back (for a film point on
    /// +x; the shape turns against the film point).
    Shaped {
        /// The shape's period of symmetry, radians (2 pi / blades for a
        /// polygon).
        period: f64,
        /// One fan per slice of azimuth.
        buckets: Vec<Fan>,
    },
    /// The stop's shape mapped back to the rear plane.
    Stop {
        /// Target = `inverse` (stop point - `offset`), for a film point on
        /// +x (the 2 x 2 matrix, row-major).
        inverse: [f64; 4],
        /// The fitted map's offset, mm.
        offset: [f64; 2],
        /// Shapes are drawn at this multiple of the stop's radius.
        scale: f64,
        /// The region's area on the rear plane, mm^2.
        area: f64,
    },
}

/// The bounds for every film radius.
#[derive(Debug, Clone)]
pub struct PupilTables {
    bin_width: f64,
    bins: Vec<PupilBounds>,
    /// For a shaped stop: the shape and the stop's radius, mm.
    stop: Option<(Aperture, f64)>,
}

/// The lens traced in two parts for probing: film to the stop (round stop
/// clipping), then on to object space; a probe passes when it gets through
/// both, and its stop point is where the first part left it.
pub(super) struct Probe {
    whole: Tracer,
    /// The whole lens at the other wavelengths bounded (none for a lens
    /// without glasses).
    others: Vec<Tracer>,
    to_stop: Tracer,
    rest: Option<Tracer>,
    z_rear: f64,
    /// The film the bounds' coordinates belong to (mm from the first
    /// vertex) and the paraxial exit pupil's z: see [`pupil_scale`].
    z_ref: f64,
    z_xp: Option<f64>,
    /// The paraxial exit pupil (z, radius), mm: where a small stop's rays
    /// go, for finding them when the probes across the rear element are
    /// too coarse.
    exit_pupil: Option<(f64, f64)>,
}

impl Probe {
    /// Fills `batch` with rays from the film point `(r, z)` (on +x, the
    /// film at z) toward each target on the rear plane.
    fn aim(&self, (r, z_film): FilmPoint, targets: &[(f64, f64)], batch: &mut RayBatch) {
        batch.clear();
        let dz = self.z_rear - z_film;
        let origin = DVec3::new(r, 0.0, z_film);
        let k = pupil_scale(self.z_ref, z_film, self.z_rear, self.z_xp);
        for &(x, y) in targets {
            // a target of the bounds' film, scaled for this film
            let d = DVec3::new((x - r) * k, y * k, dz);
            let len = d.length();
            if len > 0.0 && len.is_finite() {
                batch.push(lens::Ray { origin, direction: d / len });
            } else {
                batch.push_skipped();
            }
        }
    }

    /// For every film point of `points` and target in `targets`: the stop
    /// point (mm, lens frame) where the ray passes, indexed
    /// `[point][target]`.
    pub(super) fn stop_points(&self, points: &[FilmPoint], targets: &[(f64, f64)]) -> Vec<Vec<Option<(f64, f64)>>> {
        let mut batch = RayBatch::with_capacity(targets.len());
        points
            .iter()
            .map(|&r| {
                self.aim(r, targets, &mut batch);
                self.to_stop.trace_soa(&mut batch);
                let at_stop: Vec<(f64, f64)> = batch.x.iter().zip(&batch.y).map(|(x, y)| (*x, *y)).collect();
                if let Some(rest) = &self.rest {
                    rest.trace_soa(&mut batch);
                }
                batch.status.iter().zip(at_stop).map(|(s, at)| (*s == 0).then_some(at)).collect()
            })
            .collect()
    }

    /// Whether the ray toward each target passes, for each film point of
    /// `points`, indexed `[point][target]`.
    pub(super) fn passes_each(&self, points: &[FilmPoint], targets: &[(f64, f64)]) -> Vec<Vec<bool>> {
        let mut batch = RayBatch::with_capacity(targets.len());
        points
            .iter()
            .map(|&r| {
                let mut pass = vec![false; targets.len()];
                self.each_wavelength(r, targets, &mut batch, |i| pass[i] = true);
                pass
            })
            .collect()
    }

    /// Calls `passed(i)` for each target `i` whose ray from film point
    /// `r` passes at any of the bounded wavelengths.
    fn each_wavelength(
        &self,
        r: FilmPoint,
        targets: &[(f64, f64)],
        batch: &mut RayBatch,
        mut passed: impl FnMut(usize),
    ) {
        for tracer in std::iter::once(&self.whole).chain(&self.others) {
            self.aim(r, targets, batch);
            tracer.trace_soa(batch);
            for (i, s) in batch.status.iter().enumerate() {
                if *s == 0 {
                    passed(i);
                }
            }
        }
    }

    /// Whether the ray toward each target passes from any film point of
    /// `points`.
    pub(super) fn passes(&self, points: &[FilmPoint], targets: &[(f64, f64)]) -> Vec<bool> {
        let mut batch = RayBatch::with_capacity(targets.len());
        let mut any = vec![false; targets.len()];
        for &r in points {
            self.each_wavelength(r, targets, &mut batch, |i| any[i] = true);
        }
        any
    }
}

impl PupilTables {
    /// Bounds the exit pupil of the prescription `p` for film points up
    /// to `half_diag` mm from the centre, the bins in parallel, at its
    /// primary wavelength and at each of `wavelengths_nm`, for a film at
    /// each of `z_films` (mm from the first vertex) and between them (a
    /// frame sequence's focus pull shares one set of bounds, so a sample
    /// is aimed alike in every frame; a still has one film). The bounds
    /// are in the coordinates of the film at `z_ref`: a film elsewhere
    /// scales them by [`pupil_scale`].
    pub(crate) fn build(
        p: &Prescription,
        aperture: &Aperture,
        z_films: &[f64],
        z_ref: f64,
        z_rear: f64,
        half_diag: f64,
        wavelengths_nm: &[f64],
    ) -> Self {
        let (stop, n) = (p.stop_index(), p.surfaces().len());
        let z_xp = lens::paraxial::FirstOrder::of(p).ok().and_then(|f| f.exit_pupil).map(|x| x.z);
        let probe = Probe {
            z_ref,
            z_xp,
            whole: Tracer::reverse(p),
            others: wavelengths_nm
                .iter()
                .filter_map(|nm| p.at_wavelength(*nm).ok())
                .map(|q| Tracer::reverse(&q))
                .collect(),
            to_stop: Tracer::reverse_range(p, stop..n),
            rest: (stop > 0).then(|| Tracer::reverse_range(p, 0..stop)),
            z_rear,
            exit_pupil: lens::paraxial::FirstOrder::of(p)
                .ok()
                .and_then(|f| f.exit_pupil)
                .map(|x| (x.z, x.diameter / 2.0))
                .filter(|x| x.0.is_finite() && x.1 > 0.0 && z_films.iter().all(|z| (x.0 - z).abs() > 0.0)),
        };
        let stop_sd = p.stop_semi_diameter();
        let rear = p.surfaces().iter().rev().find_map(|x| x.semi_diameter).unwrap_or(stop_sd) * 1.5;
        let bin_width = half_diag / BINS as f64;
        let shaped = (*aperture != Aperture::Circle).then(|| (aperture.clone(), stop_sd));
        let bins = (0..BINS)
            .into_par_iter()
            .map(|i| {
                let radii: Vec<FilmPoint> = (0..RADII)
                    .flat_map(|k| {
                        let r = bin_width * (i as f64 + k as f64 / (RADII - 1) as f64);
                        z_films.iter().map(move |&z| (r, z))
                    })
                    .collect();
                match &shaped {
                    None => star_bin(&probe, &radii, rear).unwrap_or_else(|| cells_bin(&probe, &radii, rear)),
                    Some((shape, sd)) => stop_bin(&probe, &radii, rear, shape, *sd),
                }
            })
            .collect();
        PupilTables { bin_width, bins, stop: shaped }
    }

    /// A target drawn with the uniforms `a` from the bounds for the film
    /// point (fx, fy) mm, turned to the film point's azimuth (lens frame,
    /// mm), and the area of the region it was drawn from (mm^2; targets are
    /// uniform over it). `None` when no ray passes from there.
    pub fn sample(&self, fx: f64, fy: f64, a: (f64, f64)) -> Option<(f64, (f64, f64))> {
        let (b, c, s) = self.bin_at(fx, fy)?;
        let rotate = |(x, y): (f64, f64)| (c * x - s * y, s * x + c * y);
        Some(match b {
            PupilBounds::Empty => return None,
            PupilBounds::Cells { whole, whole_side, sub, sub_side } => {
                let w_area = whole.len() as f64 * whole_side * whole_side;
                let area = w_area + sub.len() as f64 * sub_side * sub_side;
                let share = w_area / area;
                // the first uniform picks the size, then the cell, and its
                // remainder places the point across the cell
                let (cells, side, u) = if a.0 < share {
                    (whole, *whole_side, a.0 / share)
                } else {
                    (sub, *sub_side, (a.0 - share) / (1.0 - share))
                };
                let scaled = u * cells.len() as f64;
                let k = (scaled as usize).min(cells.len().checked_sub(1)?);
                let [x0, y0] = cells[k];
                let across = (scaled - k as f64).clamp(0.0, 1.0);
                (area, rotate((x0 + across * side, y0 + a.1 * side)))
            }
            PupilBounds::Star(fan) => (fan.area(), rotate(fan.sample(a))),
            PupilBounds::Shaped { period, buckets } => {
                let phi = s.atan2(c).rem_euclid(*period);
                let k = ((phi / period * buckets.len() as f64) as usize).min(buckets.len() - 1);
                (buckets[k].area(), rotate(buckets[k].sample(a)))
            }
            PupilBounds::Stop { inverse: m, offset, scale, area } => {
                let (shape, sd) = self.stop.as_ref()?;
                // a stop point in the lens frame, turned into the bin's
                // frame (film point on +x), mapped back, turned again
                let (ux, uy) = shape.sample_uniform(a);
                let (sx, sy) = (ux * scale * sd, uy * scale * sd);
                let (qx, qy) = (c * sx + s * sy - offset[0], -s * sx + c * sy - offset[1]);
                (*area, rotate((m[0] * qx + m[1] * qy, m[2] * qx + m[3] * qy)))
            }
        })
    }
}

impl PupilTables {
    /// The bin of film point (fx, fy) mm, and the cosine and sine of its
    /// azimuth.
    fn bin_at(&self, fx: f64, fy: f64) -> Option<(&PupilBounds, f64, f64)> {
        let r = (fx * fx + fy * fy).sqrt();
        if !r.is_finite() {
            return None;
        }
        let bin = ((r / self.bin_width) as usize).min(BINS - 1);
        let b = self.bins.get(bin)?;
        let (c, s) = if r > 0.0 {
            let inv = 1.0 / r;
            (fx * inv, fy * inv)
        } else {
            (1.0, 0.0)
        };
        Some((b, c, s))
    }

    /// The area (mm^2) of the region targets are drawn from for film point
    /// (fx, fy) mm: what [`Self::sample`] returns with its target. `None`
    /// where no ray passes.
    pub fn area_at(&self, fx: f64, fy: f64) -> Option<f64> {
        let (b, c, s) = self.bin_at(fx, fy)?;
        match b {
            PupilBounds::Empty => None,
            PupilBounds::Cells { whole, whole_side, sub, sub_side } => {
                Some(whole.len() as f64 * whole_side * whole_side + sub.len() as f64 * sub_side * sub_side)
            }
            PupilBounds::Star(fan) => Some(fan.area()),
            PupilBounds::Shaped { period, buckets } => {
                let phi = s.atan2(c).rem_euclid(*period);
                let k = ((phi / period * buckets.len() as f64) as usize).min(buckets.len() - 1);
                Some(buckets[k].area())
            }
            PupilBounds::Stop { area, .. } => Some(*area),
        }
    }
}

/// The probes' box: targets on a `COARSE` grid over the rear element, and
/// the box of those through which any of `radii` passes, grown by a probe
/// step. `None` when nothing passes.
pub(super) fn passing_box(probe: &Probe, radii: &[FilmPoint], rear: f64) -> Option<[f64; 4]> {
    passing_probes(probe, radii, rear).map(|(b, _)| b)
}

/// [`passing_box`] and the probe targets that passed.
pub(super) fn passing_probes(probe: &Probe, radii: &[FilmPoint], rear: f64) -> Option<(Bounds, Vec<Point>)> {
    let step = 2.0 * rear / COARSE as f64;
    let mut targets: Vec<(f64, f64)> = (0..=COARSE)
        .flat_map(|j| (0..=COARSE).map(move |i| (-rear + step * i as f64, -rear + step * j as f64)))
        .collect();
    // and a grid over the paraxial exit pupil as seen from each film radius,
    // projected on the rear plane (three times its size)
    if let Some((z_xp, r_xp)) = probe.exit_pupil {
        for &(r, z_film) in radii {
            let k = (probe.z_rear - z_film) / (z_xp - z_film);
            // in the bounds' coordinates
            let back = 1.0 / pupil_scale(probe.z_ref, z_film, probe.z_rear, probe.z_xp);
            let (cx, half) = (r + (0.0 - r) * k * back, 1.5 * r_xp * (k * back).abs());
            if !(cx.is_finite() && half.is_finite() && half > 0.0) {
                continue;
            }
            let n = 16;
            for j in 0..=n {
                for i in 0..=n {
                    let u = (i as f64 / n as f64) * 2.0 - 1.0;
                    let v = (j as f64 / n as f64) * 2.0 - 1.0;
                    targets.push((cx + half * u, half * v));
                }
            }
        }
    }
    let pass = probe.passes(radii, &targets);
    let passed: Vec<(f64, f64)> = targets.iter().zip(&pass).filter(|(_, p)| **p).map(|(t, _)| *t).collect();
    let mut b = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
    for &(x, y) in &passed {
        b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
    }
    // grown by a probe step of whichever grid found the edge
    let grow = step.min((b[1] - b[0]).max(b[3] - b[2]).max(f64::MIN_POSITIVE));
    b[0].is_finite().then_some(([b[0] - grow, b[1] + grow, b[2] - grow, b[3] + grow], passed))
}

/// How a film at `z_film` sees bounds made in the coordinates of the film
/// at `z_ref` (mm from the first vertex): a target t of the bounds, for a
/// film point f, is aimed at f + (t - f) k on the rear plane (`z_rear`), so
/// that the ray passes through the same point of the paraxial exit pupil
/// (at `z_xp`) from either film: k is the ratio of the rear plane's
/// distances along the rays to the pupil, (z_rear - z_film) / (z_xp -
/// z_film) over the same at z_ref. A sample's aim then moves with the film
/// the way the pupil's image does, and a ray near the edge of the passing
/// region stays on its side from frame to frame. 1 (exactly) for the film
/// the bounds were made at or a pupil at infinity; the region's area
/// scales by k^2.
pub(crate) fn pupil_scale(z_ref: f64, z_film: f64, z_rear: f64, z_xp: Option<f64>) -> f64 {
    if z_film == z_ref {
        return 1.0;
    }
    let Some(z_xp) = z_xp else { return 1.0 };
    let k = ((z_rear - z_film) / (z_xp - z_film)) / ((z_rear - z_ref) / (z_xp - z_ref));
    if k.is_finite() && k > 0.0 {
        k
    } else {
        1.0
    }
}
