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
//!   shape, so the shape itself is sampled. Per radial bin, the map from
//!   rear-plane target to stop point is fitted by an affine map (least
//!   squares over the bin's passing probes) and targets are drawn by
//!   drawing stop points uniformly over the shape grown by the fit's worst
//!   residual (with margin) and mapping them back; the map is rotated with
//!   the film point, and the shape stays fixed in the lens, because the
//!   stop point is drawn in the lens frame.
//!
//! Either way the density of targets over the rear plane is known exactly
//! (uniform over the region), so the estimator is unbiased as long as the
//! region contains every passing target, which the growth margins see to.

use super::aperture::Aperture;
use lens::{DVec3, Prescription, RayBatch, Tracer};
use rayon::prelude::*;

/// A point of the rear plane or the stop, mm.
type Point = (f64, f64);
/// A box: x min, x max, y min, y max, mm.
type Bounds = [f64; 4];

/// Radial bins of the bounds.
const BINS: usize = 96;
/// Probes across the rear element when finding a bin's box.
const COARSE: usize = 32;
/// Cells across a bin's box.
const CELLS: usize = 32;
/// Sub-cells across an edge cell.
const SUB: usize = 8;
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
    /// A star-shaped polygon about `centre` for a film point on +x, drawn
    /// from by choosing one of its triangles (centre and two neighbouring
    /// corners) in proportion to its area.
    Star {
        /// The centre, mm.
        centre: [f64; 2],
        /// The corners relative to the centre, mm, by angle.
        corners: Vec<[f64; 2]>,
        /// Alias table over the triangles (probability of keeping the
        /// triangle, the other one), for a choice in proportion to area in
        /// constant time.
        alias: Vec<(f64, u32)>,
        /// Total area, mm^2.
        area: f64,
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

impl PupilBounds {
    /// Area of the region targets are drawn from, mm^2 (the inverse of
    /// their density).
    pub fn area(&self) -> f64 {
        match self {
            PupilBounds::Empty => 0.0,
            PupilBounds::Cells { whole, whole_side, sub, sub_side } => {
                whole.len() as f64 * whole_side * whole_side + sub.len() as f64 * sub_side * sub_side
            }
            PupilBounds::Stop { area, .. } => *area,
            PupilBounds::Star { area, .. } => *area,
        }
    }
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
struct Probe {
    whole: Tracer,
    to_stop: Tracer,
    rest: Option<Tracer>,
    z_film: f64,
    z_rear: f64,
    /// The paraxial exit pupil (z, radius), mm: where a small stop's rays
    /// go, for finding them when the probes across the rear element are
    /// too coarse.
    exit_pupil: Option<(f64, f64)>,
}

impl Probe {
    /// Fills `batch` with rays from the film point at radius `r` (on +x)
    /// toward each target on the rear plane.
    fn aim(&self, r: f64, targets: &[(f64, f64)], batch: &mut RayBatch) {
        batch.clear();
        let dz = self.z_rear - self.z_film;
        let origin = DVec3::new(r, 0.0, self.z_film);
        for &(x, y) in targets {
            let d = DVec3::new(x - r, y, dz);
            let len = d.length();
            if len > 0.0 && len.is_finite() {
                batch.push(lens::Ray { origin, direction: d / len });
            } else {
                batch.push(lens::Ray::default());
                let last = batch.len() - 1;
                batch.status[last] = u64::MAX;
            }
        }
    }

    /// For every film radius in `radii` (film point on +x) and target in
    /// `targets`: the stop point (mm, lens frame) where the ray passes,
    /// indexed `[radius][target]`.
    fn stop_points(&self, radii: &[f64], targets: &[(f64, f64)]) -> Vec<Vec<Option<(f64, f64)>>> {
        let mut batch = RayBatch::with_capacity(targets.len());
        radii
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

    /// Whether the ray toward each target passes, for each film radius of
    /// `radii` (film points on +x), indexed `[radius][target]`.
    fn passes_each(&self, radii: &[f64], targets: &[(f64, f64)]) -> Vec<Vec<bool>> {
        let mut batch = RayBatch::with_capacity(targets.len());
        radii
            .iter()
            .map(|&r| {
                self.aim(r, targets, &mut batch);
                self.whole.trace_soa(&mut batch);
                batch.status.iter().map(|s| *s == 0).collect()
            })
            .collect()
    }

    /// Whether the ray toward each target passes from any film radius of
    /// `radii` (film points on +x).
    fn passes(&self, radii: &[f64], targets: &[(f64, f64)]) -> Vec<bool> {
        let mut batch = RayBatch::with_capacity(targets.len());
        let mut any = vec![false; targets.len()];
        for &r in radii {
            self.aim(r, targets, &mut batch);
            self.whole.trace_soa(&mut batch);
            for (a, s) in any.iter_mut().zip(&batch.status) {
                *a |= *s == 0;
            }
        }
        any
    }
}

impl PupilTables {
    /// Bounds the exit pupil of the focused prescription `p` for film
    /// points up to `half_diag` mm from the centre, the bins in parallel.
    pub(crate) fn build(p: &Prescription, aperture: &Aperture, z_film: f64, z_rear: f64, half_diag: f64) -> Self {
        let (stop, n) = (p.stop_index(), p.surfaces().len());
        let probe = Probe {
            whole: Tracer::reverse(p),
            to_stop: Tracer::reverse_range(p, stop..n),
            rest: (stop > 0).then(|| Tracer::reverse_range(p, 0..stop)),
            z_film,
            z_rear,
            exit_pupil: lens::paraxial::FirstOrder::of(p)
                .ok()
                .and_then(|f| f.exit_pupil)
                .map(|x| (x.z, x.diameter / 2.0))
                .filter(|x| x.0.is_finite() && x.1 > 0.0 && (x.0 - z_film).abs() > 0.0),
        };
        let stop_sd = p.stop_semi_diameter();
        let rear = p.surfaces().iter().rev().find_map(|x| x.semi_diameter).unwrap_or(stop_sd) * 1.5;
        let bin_width = half_diag / BINS as f64;
        let shaped = (*aperture != Aperture::Circle).then(|| (aperture.clone(), stop_sd));
        let bins = (0..BINS)
            .into_par_iter()
            .map(|i| {
                let radii: Vec<f64> =
                    (0..RADII).map(|k| bin_width * (i as f64 + k as f64 / (RADII - 1) as f64)).collect();
                match &shaped {
                    None => star_bin(&probe, &radii, rear).unwrap_or_else(|| cells_bin(&probe, &radii, rear)),
                    Some((shape, sd)) => stop_bin(&probe, &radii, rear, shape, *sd),
                }
            })
            .collect();
        PupilTables { bin_width, bins, stop: shaped }
    }

    /// The bounds for the film point (fx, fy) mm and a target drawn from
    /// them with the uniforms `a`, rotated to the film point's azimuth
    /// (lens frame, mm). `None` when no ray passes from there.
    pub fn sample(&self, fx: f64, fy: f64, a: (f64, f64)) -> Option<(&PupilBounds, (f64, f64))> {
        let r = (fx * fx + fy * fy).sqrt();
        let bin = ((r / self.bin_width) as usize).min(BINS - 1);
        let b = self.bins.get(bin)?;
        let (c, s) = if r > 0.0 {
            let inv = 1.0 / r;
            (fx * inv, fy * inv)
        } else {
            (1.0, 0.0)
        };
        let rotate = |(x, y): (f64, f64)| (c * x - s * y, s * x + c * y);
        let t = match b {
            PupilBounds::Empty => return None,
            PupilBounds::Cells { whole, whole_side, sub, sub_side } => {
                let w_area = whole.len() as f64 * whole_side * whole_side;
                let share = w_area / b.area();
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
                rotate((x0 + across * side, y0 + a.1 * side))
            }
            PupilBounds::Star { centre, corners, alias, .. } => {
                // a triangle by the alias table, the first uniform's
                // remainder reused across the triangle
                let scaled = a.0 * alias.len() as f64;
                let j = (scaled as usize).min(alias.len() - 1);
                let u = scaled - j as f64;
                let (keep, other) = alias[j];
                let (k, rest) = if u < keep { (j, u / keep) } else { (other as usize, (u - keep) / (1.0 - keep)) };
                let (mut s1, mut t1) = (rest.clamp(0.0, 1.0), a.1);
                if s1 + t1 > 1.0 {
                    (s1, t1) = (1.0 - s1, 1.0 - t1);
                }
                let (p, q) = (corners[k], corners[(k + 1) % corners.len()]);
                rotate((centre[0] + s1 * p[0] + t1 * q[0], centre[1] + s1 * p[1] + t1 * q[1]))
            }
            PupilBounds::Stop { inverse: m, offset, scale, .. } => {
                let (shape, sd) = self.stop.as_ref()?;
                // a stop point in the lens frame, turned into the bin's
                // frame (film point on +x), mapped back, turned again
                let (ux, uy) = shape.sample_uniform(a);
                let (sx, sy) = (ux * scale * sd, uy * scale * sd);
                let (qx, qy) = (c * sx + s * sy - offset[0], -s * sx + c * sy - offset[1]);
                rotate((m[0] * qx + m[1] * qy, m[2] * qx + m[3] * qy))
            }
        };
        Some((b, t))
    }

    /// Number of radial bins.
    pub fn bins(&self) -> usize {
        self.bins.len()
    }
}

/// The probes' box: targets on a `COARSE` grid over the rear element, and
/// the box of those through which any of `radii` passes, grown by a probe
/// step. `None` when nothing passes.
fn passing_box(probe: &Probe, radii: &[f64], rear: f64) -> Option<[f64; 4]> {
    passing_probes(probe, radii, rear).map(|(b, _)| b)
}

/// [`passing_box`] and the probe targets that passed.
fn passing_probes(probe: &Probe, radii: &[f64], rear: f64) -> Option<(Bounds, Vec<Point>)> {
    let step = 2.0 * rear / COARSE as f64;
    let mut targets: Vec<(f64, f64)> = (0..=COARSE)
        .flat_map(|j| (0..=COARSE).map(move |i| (-rear + step * i as f64, -rear + step * j as f64)))
        .collect();
    // and a grid over the paraxial exit pupil as seen from each film radius,
    // projected on the rear plane (three times its size)
    if let Some((z_xp, r_xp)) = probe.exit_pupil {
        let k = (probe.z_rear - probe.z_film) / (z_xp - probe.z_film);
        for &r in radii {
            let (cx, half) = (r + (0.0 - r) * k, 1.5 * r_xp * k.abs());
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

/// Directions of a star-shaped region's boundary.
const DIRECTIONS: usize = 256;
/// Bisection steps along each direction (to 1/4096 of the box).
const BISECTIONS: usize = 12;

/// The star-shaped bounds of one bin (see the module's description), or
/// `None` where the region is not star-shaped about the passing probes'
/// centroid for every film radius of the bin (the cells take over).
fn star_bin(probe: &Probe, radii: &[f64], rear: f64) -> Option<PupilBounds> {
    let (b, passed) = passing_probes(probe, radii, rear)?;
    let n = passed.len() as f64;
    let c = passed.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    // every film radius must pass at the centre
    if probe.passes_each(radii, &[c]).iter().any(|p| !p[0]) {
        return None;
    }
    let reach = (b[0] - c.0).abs().max((b[1] - c.0).abs()).hypot((b[2] - c.1).abs().max((b[3] - c.1).abs()));
    let dirs: Vec<(f64, f64)> = (0..DIRECTIONS)
        .map(|k| (std::f64::consts::TAU * k as f64 / DIRECTIONS as f64).sin_cos())
        .map(|(s, co)| (co, s))
        .collect();
    // bisection along every direction for every radius at once: lo passes,
    // hi (the box's far corner) does not
    let mut lo = vec![vec![0.0; DIRECTIONS]; radii.len()];
    let mut hi = vec![vec![reach; DIRECTIONS]; radii.len()];
    let at = |d: &(f64, f64), t: f64| (c.0 + d.0 * t, c.1 + d.1 * t);
    let outer: Vec<(f64, f64)> = dirs.iter().map(|d| at(d, reach)).collect();
    if probe.passes_each(radii, &outer).iter().flatten().any(|p| *p) {
        return None;
    }
    for _ in 0..BISECTIONS {
        for (ri, &r) in radii.iter().enumerate() {
            let mids: Vec<(f64, f64)> =
                dirs.iter().enumerate().map(|(k, d)| at(d, 0.5 * (lo[ri][k] + hi[ri][k]))).collect();
            let pass = &probe.passes_each(&[r], &mids)[0];
            for k in 0..DIRECTIONS {
                let mid = 0.5 * (lo[ri][k] + hi[ri][k]);
                if pass[k] {
                    lo[ri][k] = mid;
                } else {
                    hi[ri][k] = mid;
                }
            }
        }
    }
    // the region's radius per direction: the largest over the bin's film
    // radii, grown for the film radii between them (a quarter of their
    // spread), for the boundary between directions (the neighbours' largest,
    // over the cosine of half the step) and by half a percent
    let half_step = std::f64::consts::PI / DIRECTIONS as f64;
    let radius: Vec<f64> = (0..DIRECTIONS)
        .map(|k| {
            let spread = |k: usize| {
                let v: Vec<f64> = hi.iter().map(|h| h[k]).collect();
                let (mx, mn) = v.iter().fold((0.0f64, f64::INFINITY), |a, x| (a.0.max(*x), a.1.min(*x)));
                mx + 0.25 * (mx - mn)
            };
            let around = [(k + DIRECTIONS - 1) % DIRECTIONS, k, (k + 1) % DIRECTIONS].map(spread);
            around.iter().fold(0.0f64, |a, x| a.max(*x)) * 1.005 / half_step.cos()
        })
        .collect();
    // the passing probes must all lie inside the polygon
    let inside = |p: &(f64, f64)| {
        let (dx, dy) = (p.0 - c.0, p.1 - c.1);
        let t = dy.atan2(dx).rem_euclid(std::f64::consts::TAU) / (2.0 * half_step);
        let k = (t as usize).min(DIRECTIONS - 1);
        let r = radius[k].min(radius[(k + 1) % DIRECTIONS]);
        dx.hypot(dy) <= r * half_step.cos()
    };
    if !passed.iter().all(inside) {
        return None;
    }
    let wedge = (2.0 * half_step).sin() / 2.0;
    let areas: Vec<f64> = (0..DIRECTIONS).map(|k| wedge * radius[k] * radius[(k + 1) % DIRECTIONS]).collect();
    let corners = (0..DIRECTIONS).map(|k| [dirs[k].0 * radius[k], dirs[k].1 * radius[k]]).collect();
    Some(PupilBounds::Star { centre: [c.0, c.1], corners, area: areas.iter().sum(), alias: alias_table(&areas) })
}

/// Walker's alias table (Vose's construction) for choosing index k with
/// probability `w[k] / sum(w)`: entry j keeps j with its probability and
/// otherwise gives its alias.
fn alias_table(w: &[f64]) -> Vec<(f64, u32)> {
    let n = w.len();
    let total: f64 = w.iter().sum();
    let mut p: Vec<f64> = w.iter().map(|x| x * n as f64 / total).collect();
    let mut table = vec![(1.0, 0u32); n];
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&k| p[k] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        table[s] = (p[s], l as u32);
        p[l] -= 1.0 - p[s];
        if p[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    for k in small.into_iter().chain(large) {
        table[k] = (1.0, k as u32);
    }
    table
}

/// The cells of one bin (see the module's description).
fn cells_bin(probe: &Probe, radii: &[f64], rear: f64) -> PupilBounds {
    let Some(b) = passing_box(probe, radii, rear) else { return PupilBounds::Empty };
    let side = (b[1] - b[0]).max(b[3] - b[2]);
    let (x0, y0) = (b[0], b[2]);
    let fine = CELLS * SUB;
    let h = side / fine as f64;
    // corners on the fine grid, (fine + 1)^2 of them; probed: the corners
    // of the coarse cells, then every corner of the edge cells
    let w = fine + 1;
    let mut known = vec![false; w * w];
    let mut pass = vec![false; w * w];
    let run = |idx: &[usize], known: &mut Vec<bool>, pass: &mut Vec<bool>| {
        let todo: Vec<usize> = idx.iter().copied().filter(|&k| !known[k]).collect();
        let targets: Vec<(f64, f64)> =
            todo.iter().map(|&k| (x0 + h * (k % w) as f64, y0 + h * (k / w) as f64)).collect();
        for (&k, p) in todo.iter().zip(probe.passes(radii, &targets)) {
            known[k] = true;
            pass[k] = p;
        }
    };
    let corner = |ci: usize, cj: usize| cj * SUB * w + ci * SUB;
    let coarse: Vec<usize> = (0..=CELLS).flat_map(|j| (0..=CELLS).map(move |i| corner(i, j))).collect();
    run(&coarse, &mut known, &mut pass);
    let cell_corners =
        |ci: usize, cj: usize| [corner(ci, cj), corner(ci + 1, cj), corner(ci, cj + 1), corner(ci + 1, cj + 1)];
    let hit: Vec<bool> =
        (0..CELLS * CELLS).map(|k| cell_corners(k % CELLS, k / CELLS).iter().any(|&c| pass[c])).collect();
    let near_hit = |ci: usize, cj: usize| {
        (cj.saturating_sub(1)..=(cj + 1).min(CELLS - 1))
            .any(|j| (ci.saturating_sub(1)..=(ci + 1).min(CELLS - 1)).any(|i| hit[j * CELLS + i]))
    };
    // whole cells: every corner passes and so do the cells around; edge
    // cells: the rest of those near a passing corner
    let mut whole = vec![false; CELLS * CELLS];
    let mut edge = vec![false; CELLS * CELLS];
    for cj in 0..CELLS {
        for ci in 0..CELLS {
            if !near_hit(ci, cj) {
                continue;
            }
            let all = cell_corners(ci, cj).iter().all(|&c| pass[c]);
            let around = (cj.saturating_sub(1)..=(cj + 1).min(CELLS - 1))
                .all(|j| (ci.saturating_sub(1)..=(ci + 1).min(CELLS - 1)).all(|i| hit[j * CELLS + i]));
            if all && around && ci > 0 && cj > 0 && ci + 1 < CELLS && cj + 1 < CELLS {
                whole[cj * CELLS + ci] = true;
            } else {
                edge[cj * CELLS + ci] = true;
            }
        }
    }
    let mut fine_corners = Vec::new();
    for k in (0..CELLS * CELLS).filter(|&k| edge[k]) {
        let (ci, cj) = (k % CELLS, k / CELLS);
        for j in 0..=SUB {
            for i in 0..=SUB {
                fine_corners.push((cj * SUB + j) * w + ci * SUB + i);
            }
        }
    }
    run(&fine_corners, &mut known, &mut pass);
    // a corner inside a whole cell counts as passing
    let passes = |fx: usize, fy: usize| {
        let k = fy * w + fx;
        pass[k] || {
            let (ci, cj) = ((fx / SUB).min(CELLS - 1), (fy / SUB).min(CELLS - 1));
            whole[cj * CELLS + ci] && !fx.is_multiple_of(SUB) && !fy.is_multiple_of(SUB)
        }
    };
    let big = side / CELLS as f64;
    let (mut whole_cells, mut sub) = (Vec::new(), Vec::new());
    for k in 0..CELLS * CELLS {
        let (ci, cj) = (k % CELLS, k / CELLS);
        if whole[k] {
            whole_cells.push([x0 + big * ci as f64, y0 + big * cj as f64]);
        } else if edge[k] {
            for j in 0..SUB {
                for i in 0..SUB {
                    let (fx, fy) = (ci * SUB + i, cj * SUB + j);
                    // kept when a passing corner lies within one sub-cell
                    let keep = (fy.saturating_sub(1)..=(fy + 2).min(fine))
                        .any(|y| (fx.saturating_sub(1)..=(fx + 2).min(fine)).any(|x| passes(x, y)));
                    if keep {
                        sub.push([x0 + h * fx as f64, y0 + h * fy as f64]);
                    }
                }
            }
        }
    }
    if whole_cells.is_empty() && sub.is_empty() {
        return PupilBounds::Empty;
    }
    PupilBounds::Cells { whole: whole_cells, whole_side: big, sub, sub_side: h }
}

/// The shaped-stop bounds of one bin (see the module's description).
fn stop_bin(probe: &Probe, radii: &[f64], rear: f64, shape: &Aperture, sd: f64) -> PupilBounds {
    let Some(b) = passing_box(probe, radii, rear) else { return PupilBounds::Empty };
    let n = 24;
    let targets: Vec<(f64, f64)> = (0..=n)
        .flat_map(|j| {
            (0..=n)
                .map(move |i| (b[0] + (b[1] - b[0]) * i as f64 / n as f64, b[2] + (b[3] - b[2]) * j as f64 / n as f64))
        })
        .collect();
    let hits = probe.stop_points(radii, &targets);
    // least squares s = A t + c over every passing probe of every radius
    let pairs: Vec<((f64, f64), (f64, f64))> =
        hits.iter().flat_map(|h| targets.iter().zip(h).filter_map(|(t, s)| s.map(|s| (*t, s)))).collect();
    if pairs.len() < 3 {
        return PupilBounds::Empty;
    }
    let Some((a, c)) = fit_affine(&pairs) else { return PupilBounds::Empty };
    let det = a[0] * a[3] - a[1] * a[2];
    if !(det.is_finite() && det.abs() > 0.0) {
        return PupilBounds::Empty;
    }
    let inverse = [a[3] / det, -a[1] / det, -a[2] / det, a[0] / det];
    // the worst miss of the fit over the passing probes, and a probe step
    // of slack for the passing region between probes
    let worst = pairs
        .iter()
        .map(|((tx, ty), (sx, sy))| (a[0] * tx + a[1] * ty + c[0] - sx).hypot(a[2] * tx + a[3] * ty + c[1] - sy))
        .fold(0.0f64, f64::max);
    let step = (b[1] - b[0]).max(b[3] - b[2]) / n as f64 * det.abs().sqrt();
    let margin = 1.5 * worst + 0.05 * step + 1e-6 * sd;
    let scale = 1.0 + margin / (sd * shape.inradius());
    let area = shape.proposal_area() * (scale * sd).powi(2) / det.abs();
    PupilBounds::Stop { inverse, offset: c, scale, area }
}

/// Least-squares affine map s = A t + c from pairs (t, s): A row-major.
fn fit_affine(pairs: &[(Point, Point)]) -> Option<([f64; 4], [f64; 2])> {
    let n = pairs.len() as f64;
    let (mut mt, mut ms) = ((0.0, 0.0), (0.0, 0.0));
    for ((tx, ty), (sx, sy)) in pairs {
        mt = (mt.0 + tx / n, mt.1 + ty / n);
        ms = (ms.0 + sx / n, ms.1 + sy / n);
    }
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let (mut bx, mut by) = ((0.0, 0.0), (0.0, 0.0));
    for ((tx, ty), (sx, sy)) in pairs {
        let (dx, dy) = (tx - mt.0, ty - mt.1);
        let (ex, ey) = (sx - ms.0, sy - ms.1);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
        bx = (bx.0 + dx * ex, bx.1 + dy * ex);
        by = (by.0 + dx * ey, by.1 + dy * ey);
    }
    let m = nalgebra::Matrix2::new(sxx, sxy, sxy, syy);
    let inv = m.try_inverse()?;
    let rx = inv * nalgebra::Vector2::new(bx.0, bx.1);
    let ry = inv * nalgebra::Vector2::new(by.0, by.1);
    let a = [rx[0], rx[1], ry[0], ry[1]];
    let c = [ms.0 - a[0] * mt.0 - a[1] * mt.1, ms.1 - a[2] * mt.0 - a[3] * mt.1];
    a.iter().chain(&c).all(|v| v.is_finite()).then_some((a, c))
}

impl PupilTables {
    /// How many bins use each kind of bounds: (empty, cells, star, stop).
    pub fn kinds(&self) -> [usize; 4] {
        let mut k = [0; 4];
        for b in &self.bins {
            k[match b {
                PupilBounds::Empty => 0,
                PupilBounds::Cells { .. } => 1,
                PupilBounds::Star { .. } => 2,
                PupilBounds::Stop { .. } => 3,
            }] += 1;
        }
        k
    }
}
