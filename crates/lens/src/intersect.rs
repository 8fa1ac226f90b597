//! Intersection of a ray with a spherical surface, in the surface's local
//! frame (vertex at the origin, axis +z), by the rationalised
//! Spencer & Murty / Welford root (DESIGN.md, Numerics).

use glam::DVec3;

/// Where a ray meets a sphere: the signed distance along the ray and the hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Signed distance from the ray's origin to the hit, mm (negative when the
    /// surface lies behind the origin: sequential tracing follows the line).
    pub t: f64,
    /// The hit point in the surface's local frame, mm.
    pub point: DVec3,
}

/// Intersects the ray `p + t d` (`d` a unit vector, local frame) with the
/// sphere of curvature `c` (1/mm; 0 = the plane z = 0) whose vertex is at the
/// origin. Returns `None` for a miss: the line does not meet the sphere, meets
/// only its far side (1 - c z <= 0), or runs parallel to a plane.
///
/// ```
/// use glam::DVec3;
/// let hit = lens::intersect::intersect(0.02, DVec3::new(0.0, 5.0, -10.0), DVec3::Z).unwrap();
/// // sag of R = 50 mm at h = 5 mm
/// assert!((hit.point.z - (50.0 - (50.0f64 * 50.0 - 25.0).sqrt())).abs() < 1e-12);
/// ```
pub fn intersect(c: f64, p: DVec3, d: DVec3) -> Option<Hit> {
    let r = intersect_lanes(c, p.x, p.y, p.z, d.x, d.y, d.z);
    r.ok.then(|| Hit { t: r.t, point: DVec3::new(r.x, r.y, r.z) })
}

/// Result of [`intersect_lanes`]: plain numbers so that loops over many rays
/// vectorise. When `ok` is false the other fields are meaningless (but finite
/// or not, they must be masked by the caller).
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneHit {
    pub t: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub ok: bool,
}

/// The intersection on scalars, branch-free, shared by the one-ray and the
/// batch tracers so that both give bit-identical results.
#[inline(always)]
pub(crate) fn intersect_lanes(c: f64, px: f64, py: f64, pz: f64, dx: f64, dy: f64, dz: f64) -> LaneHit {
    // 1. closest approach to the vertex
    let t0 = -pz.mul_add(dz, px.mul_add(dx, py * dy));
    let x0 = t0.mul_add(dx, px);
    let y0 = t0.mul_add(dy, py);
    let z0 = t0.mul_add(dz, pz);
    // 2. F and G
    let f = c.mul_add(z0.mul_add(z0, x0.mul_add(x0, y0 * y0)), -2.0 * z0);
    let g = (-c).mul_add(z0.mul_add(dz, x0.mul_add(dx, y0 * dy)), dz);
    // 3. discriminant
    let disc = g.mul_add(g, -c * f);
    // 4. rationalised root, no cancellation
    let den = g + f64::copysign(disc.max(0.0).sqrt(), g);
    let t1 = f / den;
    let x = t1.mul_add(dx, x0);
    let y = t1.mul_add(dy, y0);
    let z = t1.mul_add(dz, z0);
    // 5. on the cap around the vertex, not the far side
    let ok = disc >= 0.0 && t1.is_finite() && 1.0 - c * z > 0.0;
    LaneHit { t: t0 + t1, x, y, z, ok }
}
