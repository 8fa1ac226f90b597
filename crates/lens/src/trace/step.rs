//! One surface step, written once: the ray moved into the surface's frame,
//! intersected (plane, or sphere by the rationalised Spencer & Murty /
//! Welford root), clipped by the clear aperture, refracted by the vector
//! form of Snell's law, and the verdict (passed, missed, blocked, totally
//! reflected). docs/architecture.md gives the method and its error bounds.
//!
//! Everything is generic over the lane type (`Real`): `f64` for the
//! one-ray path, four rays in an AVX2 register for the batch. Both paths
//! call these functions, so they agree bit for bit.
//!
//! This file is longer than most (about 670 lines) on purpose: the whole
//! step - intersection, refraction, verdicts, and the step's numbers for a
//! ray of its own wavelength - reads top to bottom in one place, the order a
//! ray meets them.

use super::asphere::{asphere_step, rings_of, AsphereLanes};
use super::zones::Zones;
use crate::model::surface::Asphere;
use crate::model::Surface;
use crate::simd::lanes::{Mask, Real};
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
/// let hit = lens::trace::intersect(0.02, DVec3::new(0.0, 5.0, -10.0), DVec3::Z).unwrap();
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

/// Steps 1 to 3 of the sphere intersection (docs/architecture.md) with
/// the sphere of curvature `c` (vertex at the origin).
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
pub(crate) const MULTIPLIED_ROOT_FROM: f64 = 1e-4;

/// Whether a sphere of curvature `c` takes the multiplied root ([`MULTIPLIED_ROOT_FROM`]).
#[inline]
pub(crate) fn is_curved(c: f64) -> bool {
    c.abs() >= MULTIPLIED_ROOT_FROM
}

/// Step 4: the square root and the root from the closest approach `a`;
/// `radius` is `1 / c`, and `curved` whether `|c| >= MULTIPLIED_ROOT_FROM` (see there).
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
/// let out = lens::trace::refract(d, DVec3::Z, 1.0, 1.5).unwrap();
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
/// ([`Real`]), behind the one-ray [`refract`] (the tracers refract at the
/// hit from the closest approach's normal instead, see `refract_at`):
/// `d' = mu d + (sqrt(k) - mu cos_i) N`, with `mu = n1 / n2`, `cos = D . N`
/// of either sign (the normal is turned along the ray by flipping signs with
/// its sign bit) and `root_k` the square root of [`snell_k`] (of its positive
/// part). Meaningless where `k < 0`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn refract_lanes<L: Real>(dx: L, dy: L, dz: L, nx: L, ny: L, nz: L, mu: L, cos: L, root_k: L) -> [L; 3] {
    refract_scaled([dx, dy, dz], [nx, ny, nz], mu, cos, root_k, L::splat(1.0))
}

/// [`refract_lanes`] at the normal `scale N` (`N` not unit: `cos` and
/// `root_k` are for `scale N`), the scale applied once to the normal's
/// multiplier rather than to its three parts.
#[inline(always)]
pub(crate) fn refract_scaled<L: Real>(d: [L; 3], n: [L; 3], mu: L, cos: L, root_k: L, scale: L) -> [L; 3] {
    let flip = cos.sign_bit();
    let cos_i = cos.xor(flip);
    let g = (-mu).fma(cos_i, root_k).xor(flip) * scale;
    [mu.fma(d[0], g * n[0]), mu.fma(d[1], g * n[1]), mu.fma(d[2], g * n[2])]
}

