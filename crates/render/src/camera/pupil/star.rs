//! Star-shaped bounds: the passing region's edge along 256 directions from
//! its centroid, for the round stop (see the module above).

use super::fan::Fan;
use super::{passing_probes, FilmPoint, Probe, PupilBounds};

/// Directions of a star-shaped region's boundary.
const DIRECTIONS: usize = 256;
/// Bisection steps along each direction (to 1/4096 of the box).
const BISECTIONS: usize = 12;

/// The star-shaped bounds of one bin (see the module's description), or
/// `None` where the region is not star-shaped about the passing probes'
/// centroid for every film radius of the bin (the cells take over).
pub(super) fn star_bin(probe: &Probe, radii: &[FilmPoint], rear: f64) -> Option<PupilBounds> {
    star_fan(probe, radii, rear).map(PupilBounds::Star)
}

/// The star-shaped polygon of [`star_bin`].
pub(super) fn star_fan(probe: &Probe, radii: &[FilmPoint], rear: f64) -> Option<Fan> {
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
    let corners: Vec<[f64; 2]> =
        (0..DIRECTIONS).map(|k| [c.0 + dirs[k].0 * radius[k], c.1 + dirs[k].1 * radius[k]]).collect();
    Fan::new([c.0, c.1], &corners)
}
