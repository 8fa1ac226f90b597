//! Shaped-stop bounds: the stop's shape mapped back to the rear plane through
//! an affine fit of the target-to-stop map (see the module above).

use super::{passing_box, Point, Probe, PupilBounds};
use crate::camera::aperture::Aperture;

/// The shaped-stop bounds of one bin (see the module's description).
pub(super) fn stop_bin(probe: &Probe, radii: &[f64], rear: f64, shape: &Aperture, sd: f64) -> PupilBounds {
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