/// One surface as a tracing step, in the order of travel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Step {
    /// Curvature, 1/mm.
    pub c: f64,
    /// Squared clear radius, mm^2 (infinity: no clipping).
    pub sd2: f64,
    /// Index ratio n_before / n_after.
    pub mu: f64,
    /// Index of the medium the ray crosses to reach this surface.
    pub n_before: f64,
    /// Index of the medium after the surface.
    pub n_after: f64,
    /// The tracer's glass (an index into its list) before the surface,
    /// [`NO_GLASS`] for a constant index: a batch of mixed wavelengths
    /// takes each ray's own index of it.
    pub glass_before: u32,
    /// The glass after the surface, as `glass_before`.
    pub glass_after: u32,
    /// Subtracted from the ray's z to go from the previous frame to this one.
    pub shift: f64,
    /// Global z of this step's vertex, mm.
    pub vertex_z: f64,
    /// 0-based surface index (number of surfaces = the film).
    pub surface: usize,
    /// Whether the indices differ (otherwise the direction is kept exactly).
    /// A [`Self::reflect`] step refracts too (with `mu` 1).
    pub refract: bool,
    /// Whether the ray is reflected here rather than refracted (a ghost
    /// path's two reflections): the same kernel with `mu = 1` and the root
    /// of Snell's `k` negated, `d' = d - 2 (D . N) N`, the medium kept.
    pub reflect: bool,
    /// How the surface is met: [`PLANE`], [`FLAT`], [`CURVED`] or
    /// [`ASPHERE`].
    pub shape: u8,
    /// The conic and terms of an [`ASPHERE`] step.
    pub asphere: Option<Asphere>,
    /// Its rings (`zones.rs`), made with the step, so that both paths
    /// start from the same ones (kept when a tracer widens `sd2` later:
    /// the start only decides how many steps a ray takes).
    pub zones: Option<Zones>,
    /// The focal length of a [`PARAXIAL`] step, mm (0 for any other).
    pub focal: f64,
    /// The frame change of a decentred or tilted surface (`None` on the
    /// axis): the step then runs in the surface's own frame, with `shift`
    /// 0 (the frame change holds it), and its rays leave in the co-axial
    /// frame at `vertex_z`.
    pub frame: Option<super::frame::Frame>,
}

/// How much (relative) a clear aperture's squared radius is widened for
/// the test: a ray aimed exactly at a rim (the pupil's edge on a stop that
/// is the entrance pupil, as fans and spots aim) lands there to within a
/// few ulps, and would otherwise pass or be blocked by rounding. A part in
/// 1e12 of the radius squared is 5e-13 of it: nanometres of nothing.
pub(crate) const RIM_TOLERANCE: f64 = 1e-12;

/// [`Step::glass_before`] of a medium of constant index.
pub(crate) const NO_GLASS: u32 = u32::MAX;

/// A plane (`c == 0`): met by [`meet_plane`], no square root.
pub(crate) const PLANE: u8 = 0;
/// A sphere with `|c| <` [`MULTIPLIED_ROOT_FROM`]: the rationalised root,
/// a division.
pub(crate) const FLAT: u8 = 1;
/// A sphere with `|c| >=` [`MULTIPLIED_ROOT_FROM`]: the root as
/// `(G - s sqrt(disc)) / c`, a multiplication.
pub(crate) const CURVED: u8 = 2;

/// An asphere (a conic, polynomial terms): Newton's iteration
/// (`asphere.rs`).
pub(crate) const ASPHERE: u8 = 3;

/// An ideal thin lens in the vertex plane ([`paraxial_step`]), traced ray
/// by ray on both paths.
pub(crate) const PARAXIAL: u8 = 4;

/// The [`Step::shape`] of a surface of curvature `c` (an asphere when
/// `aspheric`).
pub(crate) fn shape_of(c: f64, aspheric: bool) -> u8 {
    if aspheric {
        ASPHERE
    } else if c == 0.0 {
        PLANE
    } else if is_curved(c) {
        CURVED
    } else {
        FLAT
    }
}

/// Whether this CPU runs the AVX2 + FMA kernels (detected once, cached by
/// the standard library).
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn simd_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

/// Outcome kinds of one step, as small integers so the batch loop can mask.
pub(crate) const PASSED: u64 = 0;
pub(crate) const MISSED: u64 = 1;
pub(crate) const BLOCKED: u64 = 2;
pub(crate) const TIR: u64 = 3;
/// Newton's iteration on an asphere did not converge.
pub(crate) const NOT_CONVERGED: u64 = 4;
/// Bits of a batch status that hold the kind; the step above them.
pub(crate) const KIND_BITS: u32 = 3;
/// The kind's bits of a status.
pub(crate) const KIND_MASK: u64 = (1 << KIND_BITS) - 1;

/// The state of rays in a step's local frame: one ray (`f64`) or one per
/// lane of a vector ([`Real`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lane<L> {
    pub px: L,
    pub py: L,
    pub pz: L,
    pub dx: L,
    pub dy: L,
    pub dz: L,
    pub opl: L,
}

impl Lane<f64> {
    /// A ray as a lane, path length 0.
    #[inline(always)]
    pub(crate) fn of_ray(r: &super::ray::Ray) -> Self {
        let (o, d) = (r.origin, r.direction);
        Lane { px: o.x, py: o.y, pz: o.z, dx: d.x, dy: d.y, dz: d.z, opl: 0.0 }
    }
}

