//! Shaped-stop bounds: the stop's shape mapped back to the rear plane through
//! an affine fit of the target-to-stop map, clipped by the round stop's
//! bounds per slice of the film point's azimuth (see the module above).

use super::fan::{clip, Fan};
use super::star::star_fan;
use super::{passing_box, FilmPoint, Point, Probe, PupilBounds};
use crate::camera::aperture::Aperture;

/// The shaped-stop bounds of one bin (see the module's description).
pub(super) fn stop_bin(probe: &Probe, radii: &[FilmPoint], rear: f64, shape: &Aperture, sd: f64) -> PupilBounds {
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
    match round_stop_fan(probe, radii, rear) {
        Some(round) => buckets(&round, shape, sd, margin, inverse, c),
        None => {
            let area = shape.proposal_area() * (scale * sd).powi(2) / det.abs();
            PupilBounds::Stop { inverse, offset: c, scale, area }
        }
    }
}

/// Slices of the film point's azimuth per period of the shape's symmetry.
const BUCKETS: usize = 64;

/// The round stop's star-shaped bounds with 64 corners, grown so that they
/// contain the 256-corner polygon: each corner at the largest radius of
/// the eight directions around it, over the cosine of half the angle
/// between corners.
fn round_stop_fan(probe: &Probe, radii: &[FilmPoint], rear: f64) -> Option<Fan> {
    let fine = star_fan(probe, radii, rear)?;
    let centre = fine.centre();
    let r: Vec<f64> = fine.corners().map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1])).collect();
    let (n, m) = (r.len(), r.len() / 4);
    let grow = 1.0 / (std::f64::consts::PI / m as f64).cos();
    let corners: Vec<[f64; 2]> = (0..m)
        .map(|j| {
            let rho = (0..=8).map(|i| r[(4 * j + n - 4 + i) % n]).fold(0.0f64, f64::max) * grow;
            let (sn, cs) = (std::f64::consts::TAU * j as f64 / m as f64).sin_cos();
            [centre[0] + rho * cs, centre[1] + rho * sn]
        })
        .collect();
    Fan::new(centre, &corners)
}

/// For each slice of azimuth, the round-stop polygon clipped by the stop's
/// shape mapped back to the rear plane (bin frame). The shape turns by
/// minus the film point's azimuth; over a slice it is grown so that it
/// contains every turn of the slice (a corner at half the slice's angle
/// from the middle stays inside the shape grown by cos(pi/N - delta) /
/// cos(pi/N)), then by the fit's margin.
fn buckets(round: &Fan, shape: &Aperture, sd: f64, margin: f64, inverse: [f64; 4], offset: [f64; 2]) -> PupilBounds {
    let outline = shape.outline();
    let period = shape.period();
    let corners = outline.len() as f64;
    let delta = period / (2.0 * BUCKETS as f64);
    let half = std::f64::consts::PI / corners;
    let turn = (half - delta).cos() / half.cos();
    let scale = (turn + margin / (sd * shape.inradius())) * sd;
    let subject: Vec<[f64; 2]> = round.corners().collect();
    let m = inverse;
    let fans = (0..BUCKETS)
        .map(|k| {
            let phi = (k as f64 + 0.5) * period / BUCKETS as f64;
            let (sn, cs) = phi.sin_cos();
            let mut mapped: Vec<[f64; 2]> = outline
                .iter()
                .map(|&(x, y)| {
                    // the stop point in the bin frame: turned by -phi
                    let (sx, sy) = (scale * (cs * x + sn * y) - offset[0], scale * (-sn * x + cs * y) - offset[1]);
                    [m[0] * sx + m[1] * sy, m[2] * sx + m[3] * sy]
                })
                .collect();
            let signed: f64 = (0..mapped.len())
                .map(|i| {
                    let (p, q) = (mapped[i], mapped[(i + 1) % mapped.len()]);
                    p[0] * q[1] - p[1] * q[0]
                })
                .sum();
            if signed < 0.0 {
                mapped.reverse();
            }
            let own = || {
                let n = mapped.len() as f64;
                let c = mapped.iter().fold([0.0, 0.0], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n]);
                Fan::new(c, &mapped)
            };
            Fan::new(round.centre(), &clip(&subject, &mapped)).or_else(own)
        })
        .collect::<Option<Vec<Fan>>>();
    match fans {
        Some(buckets) => PupilBounds::Shaped { period, buckets },
        None => PupilBounds::Empty,
    }
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
