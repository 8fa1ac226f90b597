//! Intersection of a ray with a spherical surface, in the surface's local
//! frame (vertex at the origin, axis +z), by the rationalised
//! Spencer & Murty / Welford root (DESIGN.md, Numerics).

use crate::lanes::Real;
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
    let r = if c == 0.0 {
        meet_plane(p.x, p.y, p.z, d.x, d.y, d.z)
    } else {
        let a = approach(c, p.x, p.y, p.z, d.x, d.y, d.z);
        meet_sphere(c, &sphere_root(&a, 1.0 / c, is_curved(c)), p.to_array(), d.to_array())
    };
    r.ok.then(|| Hit { t: r.t, point: DVec3::new(r.x, r.y, r.z) })
}

/// Where rays meet a surface ([`meet_plane`], [`meet_sphere`]), per lane. Where `ok` is false the other
/// fields are meaningless (finite or not) and must be masked by the caller.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneHit<L: Real> {
    /// Distance along the ray from its start to the hit, mm.
    pub t: L,
    pub x: L,
    pub y: L,
    pub z: L,
    /// `|D . N|` at the hit, with `N = (-c x, -c y, 1 - c z)` the unit
    /// normal: the cosine of incidence.
    pub cos_i: L,
    /// The sign bit of `D . N` (`+0` or `-0`).
    pub flip: L,
    /// `G - cos = c t1`, the curvature times the distance from the closest
    /// approach to the hit (0 for a plane): the normal at the hit is
    /// `N0 - (G - cos) D`, with `N0` the normal at the closest approach.
    pub ct1: L,
    /// The closest approach `P0` (the origin for a plane).
    pub p0: [L; 3],
    /// The ray met the surface (on the cap around the vertex, for a
    /// sphere).
    pub ok: L::Mask,
}

/// The plane z = 0, met at `t = -pz / dz` (exactly `z = 0`); a ray parallel
/// to it misses.
#[inline(always)]
pub(crate) fn meet_plane<L: Real>(px: L, py: L, pz: L, dx: L, dy: L, dz: L) -> LaneHit<L> {
    let t = -pz / dz;
    let zero = L::splat(0.0);
    let flip = dz.sign_bit();
    LaneHit {
        t,
        x: t.fma(dx, px),
        y: t.fma(dy, py),
        z: zero,
        cos_i: dz.xor(flip),
        flip,
        ct1: zero,
        p0: [zero; 3],
        ok: t.is_finite(),
    }
}

/// The first half of a sphere's intersection: the ray moved to its closest
/// approach to the vertex, and the quadratic's coefficients there.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Approach<L> {
    /// Distance from the ray's start to the closest approach `P0`, mm.
    pub t0: L,
    /// `F = c |P0|^2 - 2 z0`.
    pub f: L,
    /// `G = Dz - c (P0 . D)`.
    pub g: L,
    /// `G^2 - c F`: negative for a miss.
    pub disc: L,
}

/// Steps 1 to 3 of DESIGN.md's intersection with the sphere of curvature
/// `c` (vertex at the origin).
#[inline(always)]
pub(crate) fn approach<L: Real>(c: L, px: L, py: L, pz: L, dx: L, dy: L, dz: L) -> Approach<L> {
    // 1. closest approach to the vertex
    let t0 = -pz.fma(dz, px.fma(dx, py * dy));
    let x0 = t0.fma(dx, px);
    let y0 = t0.fma(dy, py);
    let z0 = t0.fma(dz, pz);
    // 2. F = c |P0|^2 - 2 z0 (as c (x0^2 + y0^2) + z0 (c z0 - 2), two short
    //    chains) and G = Dz - c (P0 . D)
    let f = c.fma(x0.fma(x0, y0 * y0), z0 * c.fma(z0, L::splat(-2.0)));
    let g = (-c).fma(z0.fma(dz, x0.fma(dx, y0 * dy)), dz);
    // 3. discriminant
    let disc = g.fma(g, -c * f);
    Approach { t0, f, g, disc }
}

/// Step 4 of a sphere's intersection: what is left of the closest approach
/// after the square root and the division, all the rest needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SphereRoot<L: Real> {
    /// Distance from the ray's start to the closest approach, mm.
    pub t0: L,
    /// `sqrt(disc)`: the cosine of incidence `|D . N|` (NaN for a miss).
    pub root: L,
    /// The sign bit of `G`, which `D . N` has.
    pub sign: L,
    /// `G - cos = c t1`.
    pub ct1: L,
    /// Distance from the closest approach to the hit, mm: the rationalised
    /// root `F / (G + s sqrt(disc))`, free of cancellation.
    pub t1: L,
    /// The line meets the sphere: `t1` is finite (a miss, `disc < 0`, has
    /// a NaN root).
    pub met: L::Mask,
}