/// How a step went, per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Verdict<M> {
    /// The ray met the surface.
    pub ok: M,
    /// ... where an asphere's iteration converged (always for a sphere).
    pub converged: M,
    /// ... inside its clear aperture.
    pub inside: M,
    /// ... and was refracted (no total internal reflection).
    pub through: M,
    /// All three, for a ray that was travelling: it goes on.
    pub passed: M,
}

impl<M: Mask> Verdict<M> {
    /// The verdict from the three tests.
    #[inline(always)]
    pub(crate) fn of(ok: M, inside: M, through: M) -> Self {
        Verdict { ok, converged: M::all_true(), inside, through, passed: ok & inside & through }
    }

    /// The verdict of a step that may not converge (an asphere).
    #[inline(always)]
    pub(crate) fn with_convergence(ok: M, converged: M, inside: M, through: M) -> Self {
        Verdict { ok, converged, inside, through, passed: ok & converged & inside & through }
    }
}

impl Verdict<bool> {
    /// The outcome kind of one ray's step.
    pub(crate) fn kind(self) -> u64 {
        kind_of(self.ok, self.converged, self.inside, self.through)
    }
}

/// The outcome kind from the three tests, in the order they apply.
#[inline(always)]
pub(crate) fn kind_of(ok: bool, converged: bool, inside: bool, through: bool) -> u64 {
    if !ok {
        MISSED
    } else if !converged {
        NOT_CONVERGED
    } else if !inside {
        BLOCKED
    } else if !through {
        TIR
    } else {
        PASSED
    }
}

/// A step's numbers in the kernel's number type.
#[derive(Clone, Copy)]
pub(crate) struct StepLanes<L> {
    pub c: L,
    sd2: L,
    pub mu: L,
    mu2: L,
    one_minus_mu2: L,
    pub n_before: L,
    pub shift: L,
    /// `1 / c` for a [`CURVED`] sphere (0 otherwise).
    pub radius: L,
    /// `-0` for a reflecting step, `+0` otherwise: xored into the root of
    /// Snell's `k` (exact: `+0` leaves it alone to the bit).
    root_sign: L,
}

impl<L: Real> StepLanes<L> {
    #[inline(always)]
    pub(crate) fn of(s: &Step) -> Self {
        StepLanes {
            c: L::splat(s.c),
            sd2: L::splat(s.sd2),
            mu: L::splat(s.mu),
            mu2: L::splat(s.mu * s.mu),
            one_minus_mu2: L::splat(one_minus_square(s.mu)),
            n_before: L::splat(s.n_before),
            shift: L::splat(s.shift),
            radius: L::splat(if s.shape == CURVED { 1.0 / s.c } else { 0.0 }),
            root_sign: L::splat(if s.reflect { -0.0 } else { 0.0 }),
        }
    }

    /// The step's numbers with the indices `n_before` and `n_after` of
    /// each lane and their ratio `mu` (`n_before / n_after`, as the caller
    /// has it): what a ray of its own wavelength meets. With the indices
    /// of one wavelength this is [`Self::of`] of that wavelength's step, to
    /// the bit.
    #[inline(always)]
    pub(crate) fn with_indices(self, n_before: L, mu: L) -> Self {
        StepLanes { mu, mu2: mu * mu, one_minus_mu2: (-mu).fma(mu, L::splat(1.0)), n_before, ..self }
    }

    /// Whether a hit at `(x, y)` (the step's frame) lies inside the clear
    /// aperture.
    #[inline(always)]
    pub(crate) fn inside(&self, x: L, y: L) -> L::Mask {
        self.inside_r2(x.fma(x, y * y))
    }

    /// [`Self::inside`] for a hit at `r2 = x^2 + y^2` (mm^2, as
    /// `x.fma(x, y * y)`).
    #[inline(always)]
    pub(crate) fn inside_r2(&self, r2: L) -> L::Mask {
        !(self.sd2 - r2).is_neg()
    }

    /// Snell's `k` at this step for the squared cosine of incidence `cos2`.
    #[inline(always)]
    fn k(&self, cos2: L) -> L {
        snell_k(self.mu2, self.one_minus_mu2, cos2)
    }

    /// Snell's `k` times `q` for a normal `N` that is not unit: `g2 = (D .
    /// N)^2`, `q = N . N` (the squared cosine is `g2 / q`), so that a
    /// surface whose normal comes unnormalised refracts without its square
    /// root (see [`snell_root_unnormalised`]).
    #[inline(always)]
    fn k_times(&self, g2: L, q: L) -> L {
        self.mu2.fma(g2, self.one_minus_mu2 * q)
    }
}

