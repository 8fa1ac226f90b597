//! Spot diagrams: where a pupil pattern of rays lands on an image plane, its
//! RMS and geometric radii, and the focus shift of least RMS spot.

use super::fan::ImagePlane;
use super::launch::{Aim, Field, Launcher};
use super::pattern::{points, Pattern};
use super::WAVELENGTH_MM;
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::imaging;
use crate::trace::ray::Outcome;
use crate::trace::Tracer;
use serde::Serialize;

/// Most rays a spot diagram traces (a bound on memory, not on accuracy).
pub const MAX_RAYS: usize = 50_000_000;

/// A spot diagram at one field. Lengths in mm, on the image plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpotDiagram {
    /// Field angle, degrees, or `None` for a finite object.
    pub field_deg: Option<f64>,
    /// z of the image plane, mm from the first vertex.
    pub image_z: f64,
    /// Rays that reached the image plane.
    pub rays: usize,
    /// Rays blocked by a clear aperture (left out of the statistics),
    /// including those of `aim_failures`.
    pub vignetted: usize,
    /// Rays real aiming could not place on the stop (no real ray reaches that
    /// stop point); left out like vignetted rays.
    pub aim_failures: usize,
    /// Mean position of the rays.
    pub centroid: [f64; 2],
    /// RMS distance from the centroid.
    pub rms_radius: f64,
    /// RMS distance from the chief ray.
    pub rms_radius_chief: f64,
    /// Largest distance from the centroid.
    pub geo_radius: f64,
    /// Largest distance from the chief ray.
    pub geo_radius_chief: f64,
    /// Chief ray position.
    pub chief: [f64; 2],
    /// Airy disk radius 1.22 lambda N_w (lambda = 587.56 nm, paraxial
    /// working f-number), for scale.
    pub airy_radius: f64,
    /// Axial shift of the plane (mm, + toward the image) that minimises the
    /// RMS radius about the centroid, and that radius.
    pub best_focus_shift: f64,
    /// RMS radius about the centroid at the best focus shift.
    pub rms_radius_best_focus: f64,
    /// Every ray that reached the plane: x, y, dx/dz, dy/dz.
    #[serde(skip)]
    pub hits: Vec<[f64; 4]>,
}

impl SpotDiagram {
    /// RMS radius about the centroid on a plane shifted by `dz` mm (+ toward
    /// the image): exact, since every ray is a straight line there.
    pub fn rms_at_shift(&self, dz: f64) -> f64 {
        let (pp, ps, ss) = self.moments();
        (pp + 2.0 * dz * ps + dz * dz * ss).max(0.0).sqrt()
    }

    /// Through-focus RMS radius at each shift.
    pub fn through_focus(&self, shifts: &[f64]) -> Vec<(f64, f64)> {
        shifts.iter().map(|&s| (s, self.rms_at_shift(s))).collect()
    }

    /// Mean of |p'|^2, p'.s' and |s'|^2 with p', s' the positions and slopes
    /// about their means.
    fn moments(&self) -> (f64, f64, f64) {
        let n = self.hits.len().max(1) as f64;
        let mean = |k: usize| self.hits.iter().map(|h| h[k]).sum::<f64>() / n;
        let (mx, my, msx, msy) = (mean(0), mean(1), mean(2), mean(3));
        let (mut pp, mut ps, mut ss) = (0.0, 0.0, 0.0);
        for h in &self.hits {
            let (px, py, sx, sy) = (h[0] - mx, h[1] - my, h[2] - msx, h[3] - msy);
            pp += px * px + py * py;
            ps += px * sx + py * sy;
            ss += sx * sx + sy * sy;
        }
        (pp / n, ps / n, ss / n)
    }
}

/// Traces `pattern` (size `n`) at `field` to `plane` and measures the spot.
/// Errors when the chief ray is lost or every ray is vignetted.
pub fn spot_diagram(
    p: &Prescription,
    field: Field,
    pattern: Pattern,
    n: usize,
    aim: Aim,
    plane: ImagePlane,
) -> Result<SpotDiagram, OpticsError> {
    let count = match pattern {
        Pattern::Square => (n as f64) * (n as f64),
        Pattern::Hexapolar => 1.0 + 3.0 * (n as f64) * (n as f64 + 1.0),
        Pattern::Random => n as f64,
    };
    if count > MAX_RAYS as f64 {
        return Err(OpticsError::BadInput {
            name: "pattern size n",
            value: n as f64,
            expected: "a pattern of at most 50 million rays (square n <= 7071, hexapolar n <= 4081)",
        });
    }
    let launcher = Launcher::new(p, field, aim)?;
    let image_z = plane.z(p, &launcher)?;
    let tracer = Tracer::forward_to_film(p, image_z - p.last_vertex_z());
    let chief = match tracer.trace(launcher.ray(0.0, 0.0)?) {
        Outcome::Reached { ray, .. } => [ray.origin.x, ray.origin.y],
        o => return Err(OpticsError::ChiefRayLost { field: field.describe(), why: format!("{o:?}") }),
    };
    let mut hits = Vec::new();
    let mut vignetted = 0;
    let mut aim_failures = 0;
    for (px, py) in points(pattern, n) {
        let ray = match launcher.ray(px, py) {
            Ok(r) => r,
            Err(OpticsError::AimingFailed { .. }) => {
                aim_failures += 1;
                vignetted += 1;
                continue;
            }
            Err(e) => return Err(e),
        };
        match tracer.trace(ray) {
            Outcome::Reached { ray, .. } if ray.direction.z != 0.0 => {
                let d = ray.direction;
                hits.push([ray.origin.x, ray.origin.y, d.x / d.z, d.y / d.z]);
            }
            _ => vignetted += 1,
        }
    }
    if hits.is_empty() {
        return Err(OpticsError::NoRealRays {
            why: format!("all {vignetted} rays are vignetted at {}", field.describe()),
        });
    }
    let m = hits.len() as f64;
    let centroid = [hits.iter().map(|h| h[0]).sum::<f64>() / m, hits.iter().map(|h| h[1]).sum::<f64>() / m];
    let dist = |h: &[f64; 4], c: [f64; 2]| ((h[0] - c[0]).powi(2) + (h[1] - c[1]).powi(2)).sqrt();
    let rms = |c: [f64; 2]| (hits.iter().map(|h| dist(h, c).powi(2)).sum::<f64>() / m).sqrt();
    let geo = |c: [f64; 2]| hits.iter().map(|h| dist(h, c)).fold(0.0, f64::max);
    let first = launcher.first_order();
    let wfn = imaging(p, first, field.object())?.working_f_number;
    let mut spot = SpotDiagram {
        field_deg: match field {
            Field::Angle(d) => Some(d),
            Field::Height { .. } => None,
        },
        image_z,
        rays: hits.len(),
        vignetted,
        aim_failures,
        centroid,
        rms_radius: rms(centroid),
        rms_radius_chief: rms(chief),
        geo_radius: geo(centroid),
        geo_radius_chief: geo(chief),
        chief,
        airy_radius: 1.22 * WAVELENGTH_MM * wfn,
        best_focus_shift: 0.0,
        rms_radius_best_focus: 0.0,
        hits,
    };
    let (_, ps, ss) = spot.moments();
    spot.best_focus_shift = if ss > 0.0 { -ps / ss } else { 0.0 };
    spot.rms_radius_best_focus = spot.rms_at_shift(spot.best_focus_shift);
    Ok(spot)
}
