//! Vector form of Snell's law (DESIGN.md, Numerics).

use glam::DVec3;

/// Refracts the unit direction `d` at a surface with unit normal `n` (either
/// orientation), from index `n1` into index `n2`. Returns `None` on total
/// internal reflection.
///
/// With the normal oriented so that `cos_i = d.n >= 0` and `mu = n1/n2`:
/// `k = 1 - mu^2 (1 - cos_i^2)`, and `d' = mu d + (sqrt(k) - mu cos_i) n`.
///
/// ```
/// use glam::DVec3;
/// let d = DVec3::new(0.5f64.sin(), 0.0, 0.5f64.cos());
/// let out = lens::refract::refract(d, DVec3::Z, 1.0, 1.5).unwrap();
/// assert!((out.x * 1.5 - d.x).abs() < 1e-15); // n sin(theta) conserved
/// ```
pub fn refract(d: DVec3, n: DVec3, n1: f64, n2: f64) -> Option<DVec3> {
    let r = refract_lanes(d.x, d.y, d.z, n.x, n.y, n.z, n1 / n2);
    r.ok.then(|| DVec3::new(r.x, r.y, r.z))
}

/// Result of [`refract_lanes`]; when `ok` is false (total internal
/// reflection) the direction is meaningless.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneDir {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub ok: bool,
}

/// Refraction on scalars, branch-free, shared by the one-ray and the batch
/// tracers. `mu = n1 / n2`.
#[inline(always)]
pub(crate) fn refract_lanes(dx: f64, dy: f64, dz: f64, nx: f64, ny: f64, nz: f64, mu: f64) -> LaneDir {
    let cos_raw = dz.mul_add(nz, dx.mul_add(nx, dy * ny));
    // orient the normal along the ray
    let sign = if cos_raw < 0.0 { -1.0 } else { 1.0 };
    let cos_i = cos_raw * sign;
    let k = (-mu * mu).mul_add((-cos_i).mul_add(cos_i, 1.0), 1.0);
    let g = (-mu).mul_add(cos_i, k.max(0.0).sqrt()) * sign;
    LaneDir { x: mu.mul_add(dx, g * nx), y: mu.mul_add(dy, g * ny), z: mu.mul_add(dz, g * nz), ok: k >= 0.0 }
}
