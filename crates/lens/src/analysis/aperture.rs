//! The stop sized for an f-number (paraxial f-number, object at infinity),
//! the fastest f-number the other clear apertures let through (real rays),
//! and clear apertures made to pass given fields (Zemax's automatic
//! semi-diameters).

use super::launch::{Aim, Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::FirstOrder;
use crate::trace::{Outcome, Ray, Tracer};
use glam::DVec3;

/// The fastest f-number the clear apertures other than the stop allow for
/// an object at infinity, and the surface that sets it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ApertureLimit {
    /// |EFL| / the largest entrance-pupil diameter whose marginal ray clears
    /// every surface.
    pub f_number: f64,
    /// 0-based index of the limiting surface.
    pub surface: usize,
    /// Its semi-diameter, mm.
    pub semi_diameter: Option<f64>,
}

/// The fastest f-number the clear apertures other than the stop allow for
/// an object at infinity, by real rays: the largest height at which a ray
/// parallel to the axis passes every surface with the stop left open
/// (bisection to 1e-12 of the height), and the surface that blocks the ray
/// just above it. Real rays, not paraxial ones: a lens's spherical
/// aberration moves the marginal ray's heights (the double Gauss passes
/// f/2 by real rays where the paraxial marginal ray would stop at f/2.07).
/// `None` when no surface but the stop limits the bundle.
pub fn clear_aperture_limit(p: &Prescription, first: &FirstOrder) -> Option<ApertureLimit> {
    let tracer = Tracer::forward_without_stop(p);
    let z0 = first.entrance_pupil.z.min(0.0) - 1.0;
    let blocked_at = |h: f64| -> Option<usize> {
        let ray = Ray { origin: DVec3::new(0.0, h, z0), direction: DVec3::Z };
        match tracer.trace(ray) {
            Outcome::Reached { .. } => None,
            Outcome::Missed { surface, .. }
            | Outcome::Blocked { surface, .. }
            | Outcome::TotalInternalReflection { surface, .. }
            | Outcome::NotConverged { surface, .. } => Some(surface),
        }
    };
    // an upper bound: no ray passes far above the largest clear aperture
    let largest = p.surfaces().iter().filter_map(|s| s.semi_diameter).fold(0.0, f64::max);
    let mut hi = 4.0 * largest.max(first.entrance_pupil.diameter) + 1.0;
    blocked_at(hi)?;
    let mut lo = 0.0;
    if blocked_at(lo).is_some() {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if blocked_at(mid).is_some() {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    let surface = blocked_at(hi)?;
    if lo <= 0.0 || surface >= p.surfaces().len() {
        return None;
    }
    Some(ApertureLimit {
        f_number: first.efl.abs() / (2.0 * lo),
        surface,
        semi_diameter: p.surfaces()[surface].semi_diameter,
    })
}

/// How much faster than the clear apertures allow an f-number may be asked
/// for (relative): nominal f-numbers are rounded.
pub const F_NUMBER_TOLERANCE: f64 = 0.05;

/// A copy of `p` whose stop is resized so that the paraxial f-number
/// (|EFL| / entrance-pupil diameter, object at infinity) is `f_number`.
///
/// Errors when the f-number is not positive and finite, when it is faster
/// than the other clear apertures allow by more than
/// [`F_NUMBER_TOLERANCE`] (naming the f-number they give and
/// the surface that limits), when the stop no longer fits on a curved stop
/// surface, and when the resized prescription fails validation (surfaces
/// that then cross inside the larger aperture).
pub fn with_f_number(p: &Prescription, f_number: f64) -> Result<Prescription, OpticsError> {
    if !(f_number.is_finite() && f_number > 0.0) {
        return Err(OpticsError::BadInput {
            name: "f_number",
            value: f_number,
            expected: "a positive, finite f-number",
        });
    }
    let first = FirstOrder::of(p)?;
    if let Some(limit) = clear_aperture_limit(p, &first) {
        // lens data state nominal f-numbers (the double Gauss's f/2 passes
        // f/2.018 by real rays): within the tolerance the rim of the bundle
        // is vignetted a little, beyond it the request is refused
        if f_number < limit.f_number * (1.0 - F_NUMBER_TOLERANCE) {
            return Err(OpticsError::FNumberTooFast {
                asked: f_number,
                fastest: limit.f_number,
                surface: limit.surface + 1,
                semi_diameter: limit.semi_diameter,
            });
        }
    }
    let scale = (first.efl.abs() / f_number) / first.entrance_pupil.diameter;
    let resized = p.with_stop_semi_diameter(p.stop_semi_diameter() * scale)?;
    Ok(resized)
}

/// Rays around the rim of the pupil, per field, that
/// [`automatic_semi_diameters`] traces.
pub const RIM_RAYS: usize = 72;

/// A copy of `p` whose clear apertures (all but the stop's) are just large
/// enough to pass the full stop at the axis and at each of `fields_deg`
/// (degrees, object at infinity): each surface's semi-diameter is the
/// largest height at which a real ray of those bundles meets it (the
/// chief ray and [`RIM_RAYS`] rays around the rim of the stop, aimed at the
/// stop by Newton's iteration), plus one part in a million so that the rim
/// rays are not lost to rounding. What Zemax's automatic semi-diameters
/// are; for designs whose source gives no clear apertures (patents).
///
/// Errors when a ray of those bundles does not reach the film with the
/// other apertures open (it misses a surface, or is totally reflected),
/// naming the field, and when the apertures make neighbouring surfaces cross.
pub fn automatic_semi_diameters(p: &Prescription, fields_deg: &[f64]) -> Result<Prescription, OpticsError> {
    let n = p.surfaces().len();
    let open = p.with_clear_apertures(&vec![None; n])?;
    let first = FirstOrder::of(&open)?;
    // the rim rays meet the stop at its rim: it must not clip them either
    let tracer = Tracer::forward_without_stop(&open);
    let mut largest = vec![0.0f64; n];
    let mut rim: Vec<(f64, f64)> = (0..RIM_RAYS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / RIM_RAYS as f64;
            (a.cos(), a.sin())
        })
        .collect();
    rim.push((0.0, 0.0));
    for &field in std::iter::once(&0.0).chain(fields_deg) {
        let launcher = Launcher::with_first(&open, &first, Field::Angle(field), Aim::Real)?;
        for &(px, py) in &rim {
            let ray = launcher.ray(px, py)?;
            let (path, outcome) = tracer.trace_path(ray);
            if outcome.reached().is_none() {
                return Err(OpticsError::AimingFailed {
                    px,
                    py,
                    field: Field::Angle(field).describe(),
                    why: format!("with the clear apertures open the ray {}", super::bundle::describe_outcome(&outcome)),
                });
            }
            // path: the start, then the hit on each surface, then the film
            for (i, hit) in path.iter().skip(1).take(n).enumerate() {
                largest[i] = largest[i].max(hit.x.hypot(hit.y));
            }
        }
    }
    let sd: Vec<Option<f64>> = largest.iter().map(|h| Some(h * (1.0 + 1e-6))).collect();
    p.with_clear_apertures(&sd)
}
