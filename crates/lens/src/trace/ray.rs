//! Rays and the classified outcome of tracing one.

use glam::DVec3;

/// A ray: a point and a unit direction, in mm, in the global frame (z from
/// the first vertex, +z toward the image).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ray {
    /// A point on the ray, mm.
    pub origin: DVec3,
    /// Unit direction.
    pub direction: DVec3,
}

impl Ray {
    /// A ray from `origin` along `direction` (normalised here). Returns `None`
    /// for a zero, non-finite direction or a non-finite origin.
    pub fn new(origin: DVec3, direction: DVec3) -> Option<Self> {
        let d = direction.try_normalize()?;
        origin.is_finite().then_some(Ray { origin, direction: d })
    }

    /// The point at signed distance `t` mm along the ray.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.direction * t
    }
}

/// How a traced ray ended. Surfaces are 0-based indices into
/// `Prescription::surfaces()`; an index equal to the number of surfaces means
/// the film plane. Every variant carries the ray where it stopped (global
/// frame) and the optical path length (mm, sum of index x signed distance)
/// from the starting point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// Passed every surface. Object to image: the ray on the film, with its
    /// image-space direction. Film to object: the ray at the first surface,
    /// with its object-space direction.
    Reached {
        /// Where it ended and its direction there.
        ray: Ray,
        /// Optical path length, mm.
        opl: f64,
    },
    /// The ray's line does not meet this surface (or only its far side). The
    /// ray is as it left the previous surface.
    Missed {
        /// 0-based surface index.
        surface: usize,
        /// The ray before the missed surface.
        ray: Ray,
        /// Optical path length, mm.
        opl: f64,
    },
    /// The ray hit this surface outside its clear aperture (or the stop's).
    /// The ray is at the hit, with its incident direction.
    Blocked {
        /// 0-based surface index.
        surface: usize,
        /// The hit point and incident direction.
        ray: Ray,
        /// Optical path length, mm.
        opl: f64,
    },
    /// Total internal reflection at this surface; the ray is at the hit, with
    /// its incident direction.
    TotalInternalReflection {
        /// 0-based surface index.
        surface: usize,
        /// The hit point and incident direction.
        ray: Ray,
        /// Optical path length, mm.
        opl: f64,
    },
    /// Newton's iteration for the intersection with this aspheric surface
    /// did not converge within its bound
    /// ([`crate::trace::asphere::MAX_NEWTON_STEPS`] steps to
    /// [`crate::trace::asphere::NEWTON_TOLERANCE_MM`]). The ray is as it left
    /// the previous surface, as for [`Outcome::Missed`].
    NotConverged {
        /// 0-based surface index.
        surface: usize,
        /// The ray before the surface.
        ray: Ray,
        /// Optical path length, mm.
        opl: f64,
    },
}

impl Default for Outcome {
    /// A placeholder to fill output slices before a batch trace overwrites it.
    fn default() -> Self {
        Outcome::Missed { surface: 0, ray: Ray::default(), opl: 0.0 }
    }
}

impl Outcome {
    /// The ray where it stopped.
    pub fn ray(&self) -> Ray {
        match *self {
            Outcome::Reached { ray, .. }
            | Outcome::Missed { ray, .. }
            | Outcome::Blocked { ray, .. }
            | Outcome::TotalInternalReflection { ray, .. }
            | Outcome::NotConverged { ray, .. } => ray,
        }
    }

    /// The ray if it passed every surface.
    pub fn reached(&self) -> Option<Ray> {
        match *self {
            Outcome::Reached { ray, .. } => Some(ray),
            _ => None,
        }
    }

    /// Optical path length from the start, mm.
    pub fn opl(&self) -> f64 {
        match *self {
            Outcome::Reached { opl, .. }
            | Outcome::Missed { opl, .. }
            | Outcome::Blocked { opl, .. }
            | Outcome::TotalInternalReflection { opl, .. }
            | Outcome::NotConverged { opl, .. } => opl,
        }
    }
}