/// Each ray's index of each glass: what [`lanes_at`] reads.
pub(crate) trait Indices<L> {
    /// The index of glass `g`.
    fn n(&self, g: usize) -> L;
    /// `1 / n(g)`, as computed once for the rays.
    fn inv(&self, g: usize) -> L;
}

/// The numbers of step `s` for rays each at its own wavelength: `sl` (the
/// step's own numbers) with the indices of the step's glasses taken per
/// lane from `ix`. The ratio `mu` is formed as the one-wavelength step
/// forms `n1 / n2`, so the bits agree: `n1 / 1 = n1` for a glass into air,
/// the inverse for air into a glass.
#[inline(always)]
pub(crate) fn lanes_at<L: Real>(sl: StepLanes<L>, s: &Step, ix: &impl Indices<L>) -> StepLanes<L> {
    let (gb, ga) = (s.glass_before, s.glass_after);
    if gb == NO_GLASS && ga == NO_GLASS {
        return sl;
    }
    let nb = if gb == NO_GLASS { L::splat(s.n_before) } else { ix.n(gb as usize) };
    let mu = if ga == NO_GLASS {
        if s.n_after == 1.0 {
            nb
        } else {
            nb / L::splat(s.n_after)
        }
    } else if gb == NO_GLASS && s.n_before == 1.0 {
        ix.inv(ga as usize)
    } else {
        nb / ix.n(ga as usize)
    };
    sl.with_indices(nb, mu)
}

/// What one step does to rays, per lane.
#[derive(Clone, Copy)]
pub(crate) struct StepOut<L: Real> {
    /// The ray as it goes on when it passed: on the surface, refracted, its
    /// path length grown by the index times the distance travelled.
    pub next: Lane<L>,
    /// How the step went.
    pub verdict: Verdict<L::Mask>,
}

/// Snell's `k` at step `s` for the squared cosine of incidence `cos2`, as
/// the refraction needs it: its square root (of its positive part) and
/// whether the ray goes through (`k >= 0`, no total internal reflection).
/// `REFRACT` must be `s.refract` (otherwise `(0, true)`).
#[inline(always)]
pub(crate) fn snell_root<L: Real, const REFRACT: bool>(s: &StepLanes<L>, cos2: L) -> (L, L::Mask) {
    if REFRACT {
        let k = s.k(cos2);
        // a NaN root where k < 0: the ray stops there, its direction unused;
        // a reflecting step (mu = 1, k = cos^2) takes -cos
        (k.sqrt().xor(s.root_sign), !k.is_neg())
    } else {
        (L::splat(0.0), L::Mask::all_true())
    }
}

/// [`snell_root`] for a normal `N` that is not unit (`g = D . N`, `q = N .
/// N`): `sqrt(k q)`, with which `refract_lanes(D, N / q, mu, g, sqrt(k q))`
/// is the refraction at the unit normal `N / sqrt(q)` (the added term
/// `(sqrt(k) - mu cos) n` equals `(sqrt(k q) - mu g) N / q`): one square
/// root and one division where normalising first takes two and one.
#[inline(always)]
pub(crate) fn snell_root_unnormalised<L: Real, const REFRACT: bool>(s: &StepLanes<L>, g: L, q: L) -> (L, L::Mask) {
    if REFRACT {
        let kq = s.k_times(g * g, q);
        (kq.sqrt().xor(s.root_sign), !kq.is_neg())
    } else {
        (L::splat(0.0), L::Mask::all_true())
    }
}

/// Carries rays across one step: shift into the step's frame, intersect,
/// clip by the clear aperture, refract. `REFRACT` must be `s.refract` and
/// `SHAPE` `s.shape`. The result holds the ray as it goes on; a ray that
/// stopped here is given by [`stopped`].
///
/// The batch runs a sphere step in two loops over its rays: [`approach`],
/// then [`sphere_from_approach`].
#[inline(always)]
pub(crate) fn step_lanes<L: Real, const REFRACT: bool, const SHAPE: u8>(s: &StepLanes<L>, l: Lane<L>) -> StepOut<L> {
    let (p, d) = ([l.px, l.py, l.pz - s.shift], [l.dx, l.dy, l.dz]);
    if SHAPE == PLANE {
        let h = meet_plane(p[0], p[1], p[2], d[0], d[1], d[2]);
        let (root_k, through) = snell_root::<L, REFRACT>(s, h.cos_i * h.cos_i);
        let (next, inside) = carry::<L, REFRACT>(s, &h, d, l.opl, root_k);
        StepOut { next, verdict: Verdict::of(h.ok, inside, through) }
    } else {
        let a = approach(s.c, p[0], p[1], p[2], d[0], d[1], d[2]);
        sphere_from_approach::<L, REFRACT, SHAPE>(s, &a, p, d, l.opl)
    }
}

