//! Direct light sampling: points on emissive shapes and point lights.

use crate::geometry::Shape;
use crate::rng::Sampler;
use glam::DVec3;

/// A point sampled on a shape's surface, uniform by area: the point, its
/// outward unit normal, and the density 1 / area.
pub fn sample_shape(s: &Shape, sampler: &mut Sampler) -> Option<(DVec3, DVec3, f64)> {
    sample_shape_at(s, sampler.next2())
}

/// [`sample_shape`] from the two uniforms `(u, v)`.
pub fn sample_shape_at(s: &Shape, (u, v): (f64, f64)) -> Option<(DVec3, DVec3, f64)> {
    match *s {
        Shape::Sphere { center, radius } => {
            let z = 1.0 - 2.0 * u;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f64::consts::TAU * v;
            let n = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            Some((center + n * radius, n, 1.0 / s.area()))
        }
        Shape::Quad { corner, u: eu, v: ev } => {
            Some((corner + eu * u + ev * v, eu.cross(ev).normalize(), 1.0 / s.area()))
        }
        Shape::Triangle { v: t } => {
            let su = u.sqrt();
            let (b0, b1) = (1.0 - su, v * su);
            let p = t[0] * b0 + t[1] * b1 + t[2] * (1.0 - b0 - b1);
            Some((p, (t[1] - t[0]).cross(t[2] - t[0]).normalize(), 1.0 / s.area()))
        }
        Shape::Plane { .. } => None,
    }
}
