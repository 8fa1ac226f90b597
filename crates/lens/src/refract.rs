//! Vector form of Snell's law (DESIGN.md, Numerics).

use crate::lanes::Real;
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
    let mu = n1 / n2;
    let cos = d.dot(n);
    let r = refract_lanes::<f64>(d.x, d.y, d.z, n.x, n.y, n.z, mu, one_minus_square(mu), cos, cos * cos);
    r.ok.then(|| DVec3::new(r.x, r.y, r.z))
}

/// Result of [`refract_lanes`], per lane; where `ok` is false (total
/// internal reflection) the direction is meaningless.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneDir<L: Real> {
    pub x: L,
    pub y: L,
    pub z: L,
    pub ok: L::Mask,
}

/// `1 - mu^2`, rounded once: the constant part of Snell's `k`.
#[inline(always)]
pub(crate) fn one_minus_square(mu: f64) -> f64 {
    (-mu).mul_add(mu, 1.0)
}

/// Refraction, branch-free, generic over one ray or several ([`Real`]),
/// shared by the one-ray and the batch tracers. `mu = n1 / n2`,
/// `one_minus_mu2` is [`one_minus_square`]`(mu)`, `cos = D . N` (either
/// sign: the normal is turned along the ray by flipping signs with its sign
/// bit) and `cos2` its square. `k = 1 - mu^2 (1 - cos^2)` is computed as
/// `mu^2 cos^2 + (1 - mu^2)`, from the square the intersection already has.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn refract_lanes<L: Real>(
    dx: L,
    dy: L,
    dz: L,
    nx: L,
    ny: L,
    nz: L,
    mu: L,
    one_minus_mu2: L,
    cos: L,
    cos2: L,
) -> LaneDir<L> {
    let flip = cos.sign_bit();
    let cos_i = cos.xor(flip);
    let k = (mu * mu).fma(cos2, one_minus_mu2);
    let g = (-mu).fma(cos_i, k.pos_or_zero().sqrt()).xor(flip);
    LaneDir { x: mu.fma(dx, g * nx), y: mu.fma(dy, g * ny), z: mu.fma(dz, g * nz), ok: k.ge(L::splat(0.0)) }
}
