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
    let k = snell_k(mu * mu, one_minus_square(mu), cos * cos);
    let r = refract_lanes::<f64>(d.x, d.y, d.z, n.x, n.y, n.z, mu, cos, pos_or_zero(k).sqrt());
    (k >= 0.0).then(|| DVec3::new(r[0], r[1], r[2]))
}

/// `k` where it is greater than zero, `+0` otherwise (NaN too).
fn pos_or_zero(k: f64) -> f64 {
    if k > 0.0 {
        k
    } else {
        0.0
    }
}

/// `1 - mu^2`, rounded once: the constant part of Snell's `k`.
#[inline(always)]
pub(crate) fn one_minus_square(mu: f64) -> f64 {
    (-mu).mul_add(mu, 1.0)
}

/// Snell's `k = 1 - mu^2 (1 - cos^2) = (n' cos I' / n)^2 mu^2`, computed as
/// `mu^2 cos^2 + (1 - mu^2)` from the square of the cosine of incidence
/// (which the intersection already has). `k < 0` is total internal
/// reflection.
#[inline(always)]
pub(crate) fn snell_k<L: Real>(mu2: L, one_minus_mu2: L, cos2: L) -> L {
    mu2.fma(cos2, one_minus_mu2)
}

/// The refracted direction, branch-free, generic over one ray or several
/// ([`Real`]), shared by the one-ray and the batch tracers:
/// `d' = mu d + (sqrt(k) - mu cos_i) N`, with `mu = n1 / n2`, `cos = D . N`
/// of either sign (the normal is turned along the ray by flipping signs with
/// its sign bit) and `root_k` the square root of [`snell_k`] (of its positive
/// part). Meaningless where `k < 0`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn refract_lanes<L: Real>(dx: L, dy: L, dz: L, nx: L, ny: L, nz: L, mu: L, cos: L, root_k: L) -> [L; 3] {
    let flip = cos.sign_bit();
    let cos_i = cos.xor(flip);
    let g = (-mu).fma(cos_i, root_k).xor(flip);
    [mu.fma(dx, g * nx), mu.fma(dy, g * ny), mu.fma(dz, g * nz)]
}
