//! The stop sized for an f-number (paraxial f-number, object at infinity),
//! and the fastest f-number the other clear apertures let through (real
//! rays).

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
    pub semi_diameter: f64,
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
        semi_diameter: p.surfaces()[surface].semi_diameter.unwrap_or(f64::INFINITY),
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