/// Curvature (1/mm) from which [`sphere_root`] takes the root as
/// `(G - s sqrt(disc)) / c`, a multiplication by the radius, rather than by
/// the rationalised division: |R| <= 10 m, every lens surface but the
/// nearly flat.
///
/// The two are equal in exact arithmetic (`(G + s sqrt(disc)) (G - s
/// sqrt(disc)) = c F`). The rationalised root has no cancellation and is
/// the one for nearly flat surfaces (exactly the plane's root at c = 0).
/// The multiplied one has an absolute error of about `eps |G| |R|` in
/// `t1` (`G - s sqrt(disc)` is `c t1` to within `eps |G|`), below 2.3e-12 mm
/// for |R| <= 1e4 mm, and needs no divider, whose operations are the
/// slowest of a step (docs/numerics.md).
pub(crate) const CURVED: f64 = 1e-4;

/// Whether a sphere of curvature `c` takes the multiplied root ([`CURVED`]).
#[inline]
pub(crate) fn is_curved(c: f64) -> bool {
    c.abs() >= CURVED
}

/// Step 4: the square root and the root from the closest approach `a`;
/// `radius` is `1 / c`, and `curved` whether `|c| >= CURVED` (see there).
///
/// The cosine of incidence comes with the root, as in Welford's skew-ray
/// trace: with `s` the sign of `G`, the quadratic `c t^2 - 2 G t + F = 0`
/// has the root `t1 = F / (G + s sqrt(disc)) = (G - s sqrt(disc)) / c`,
/// and `D . N = G - c t1 = s sqrt(disc)`. Refraction then needs no dot
/// product, and it does not wait for the division.
#[inline(always)]
pub(crate) fn sphere_root<L: Real>(a: &Approach<L>, radius: L, curved: bool) -> SphereRoot<L> {
    let root = a.disc.sqrt();
    let sign = a.g.sign_bit();
    let cos = root.or(sign);
    let ct1 = a.g - cos;
    let t1 = if curved { ct1 * radius } else { a.f / (a.g + cos) };
    SphereRoot { t0: a.t0, root, sign, ct1, t1, met: t1.is_finite() }
}

/// Step 5: the hit of the ray `p + t d` (the one [`approach`] was given),
/// from its root `r`, and the test that it lies on the cap around the
/// vertex. The closest approach is computed again from `r.t0`, with the
/// same operations as in [`approach`] (so the same bits): the batch keeps
/// fewer numbers between its loops.
#[inline(always)]
pub(crate) fn meet_sphere<L: Real>(c: L, r: &SphereRoot<L>, p: [L; 3], d: [L; 3]) -> LaneHit<L> {
    let [x0, y0, z0] = [r.t0.fma(d[0], p[0]), r.t0.fma(d[1], p[1]), r.t0.fma(d[2], p[2])];
    let x = r.t1.fma(d[0], x0);
    let y = r.t1.fma(d[1], y0);
    let z = r.t1.fma(d[2], z0);
    // on the cap around the vertex (1 - c z > 0, the product exact), not
    // the far side
    let ok = r.met & c.fma(z, L::splat(-1.0)).is_neg();
    LaneHit { t: r.t0 + r.t1, x, y, z, cos_i: r.root, flip: r.sign, ct1: r.ct1, p0: [x0, y0, z0], ok }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root as a multiplication by the radius, taken for |R| <= 1e4 mm,
    /// stays within its error bound `eps |G| |R|` (a few ulps of margin) of
    /// the rationalised division, on rays from everywhere at every slope,
    /// near the vertex and at the rim, on both signs of curvature.
    #[test]
    fn multiplied_root_is_within_its_bound_of_the_rationalised_one() {
        let mut worst = 0.0f64;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200_000 {
            let r = (10f64).powf(1.0 + 3.0 * next()) * if next() < 0.5 { -1.0 } else { 1.0 };
            let c = 1.0 / r;
            let h = r.abs() * next();
            let p = [h * (next() - 0.5), h * (next() - 0.5), -100.0 * next()];
            let theta = 1.5 * next();
            let phi = std::f64::consts::TAU * next();
            let d = [theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()];
            let a = approach(c, p[0], p[1], p[2], d[0], d[1], d[2]);
            let mul = sphere_root(&a, 1.0 / c, true);
            let div = sphere_root(&a, 1.0 / c, false);
            if !div.met {
                continue;
            }
            assert!(mul.met);
            let bound = 4.0 * f64::EPSILON * (a.g.abs() * r.abs() + div.t1.abs());
            let err = (mul.t1 - div.t1).abs();
            assert!(err <= bound, "R {r}: {} vs {} (bound {bound})", mul.t1, div.t1);
            worst = worst.max(err / (f64::EPSILON * r.abs()));
        }
        assert!(worst > 0.0);
    }
}