/// The rest of a sphere step from the closest approach `a` of the ray with
/// point `p` (in the step's frame), direction `d` and path length `opl`.
#[inline(always)]
pub(crate) fn sphere_from_approach<L: Real, const REFRACT: bool, const SHAPE: u8>(
    s: &StepLanes<L>,
    a: &Approach<L>,
    p: [L; 3],
    d: [L; 3],
    opl: L,
) -> StepOut<L> {
    // the squared cosine of incidence is the discriminant
    let (root_k, through) = snell_root::<L, REFRACT>(s, a.disc);
    let h = meet_sphere(s.c, &sphere_root(a, s.radius, SHAPE == CURVED), p, d);
    let (next, inside) = carry::<L, REFRACT>(s, &h, d, opl, root_k);
    StepOut { next, verdict: Verdict::of(h.ok, inside, through) }
}

/// The part of a step after the intersection `h`: clip, refract, add the
/// path. `d` and `opl` are the ray's direction and path length before the
/// step, `root_k` from [`snell_root`]. Returns the ray as it goes on and
/// whether the hit lies inside the clear aperture.
#[inline(always)]
pub(crate) fn carry<L: Real, const REFRACT: bool>(
    s: &StepLanes<L>,
    h: &LaneHit<L>,
    d: [L; 3],
    opl: L,
    root_k: L,
) -> (Lane<L>, L::Mask) {
    let inside = s.inside(h.x, h.y);
    let [dx, dy, dz] = if REFRACT { refract_at(s, h, d, root_k) } else { d };
    (Lane { px: h.x, py: h.y, pz: h.z, dx, dy, dz, opl: s.n_before.fma(h.t, opl) }, inside)
}

/// The refracted direction at the hit `h`: Snell's law in vector form,
/// `d' = mu d + g N`, with `g = sqrt(k) - mu cos_i` (signs as the normal
/// faces) and the normal at the hit written `N = N0 - c t1 D` from the normal
/// `N0 = (-c x0, -c y0, 1 - c z0)` at the closest approach and `c t1 = G -
/// cos` (Welford): `d' = (mu - g c t1) d + g N0`. The direction so needs no
/// division, and waits only for the two square roots.
#[inline(always)]
fn refract_at<L: Real>(s: &StepLanes<L>, h: &LaneHit<L>, d: [L; 3], root_k: L) -> [L; 3] {
    let g = (-s.mu).fma(h.cos_i, root_k).xor(h.flip);
    let a = (-g).fma(h.ct1, s.mu);
    let gc = g * -s.c;
    let [x0, y0, z0] = h.p0;
    [a.fma(d[0], gc * x0), a.fma(d[1], gc * y0), a.fma(d[2], gc.fma(z0, g))]
}

/// The state of one ray that stopped at step `s` with kind `kind` (not
/// [`PASSED`]), from its state `before` the step and the step's result
/// `next`: a missed ray keeps its direction and stays where it was (moved
/// into the step's frame), as does one whose asphere iteration did not
/// converge; one blocked or totally reflected moves to the hit and keeps its
/// direction.
#[inline(always)]
pub(crate) fn stopped(s: &Step, before: Lane<f64>, next: Lane<f64>, kind: u64) -> Lane<f64> {
    if kind == MISSED || kind == NOT_CONVERGED {
        Lane { pz: before.pz - s.shift, ..before }
    } else {
        Lane { dx: before.dx, dy: before.dy, dz: before.dz, ..next }
    }
}

/// [`step_lanes`] with the step's `refract` flag and shape turned into the
/// kernel's constants; `asphere` is the step's asphere in the kernel's
/// numbers (made once per tracer, [`super::tracer::Tracer`]), `None` for a
/// step of another shape.
#[inline(always)]
pub(crate) fn step_dispatch(
    s: &Step,
    asphere: Option<&AsphereLanes<f64>>,
    k: &StepLanes<f64>,
    l: Lane<f64>,
) -> StepOut<f64> {
    if s.shape == PARAXIAL {
        return paraxial_step(k, s.focal, l);
    }
    if let (ASPHERE, Some(a)) = (s.shape, asphere) {
        return if s.refract { asphere_step::<true>(k, a, l) } else { asphere_step::<false>(k, a, l) };
    }
    match (s.refract, s.shape) {
        (true, PLANE) => step_lanes::<f64, true, PLANE>(k, l),
        (true, FLAT) => step_lanes::<f64, true, FLAT>(k, l),
        (true, _) => step_lanes::<f64, true, CURVED>(k, l),
        (false, PLANE) => step_lanes::<f64, false, PLANE>(k, l),
        (false, FLAT) => step_lanes::<f64, false, FLAT>(k, l),
        (false, _) => step_lanes::<f64, false, CURVED>(k, l),
    }
}

/// The step for surface `surf` (0-based index `i`) crossed from index `n1`
/// (glass `g1`, if any) into `n2` (glass `g2`), `shift` mm from the previous
/// frame, its vertex at global `vertex_z`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn surface_step(
    surf: &Surface,
    i: usize,
    (n1, g1): (f64, Option<usize>),
    (n2, g2): (f64, Option<usize>),
    shift: f64,
    vertex_z: f64,
) -> Step {
    let id = |g: Option<usize>| g.map_or(NO_GLASS, |g| g as u32);
    let sd2 = surf.semi_diameter.map_or(f64::INFINITY, |r| r * r * (1.0 + RIM_TOLERANCE));
    Step {
        c: surf.curvature,
        sd2,
        mu: n1 / n2,
        n_before: n1,
        n_after: n2,
        glass_before: id(g1),
        glass_after: id(g2),
        shift,
        vertex_z,
        surface: i,
        refract: n1 != n2,
        reflect: false,
        shape: if surf.paraxial.is_some() { PARAXIAL } else { shape_of(surf.curvature, surf.asphere.is_some()) },
        asphere: surf.asphere,
        zones: surf.asphere.and_then(|a| rings_of(surf.curvature, &a, sd2)),
        focal: surf.paraxial.unwrap_or(0.0),
        frame: None,
    }
}

/// [`surface_step`] at a surface's placement: a decentred or tilted
/// surface's step takes its frame change, which holds the shift.
pub(crate) fn placed(mut step: Step, placement: Option<crate::model::Placement>) -> Step {
    if let Some(p) = placement {
        step.frame = Some(super::frame::Frame::of(p, step.shift));
        step.shift = 0.0;
    }
    step
}

/// An ideal thin lens of focal length `focal` (mm) in the step's vertex
/// plane, the same medium on both sides: the ray meets the plane at H, is
/// clipped by the clear aperture, and leaves with slopes t - sign(dz) h /
/// f (t = (dx/dz, dy/dz)), toward the point Q = z_Q t, z_Q = sign(dz) f,
/// where every ray of its slope meets (the focal plane); its path grows by
/// n (sign(f) (|Q| - |Q - H|) - d . H), which makes every ray of a plane
/// wave arrive at Q with the same optical path (the vertex's ray gains
/// nothing), so the wavefront of an object at infinity is exact.
pub(crate) fn paraxial_step(s: &StepLanes<f64>, focal: f64, l: Lane<f64>) -> StepOut<f64> {
    let (p, d) = ([l.px, l.py, l.pz - s.shift], [l.dx, l.dy, l.dz]);
    let h = meet_plane(p[0], p[1], p[2], d[0], d[1], d[2]);
    let inside = s.inside(h.x, h.y);
    let sign = if d[2] < 0.0 { -1.0 } else { 1.0 };
    let (tx, ty) = (d[0] / d[2], d[1] / d[2]);
    let (ux, uy) = (tx - sign * h.x / focal, ty - sign * h.y / focal);
    let dz = sign / (1.0 + ux * ux + uy * uy).sqrt();
    let zq = sign * focal;
    let q = DVec3::new(zq * tx, zq * ty, zq);
    let hit = DVec3::new(h.x, h.y, 0.0);
    let gained = s.n_before * (focal.signum() * (q.length() - (q - hit).length()) - DVec3::from(d).dot(hit));
    let opl = s.n_before.fma(h.t, l.opl) + gained;
    let next = Lane { px: h.x, py: h.y, pz: h.z, dx: ux * dz, dy: uy * dz, dz, opl };
    let ok = h.ok && next.dx.is_finite() && next.dy.is_finite() && opl.is_finite();
    StepOut { next, verdict: Verdict::of(ok, inside, true) }
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
        let mut next = crate::trace::uniform(0x2545_f491_4f6c_dd1d);
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
