//! The aspheric surface step: the ray's intersection with a conic plus
//! polynomial terms by Newton's method, started from a conic's root near
//! the surface (made in f32: `StartLanes`), and refraction at the exact
//! normal there. Written once over the lane type, as the sphere step
//! (`step.rs`), so the one-ray and the batch paths agree bit for bit;
//! docs/architecture.md gives the method.
//!
//! The sag is z(r) = c r^2 / (1 + sqrt(1 - (1 + k) c^2 r^2)) + sum_j a_j r^j
//! ([`crate::model::surface::Asphere`]). With the ray at `q + u d` (`q` where
//! it crosses the vertex plane), Newton's iteration on `F(u) = z(u) -
//! sag(r(u))` is `u <- u - F / F'`, `F' = d . N` with the surface normal
//! `N = (-g x, -g y, 1)`, `g = (dz/dr) / r`.

use super::step::{refract_scaled, snell_root_unnormalised, Lane, StepLanes, StepOut, Verdict};
use super::zones::Zones;
use crate::model::surface::{Asphere, MAX_ASPHERE_POWER};
use crate::simd::lanes::{Mask, Real, RingRows};

/// Newton steps at most before a ray is reported as not converged. From
/// the conic's root a smooth asphere converges quadratically in 2 to 5.
pub const MAX_NEWTON_STEPS: usize = 32;

/// Newton's iteration stops when its step is at most this, mm (or, for an
/// asphere without an r^1 term, when its error estimate after the step is:
/// the third-order step of docs/architecture.md).
pub const NEWTON_TOLERANCE_MM: f64 = 1e-12;

/// The longest step (mm) after which the error estimate may end the
/// iteration.
pub const ESTIMATE_FROM_MM: f64 = 1e-3;

/// A polynomial in `s` = r^2 by Horner's rule: its coefficients from
/// `s^0`, and how many.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Chain<L> {
    c: [L; MAX_ASPHERE_POWER / 2],
    n: usize,
}

impl<L: Real> Chain<L> {
    /// The chain of `coefs` (from `s^0`; zeros at the end dropped).
    fn of(coefs: &[f64]) -> Self {
        let n = coefs.iter().rposition(|a| *a != 0.0).map_or(0, |i| i + 1);
        let mut c = [L::splat(0.0); MAX_ASPHERE_POWER / 2];
        for (ci, a) in c.iter_mut().zip(coefs) {
            *ci = L::splat(*a);
        }
        Chain { c, n }
    }

    /// The chain at `s` with `N` terms (its own count, a compile-time
    /// constant: no branch on it), those past its own being zeros; `N` = 0
    /// is [`Self::at`]. Bit for bit [`Self::at`] at a finite `s`: a zero
    /// term times `s` adds an exact zero.
    #[inline(always)]
    fn at_len<const N: usize>(&self, s: L) -> L {
        if N == 0 {
            return self.at(s);
        }
        debug_assert!(self.n <= N);
        self.first(N, s)
    }

    /// [`Self::at_len`] with `N - less` terms (the chains a term or two
    /// shorter than `B` and `D`: `V` and `E` one, `vo` two); `N` = 0 is
    /// [`Self::at`].
    #[inline(always)]
    fn at_len_less<const N: usize>(&self, less: usize, s: L) -> L {
        if N == 0 {
            return self.at(s);
        }
        debug_assert!(N > less && self.n <= N - less);
        self.first(N - less, s)
    }

    /// The first `len` (>= 1) terms at `s` by Horner's rule; `len` a
    /// constant where it is called, the loop unrolls.
    #[inline(always)]
    fn first(&self, len: usize, s: L) -> L {
        let mut p = self.c[len - 1];
        for i in (0..len - 1).rev() {
            p = p.fma(s, self.c[i]);
        }
        p
    }

    #[inline(always)]
    fn at(&self, s: L) -> L {
        // short chains (most aspheres) unrolled: no loop, no branch per
        // term (one per chain, the same for every ray of the surface)
        match self.n {
            0 => L::splat(0.0),
            1 => self.c[0],
            2 => self.c[1].fma(s, self.c[0]),
            3 => self.c[2].fma(s, self.c[1]).fma(s, self.c[0]),
            4 => self.c[3].fma(s, self.c[2]).fma(s, self.c[1]).fma(s, self.c[0]),
            n => self.first(n, s),
        }
    }
}

/// An asphere's numbers in the kernel's number type.
///
/// The polynomial part P(r) = sum a_j r^j and `Q = P'(r) / r` (the normal
/// and the derivative along the ray need it) are evaluated as polynomials in
/// `s` = r^2, each split into its even and odd powers of r:
/// `P = s B(s) + r C(s)` and `Q = D(s) + r E(s) + a_1 / r`. The four chains
/// are independent of each other and of the square root that gives r, so
/// their latencies overlap (a single Horner chain in r over ten terms was
/// the step's longest wait); an even asphere has only B and D and no square
/// root. Only an r^1 term needs a division by r.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AsphereLanes<L: Real> {
    /// Base curvature, 1/mm.
    c: L,
    /// `(1 + k) c^2`.
    k1c2: L,
    /// `(1 + k) c`, and it and `c` halved (the iteration's `G / 2`).
    k1c: L,
    half_k1c: L,
    half_c: L,
    /// `k c` and `(1 + k) c` of the conic whose root starts the iteration:
    /// the surface's own, or with the r^4 term folded in (`+ 8 a_4 / c^3`,
    /// the conic's own r^4 coefficient being `(1 + k) c^3 / 8`) where that
    /// conic spans the clear aperture, so that the start is nearer the
    /// surface.
    start_kc: L,
    start_k1c: L,
    /// What the iteration starts from, in f32 ([`StartLanes`]): all but a
    /// pure conic's rays start there (a pure conic's root is its
    /// intersection, made in f64 from the fields above).
    start: StartLanes<L::F32>,
    /// `B(s) = sum_m a_2m s^(m-1)`, `C(s) = sum_m a_(2m+1) s^m`.
    b: Chain<L>,
    cc: Chain<L>,
    /// `D(s) = sum_m 2m a_2m s^(m-1)`, `E(s) = sum_m (2m+1) a_(2m+1)
    /// s^(m-1)` (m >= 1).
    d: Chain<L>,
    e: Chain<L>,
    /// `V = (dQ/dr) / r = sum_(j >= 3) j (j - 2) a_j r^(j - 4)`, with which
    /// the second derivative along a ray is `d2P/du2 = Q rho^2 + V (r .
    /// D)^2` (`rho^2 = Dx^2 + Dy^2`), split as `P` and `Q` are: `V = v(s) +
    /// r vo(s) + 3 a_3 / r`, `v(s) = sum_(j even >= 4) j (j - 2) a_j
    /// s^((j - 4) / 2)` and `vo(s) = sum_(j odd >= 5) j (j - 2) a_j s^((j -
    /// 5) / 2)`: an even asphere needs no division for it, an odd one with
    /// an r^3 term one.
    v: Chain<L>,
    vo: Chain<L>,
    /// `3 a_3`.
    v3: L,
    /// `a_1`, the r^1 term (0 for an even asphere).
    a1: L,
    /// `a_1` is not 0.
    has_a1: bool,
    /// `a_3` is not 0.
    has_a3: bool,
    /// Some term has an odd power: r itself is needed.
    odd: bool,
    /// No polynomial terms: the conic's root is the intersection, and
    /// Newton's iteration has nothing to do.
    conic_only: bool,
    /// An asphere with terms and no r^1 term (whose `V` is singular on the
    /// axis): the iteration takes third-order (Chebyshev) steps and may end
    /// by its error estimate.
    third_order: bool,
    /// The number of terms its chains are evaluated with, a compile-time
    /// constant of the iteration's functions ([`Self::chain_terms`]).
    terms: usize,
}

/// The chain lengths that get their own code ([`AsphereLanes::chain_terms`]):
/// the even aspheres' `a_4 .. a_8` to `a_4 .. a_16` (with or without
/// `a_2`).
pub(crate) const CHAIN_TERMS: [usize; 4] = [4, 5, 6, MAX_ASPHERE_POWER / 2];

/// The chain lengths that get their own code for an asphere with odd
/// powers (and no r^1 term): terms to r^10 (a phone lens's), or to
/// [`MAX_ASPHERE_POWER`].
pub(crate) const ODD_CHAIN_TERMS: [usize; 2] = [5, MAX_ASPHERE_POWER / 2];

/// [`AsphereLanes::chain_terms`] of `asphere`: 0 for a surface with an r^1
/// term (Newton's steps, each chain its own length) or none.
fn chain_terms(asphere: &Asphere) -> usize {
    let degree = asphere.degree();
    if degree == 0 || asphere.coefficients[0] != 0.0 {
        return 0;
    }
    // the longest chains: B and D's (a_2 .. a_degree) for an even asphere,
    // also C's (a_1 .. a_degree) for an odd one
    let (n, buckets) =
        if asphere.is_even() { (degree / 2, &CHAIN_TERMS[..]) } else { (degree.div_ceil(2), &ODD_CHAIN_TERMS[..]) };
    buckets.iter().copied().find(|t| n <= *t).unwrap_or(0)
}

/// `1 + k` of the conic whose root starts an asphere's iteration (no
/// rings): its own, or with the r^4 term folded in where that is a conic's
/// (an even asphere without an r^2 term) and the conic is defined with room
/// over the whole clear aperture.
fn start_k1(c: f64, asphere: &Asphere, sd2: f64) -> f64 {
    let a = |j: usize| asphere.coefficients[j - 1];
    let k1 = 1.0 + asphere.conic;
    let folded = k1 + 8.0 * a(4) / (c * c * c);
    if asphere.degree() > 0
        && asphere.is_even()
        && a(2) == 0.0
        && a(4) != 0.0
        && c != 0.0
        && sd2.is_finite()
        && folded.is_finite()
        && 1.0 - folded * c * c * sd2 >= 0.1
    {
        folded
    } else {
        k1
    }
}

/// The rings that start the iteration of the asphere on a base of
/// curvature `c` with clear radius squared `sd2` (`zones.rs`), `None` where
/// its start conic is near enough.
pub(crate) fn rings_of(c: f64, asphere: &Asphere, sd2: f64) -> Option<Zones> {
    Zones::of(c, asphere, sd2, start_k1(c, asphere, sd2) - 1.0)
}

impl<L: Real> AsphereLanes<L> {
    /// The kernel's numbers for `asphere` on a base of curvature `c`, its
    /// clear radius squared `sd2` (mm^2, infinity for none).
    #[cfg(test)]
    pub(crate) fn of(c: f64, asphere: &Asphere, sd2: f64) -> Self {
        Self::with_zones(c, asphere, sd2, rings_of(c, asphere, sd2))
    }

    /// The kernel's numbers for `asphere` on a base of curvature `c`, its
    /// clear radius squared `sd2` (mm^2, infinity for none), with the rings
    /// `zones` ([`rings_of`]'s, made once per step: both paths must start
    /// from the same rings, and they take a few thousand sag evaluations to
    /// make).
    pub(crate) fn with_zones(c: f64, asphere: &Asphere, sd2: f64, zones: Option<Zones>) -> Self {
        let a = |j: usize| if j <= MAX_ASPHERE_POWER { asphere.coefficients[j - 1] } else { 0.0 };
        const HALF: usize = MAX_ASPHERE_POWER / 2;
        // index m - 1 (b, d) or m (cc, e from m = 1 at index 0): no heap
        let b: [f64; HALF] = std::array::from_fn(|i| a(2 * (i + 1)));
        let cc: [f64; HALF] = std::array::from_fn(|i| a(2 * i + 1));
        let d: [f64; HALF] = std::array::from_fn(|i| (2 * (i + 1)) as f64 * a(2 * (i + 1)));
        let e: [f64; HALF] = std::array::from_fn(|i| (2 * i + 3) as f64 * a(2 * i + 3));
        // term j = 2i + 4 at s^i
        let v: [f64; HALF] = std::array::from_fn(|i| ((2 * i + 4) * (2 * i + 2)) as f64 * a(2 * i + 4));
        // term j = 2i + 5 at s^i
        let vo: [f64; HALF] = std::array::from_fn(|i| ((2 * i + 5) * (2 * i + 3)) as f64 * a(2 * i + 5));
        let k1 = 1.0 + asphere.conic;
        let start_k1 = start_k1(c, asphere, sd2);
        AsphereLanes {
            c: L::splat(c),
            k1c2: L::splat(k1 * c * c),
            k1c: L::splat(k1 * c),
            half_k1c: L::splat(0.5 * k1 * c),
            half_c: L::splat(0.5 * c),
            start_kc: L::splat((start_k1 - 1.0) * c),
            start_k1c: L::splat(start_k1 * c),
            start: StartLanes {
                c: L::F32::splat(c),
                kc: L::F32::splat((start_k1 - 1.0) * c),
                k1c: L::F32::splat(start_k1 * c),
                zones,
            },
            b: Chain::of(&b),
            cc: Chain::of(&cc),
            d: Chain::of(&d),
            e: Chain::of(&e),
            v: Chain::of(&v),
            vo: Chain::of(&vo),
            v3: L::splat(3.0 * a(3)),
            a1: L::splat(a(1)),
            has_a1: a(1) != 0.0,
            has_a3: a(3) != 0.0,
            odd: !asphere.is_even(),
            conic_only: asphere.degree() == 0,
            third_order: asphere.degree() > 0 && a(1) == 0.0,
            terms: chain_terms(asphere),
        }
    }

    /// The `TERMS` the iteration's functions must be called with: the
    /// longest chain's length, rounded up to one of [`CHAIN_TERMS`] for an
    /// even asphere, of [`ODD_CHAIN_TERMS`] for one with odd powers (the
    /// extra terms zeros), so that each length gets its own code, without a
    /// branch or a loop per chain and ray; 0 (each chain its own length,
    /// chosen per evaluation) for a surface with an r^1 term.
    #[inline(always)]
    pub(crate) fn chain_terms(&self) -> usize {
        self.terms
    }

    /// Whether some term has an odd power of r: the `ODD` the iteration's
    /// functions must be called with where [`Self::chain_terms`] is not 0.
    #[inline(always)]
    pub(crate) fn odd(&self) -> bool {
        self.odd
    }

    /// What the iteration starts from, in f32 lanes ([`StartLanes`]).
    #[inline(always)]
    pub(crate) fn start(&self) -> &StartLanes<L::F32> {
        &self.start
    }

    /// Whether Newton's iteration has anything to do: not for a pure conic,
    /// whose root is the intersection.
    #[inline(always)]
    pub(crate) fn iterates(&self) -> bool {
        !self.conic_only
    }

    /// Whether the iteration takes third-order steps (an asphere with terms
    /// and no r^1 term): the `THIRD` the iteration's functions must be
    /// called with.
    #[inline(always)]
    pub(crate) fn third_order(&self) -> bool {
        self.third_order
    }

    /// The polynomial part at `s` = r^2: its sag `P` and `Q = (dP/dr) /
    /// r`. On the axis (r = 0, where x = y = 0 and Q's value does not
    /// matter) an r^1 term's `a_1 / r` is kept finite. `TERMS` and `ODD`
    /// are [`Self::chain_terms`] and [`Self::odd`] (`TERMS` = 0: each chain
    /// its own length, and whether a term has an odd power read from the
    /// surface).
    #[inline(always)]
    fn poly<const ODD: bool, const TERMS: usize>(&self, s: L) -> (L, L) {
        let (p, q, _) = self.poly_r::<ODD, TERMS>(s);
        (p, q)
    }

    /// Whether the chains with odd powers of r are evaluated: `ODD`, or
    /// where the chains' lengths are not constants (`TERMS` = 0), the
    /// surface's own flag.
    #[inline(always)]
    fn odd_at<const ODD: bool, const TERMS: usize>(&self) -> bool {
        ODD || (TERMS == 0 && self.odd)
    }

    /// [`Self::poly`] with `r` where a term has an odd power (0 where none
    /// has: it is not needed).
    #[inline(always)]
    fn poly_r<const ODD: bool, const TERMS: usize>(&self, s: L) -> (L, L, L) {
        let mut p = self.b.at_len::<TERMS>(s) * s;
        let mut q = self.d.at_len::<TERMS>(s);
        if self.odd_at::<ODD, TERMS>() {
            let r = s.sqrt();
            p = r.fma(self.cc.at_len::<TERMS>(s), p);
            q = r.fma(self.e.at_len_less::<TERMS>(1, s), q);
            if self.has_a1 {
                q = q + self.a1 / r_or_one(r);
            }
            return (p, q, r);
        }
        (p, q, L::splat(0.0))
    }

    /// `V` at `s` ([`Self::v`]), `r` its square root where a term has an odd
    /// power ([`Self::poly_r`]'s). On the axis `3 a_3 / r` is kept finite
    /// (it multiplies `(r . D)^2`, 0 there).
    #[inline(always)]
    fn v_at<const ODD: bool, const TERMS: usize>(&self, s: L, r: L) -> L {
        let v = self.v.at_len_less::<TERMS>(1, s);
        if self.odd_at::<ODD, TERMS>() {
            let v = r.fma(self.vo.at_len_less::<TERMS>(2, s), v);
            if self.has_a3 {
                return v + self.v3 / r_or_one(r);
            }
            return v;
        }
        v
    }
}

/// `r`, but 1 where it is 0 (a division by it stays finite on the axis,
/// where what it divides does not matter).
#[inline(always)]
fn r_or_one<L: Real>(r: L) -> L {
    L::select(r.le(L::splat(0.0)), L::splat(1.0), r)
}

/// Where rays meet an asphere, per lane.
#[derive(Clone, Copy)]
pub(crate) struct AsphereHit<L: Real> {
    /// Distance along the ray from its start, mm.
    pub t: L,
    pub x: L,
    pub y: L,
    pub z: L,
    /// `x^2 + y^2` at the hit, mm^2 (as `x.fma(x, y * y)`).
    pub r2: L,
    /// The normal at the hit, not unit: `(-x (c + m Q), -y (c + m Q), m)`
    /// with `m = 1 - (1 + k) c w` > 0 (the conic's square root at the hit)
    /// and `Q` as [`AsphereLanes::poly`] gives it; `(0, 0, 1)` at the vertex.
    pub n: [L; 3],
    /// The ray met the surface where it is defined.
    pub ok: L::Mask,
    /// Newton's iteration converged (meaningful where `ok`).
    pub converged: L::Mask,
}

/// Newton's iteration for rays meeting an asphere, per lane, between its
/// steps: what [`newton_start`] sets up, [`newton_step`] advances and
/// [`newton_hit`] turns into the hit.
#[derive(Clone, Copy)]
pub(crate) struct Newton<L: Real> {
    /// The ray's start, mm (the surface's frame).
    pub p: [L; 3],
    /// Distance along the ray from its start, mm.
    pub u: L,
    /// `Q` and `m` of the last evaluation, a step of at most the tolerance
    /// from the hit: the normal there.
    pub q: L,
    pub m: L,
    /// The lane's step was at most the tolerance: it left the iteration.
    pub converged: L::Mask,
    /// The lane left the surface's domain: it left the iteration.
    pub missed: L::Mask,
}

/// What an asphere's iteration starts from, in the f32 lanes `S`
/// (`f32` for one ray, a vector holding two of the batch's vectors'
/// lanes): the surface's start conic (`c`, `k c`, `(1 + k) c`) and its
/// rings (`zones.rs`).
///
/// The start decides only how many steps a ray takes, never where it ends,
/// and f32 is near enough for it: its rounding moves the start by about
/// 1e-7 of the ray's distance to the surface (under 1e-6 mm in a camera
/// lens), against the 1e-5 to 1e-4 mm by which the conics themselves miss
/// the surface, while the start's arithmetic then fills twice the lanes of
/// a register (docs/performance.md). Every path computes it with the same
/// f32 operations (`lanes.rs`), so the paths still agree bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StartLanes<S> {
    c: S,
    kc: S,
    k1c: S,
    /// The rings' conics, which start the iteration instead where the
    /// start conic is far from the surface.
    zones: Option<Zones>,
}

/// The start of Newton's iteration for one ray `p + t d` (unit `d`, the
/// asphere's frame) meeting the asphere `a`: for a pure conic its root,
/// which is the intersection ([`conic_only_root`], [`conic_only_start`]);
/// otherwise the ray narrowed to f32 and its start found there
/// ([`start_root`], [`start_u`]), widened back. The batch does the same
/// for two vectors at a time.
#[inline(always)]
pub(crate) fn newton_start(a: &AsphereLanes<f64>, p: [f64; 3], d: [f64; 3]) -> Newton<f64> {
    if a.conic_only {
        return conic_only_start(p, d, &conic_only_root(a, p, d));
    }
    let far = is_far(p);
    let t0 = if far { to_vertex_plane(p, d) } else { 0.0 };
    let near = if far { along(p, d, t0) } else { p };
    let (p32, d32) = (near.map(|v| v as f32), d.map(|v| v as f32));
    let u = f64::from(start_u(&a.start, p32, d32, &start_root(&a.start, p32, d32)));
    newton_start_at(p, if far { t0 + u } else { u })
}

/// A ray whose start lies farther than this from the asphere's vertex
/// plane (mm) is first moved along itself to near that plane
/// ([`to_vertex_plane`]): its start is found from `p + t0 d`, in f32, and
/// `t0` added back in f64. A ray from 1 m away would otherwise lose 1e-4 mm
/// of its start to f32's rounding of its distance, and take more steps; a
/// ray within a lens is near enough as it is (6e-8 of 64 mm is 4e-6 mm),
/// and the batch moves only the vectors with a far lane.
pub(crate) const FAR_MM: f64 = 64.0;

/// Whether the ray from `p` starts farther than [`FAR_MM`] from the vertex
/// plane, per lane.
#[inline(always)]
pub(crate) fn is_far<L: Real>(p: [L; 3]) -> L::Mask {
    !p[2].abs().le(L::splat(FAR_MM))
}

/// The point `p + t d` of a ray, each coordinate one fused multiply-add
/// (every path and stage computes its points so, for the same bits).
#[inline(always)]
pub(crate) fn along<L: Real>(p: [L; 3], d: [L; 3], t: L) -> [L; 3] {
    [t.fma(d[0], p[0]), t.fma(d[1], p[1]), t.fma(d[2], p[2])]
}

/// About how far the ray `p + t d` goes to the asphere's vertex plane: `-pz
/// / dz` with `1 / |dz|` to first order in `dx^2 + dy^2` (no division; any
/// point of the ray near the surface will do).
#[inline(always)]
pub(crate) fn to_vertex_plane<L: Real>(p: [L; 3], d: [L; 3]) -> L {
    let rho2 = d[0].fma(d[0], d[1] * d[1]);
    // 1 / dz = sign(dz) (1 + rho2 / 2 + ...)
    let inv_dz = rho2.fma(L::splat(0.5), L::splat(1.0)).or(d[2].sign_bit());
    -(p[2] * inv_dz)
}

/// The conic's quadratic `A t^2 + 2 B t + C = 0` for the ray `p + t d`,
/// `A = c (1 + k dz^2)`, `B = c (p . d) + k c pz dz - dz` and `C = c |p|^2 +
/// k c pz^2 - 2 pz`, with the square root of its discriminant: the part of
/// the start up to its square root (the batch computes it for a chunk's
/// vectors first, so that their square roots and divisions overlap).
#[derive(Clone, Copy)]
pub(crate) struct ConicRoot<L> {
    /// The conic's `(1 + k) c`, and `pz` from its vertex.
    pub k1c: L,
    pub pz: L,
    /// `A` of the quadratic.
    pub qa: L,
    /// The start's root is `-qc / far`: from the surface's own conic `C`
    /// and `B + s sqrt(B^2 - A C)` (s the sign of B: the nearer root,
    /// rationalised), from a ring's conic the front root's parts
    /// ([`front_parts`]).
    pub qc: L,
    pub far: L,
    /// `B^2 - A C`.
    pub disc: L,
}

/// A pure conic's quadratic for the ray `p + t d` (in f64: its root is the
/// intersection).
#[inline(always)]
pub(crate) fn conic_only_root<L: Real>(a: &AsphereLanes<L>, p: [L; 3], d: [L; 3]) -> ConicRoot<L> {
    let own = StartConic { c: a.c, kc: a.start_kc, k1c: a.start_k1c, pz: p[2] };
    conic_root_of(&own, p, d, false)
}

/// A pure conic's intersection with the ray `p + t d` from its quadratic
/// `q` ([`conic_only_root`]): the nearer root on the vertex sheet
/// ([`nearer_or_other`]), done unless the line misses; the normal needs
/// `m` there (and `Q` = 0).
#[inline(always)]
pub(crate) fn conic_only_start<L: Real>(p: [L; 3], d: [L; 3], q: &ConicRoot<L>) -> Newton<L> {
    let u = nearer_or_other(q, d);
    let met = !q.disc.is_neg() & u.is_finite();
    let m = (-q.k1c).fma(u.fma(d[2], q.pz), L::splat(1.0));
    Newton { p, u, q: L::splat(0.0), m, converged: met, missed: !met }
}

/// Newton's iteration for the ray from `p`, starting `u` along it: still
/// iterating, missed where `u` is not finite.
#[inline(always)]
pub(crate) fn newton_start_at<L: Real>(p: [L; 3], u: L) -> Newton<L> {
    Newton { p, u, q: L::splat(0.0), m: L::splat(1.0), converged: !L::Mask::all_true(), missed: !u.is_finite() }
}

/// [`ConicRoot`] of the conic the ray `p + t d` starts from
/// ([`start_conic`]), in f32 lanes.
#[inline(always)]
pub(crate) fn start_root<S: RingRows>(st: &StartLanes<S>, p: [S; 3], d: [S; 3]) -> ConicRoot<S> {
    ring_or_start(st, conic_root_of(&start_conic(st, p, d), p, d, st.zones.is_some()), p, d)
}

/// `ring` (the root of a ray's ring's conic), but the start conic's root
/// for the lanes whose line misses their ring's conic: a rare ray, for
/// which the surface's own conic is the surer start.
#[inline(always)]
pub(crate) fn ring_or_start<S: Real>(st: &StartLanes<S>, ring: ConicRoot<S>, p: [S; 3], d: [S; 3]) -> ConicRoot<S> {
    let missed = ring.disc.is_neg();
    if st.zones.is_none() || !missed.any() {
        return ring;
    }
    let own = conic_root_of(&own_start(st, p[2]), p, d, false);
    // selects written out: a closure called six times may not be inlined
    // into the batch's AVX2 code (on_sheet's note)
    ConicRoot {
        k1c: S::select(missed, own.k1c, ring.k1c),
        pz: S::select(missed, own.pz, ring.pz),
        qa: S::select(missed, own.qa, ring.qa),
        qc: S::select(missed, own.qc, ring.qc),
        far: S::select(missed, own.far, ring.far),
        disc: S::select(missed, own.disc, ring.disc),
    }
}

/// The conic whose root starts the iteration of the ray `p + t d`, per
/// lane: the surface's start conic, or the ring's (`zones.rs`).
#[derive(Clone, Copy)]
pub(crate) struct StartConic<L> {
    /// Curvature `c`, `k c` and `(1 + k) c` (k the conic constant).
    pub c: L,
    pub kc: L,
    pub k1c: L,
    /// The ray's `pz` from the conic's vertex.
    pub pz: L,
}

/// [`StartConic`] for the ray `p + t d` (the part of [`start_root`] before
/// the quadratic: the batch finds a chunk's rings first, so that their
/// table reads overlap).
#[inline(always)]
pub(crate) fn start_conic<S: RingRows>(st: &StartLanes<S>, p: [S; 3], d: [S; 3]) -> StartConic<S> {
    match &st.zones {
        None => own_start(st, p[2]),
        Some(z) => ring_conic(z.of_ray(p, d), p[2]),
    }
}

/// The surface's own start conic, for a ray at `pz` from its vertex.
#[inline(always)]
fn own_start<S: Real>(st: &StartLanes<S>, pz: S) -> StartConic<S> {
    StartConic { c: st.c, kc: st.kc, k1c: st.k1c, pz }
}

/// The surface's rings, where it starts its rays from their conics.
#[inline(always)]
pub(crate) fn zones_of<L: Real>(a: &AsphereLanes<L>) -> Option<&Zones> {
    a.start.zones.as_ref()
}

/// [`StartConic`] from the conic `(c, k c, z0)` of the ray's ring.
#[inline(always)]
pub(crate) fn ring_conic<L: Real>((c, kc, z0): (L, L, L), pz: L) -> StartConic<L> {
    StartConic { c, kc, k1c: kc + c, pz: pz - z0 }
}

/// [`ConicRoot`] from the ray's start conic, its start the front root
/// where `front` (a ring's conic), else the nearer root.
#[inline(always)]
pub(crate) fn conic_root_of<L: Real>(sc: &StartConic<L>, p: [L; 3], d: [L; 3], front: bool) -> ConicRoot<L> {
    let StartConic { c, kc, k1c, pz } = *sc;
    let qa = kc.fma(d[2] * d[2], c);
    // c (p . d) + k c pz dz - dz
    let qb = c.fma(pz.fma(d[2], p[0].fma(d[0], p[1] * d[1])), (kc * pz).fma(d[2], -d[2]));
    // c |p|^2 + k c pz^2 - 2 pz
    let qc = c.fma(pz.fma(pz, p[0].fma(p[0], p[1] * p[1])), (kc * pz).fma(pz, -(pz + pz)));
    let disc = qb.fma(qb, -(qa * qc));
    let root = L::select(disc.is_neg(), L::splat(0.0), disc.sqrt());
    let (qc, far) = if front {
        // -qc / far is the front root
        let (num, den) = front_parts(qa, qb, qc, root.or(d[2].sign_bit()), d);
        (-num, den)
    } else {
        (qc, qb + root.or(qb.sign_bit()))
    };
    ConicRoot { k1c, pz, qa, qc, far, disc }
}

/// The front root of the conic's quadratic `A t^2 + 2 B t + C = 0`
/// ([`ConicRoot`]), as a numerator and denominator: where the ray of
/// direction `d` crosses the conic in its direction of travel, where the
/// conic's normal `(-c x, -c y, 1 - (1 + k) c z)` has a positive part along
/// the ray for a ray going towards +z (the sheet through the vertex, met
/// from its front), so where `G' = 2 (A t + B) = -2 sigma sqrt(B^2 - A C)`:
/// `t = (-B - sigma sqrt(..)) / A`, with one division, rationalised as
/// `C / (sigma sqrt(..) - B)` where B's sign is not sigma's (no
/// cancellation either way). Not finite where the line misses the conic's
/// front (`A` = 0 with B's sign sigma's: one root, on the back). `root` is
/// `sigma sqrt(B^2 - A C)`.
#[inline(always)]
fn front_parts<L: Real>(qa: L, qb: L, qc: L, root: L, d: [L; 3]) -> (L, L) {
    let rationalised = (qb * d[2]).le(L::splat(0.0));
    (L::select(rationalised, qc, -(qb + root)), L::select(rationalised, root - qb, qa))
}

/// The nearer root of the conic's quadratic `q` (built for it: `front`
/// false) where it lies on the vertex sheet, else the other where that
/// does (a strong hyperboloid's second sheet lies close in front of the
/// vertex): the other computed only where some lane needs it.
#[inline(always)]
fn nearer_or_other<L: Real>(q: &ConicRoot<L>, d: [L; 3]) -> L {
    let near = -q.qc / q.far;
    let near_ok = on_sheet(q.k1c, q.pz, near, d);
    if !(!near_ok).any() {
        return near;
    }
    let other = -q.far / q.qa;
    L::select(near_ok | !on_sheet(q.k1c, q.pz, other, d) | !other.is_finite(), near, other)
}

/// Whether the point `u` along the ray (direction `d`, `pz` from the
/// conic's vertex) lies on the conic's sheet through the vertex (`1 - (1 +
/// k) c z > 0`). A function, not a closure: a closure called twice may not
/// be inlined into the batch's AVX2 code, and outside it runs without its
/// target features.
#[inline(always)]
fn on_sheet<L: Real>(k1c: L, pz: L, u: L, d: [L; 3]) -> L::Mask {
    !(-k1c).fma(u.fma(d[2], pz), L::splat(1.0)).le(L::splat(0.0))
}

/// Where the iteration of the ray `p + t d` starts, from its start conic's
/// quadratic `q` ([`start_root`]), in f32 lanes: a root of that conic on
/// its sheet through the vertex (`1 - (1 + k) c z > 0`). From a ray's
/// ring's conic the root where the ray crosses it in its direction of
/// travel ([`front_parts`]: the conic is often an oblate ellipsoid the ray
/// starts inside, with its nearer root on the far sheet), or, for the rare
/// lane where that is off the vertex sheet or missing, the surface's start
/// conic's; from the surface's start conic the nearer root, rationalised
/// (`-C / (B + s R)`, `R` the discriminant's square root, s the sign of
/// B), where it lies on that sheet, else the other (a strong hyperboloid's
/// second sheet lies close in front of the vertex). Where the line misses
/// the conic, `-C / B` (where it would touch it).
#[inline(always)]
pub(crate) fn start_u<S: Real>(st: &StartLanes<S>, p: [S; 3], d: [S; 3], q: &ConicRoot<S>) -> S {
    if st.zones.is_none() {
        return nearer_or_other(q, d);
    }
    let near = -q.qc / q.far;
    let ok = on_sheet(q.k1c, q.pz, near, d) & near.is_finite();
    if (!ok).any() {
        let own = conic_root_of(&own_start(st, p[2]), p, d, false);
        S::select(ok, near, nearer_or_other(&own, d))
    } else {
        near
    }
}

/// One step of Newton's iteration for the lanes still in it; the others
/// are left as they are, so a lane's numbers do not depend on how long its
/// neighbours iterate.
///
/// The iteration solves the surface in implicit form, free of square
/// roots: with `w = z - P(r)` the height above the polynomial part, the
/// conic `G = c r^2 - 2 w + (1 + k) c w^2 = 0`, whose root near the vertex
/// (`m = 1 - (1 + k) c w > 0`) is the sag. A lane leaves when its step is at
/// most [`NEWTON_TOLERANCE_MM`] (taking that step) or when it leaves the
/// conic's domain (a miss).
///
/// For an asphere without an r^1 term the step is Chebyshev's, third
/// order: with `t = G / G'` and `h = G'' / (2 G')`, `du = t (1 + h t)`
/// (`G''` along the ray exactly, no division beyond `1 / G'` but an r^3
/// term's `1 / r`); its error after the step is
/// about `(2 h^2 - G''' / (6 G')) t^3`, and a lane also leaves when
/// `|t| <=` [`ESTIMATE_FROM_MM`] and `100 h^2 |t|^3` (the first part, with a
/// wide margin for the second) is at most the tolerance: a mild asphere
/// then needs one step from the conic's root instead of two.
///
/// `THIRD` must be [`AsphereLanes::third_order`] (as for the functions
/// below): a constant, so that each kind of surface gets its own code.
#[inline(always)]
pub(crate) fn newton_step<L: Real, const THIRD: bool, const ODD: bool, const TERMS: usize>(
    a: &AsphereLanes<L>,
    d: [L; 3],
    st: &mut Newton<L>,
) {
    let ev = newton_eval::<L, THIRD, ODD, TERMS>(a, d, st);
    newton_finish::<L, THIRD>(st, &ev);
}

/// What one step of [`newton_step`] evaluates before its division: `G`,
/// `G'` and (third-order steps) `G''` along the ray, each halved, with `Q`
/// and `m` at the point and whether it lies outside the conic's domain. The batch
/// evaluates a chunk's vectors first and divides after, so that the
/// divisions overlap.
#[derive(Clone, Copy)]
pub(crate) struct NewtonEval<L> {
    pub g: L,
    pub gp: L,
    pub gpp: L,
    pub q: L,
    pub m: L,
    /// `1 - (1 + k) c^2 r^2` there: negative outside the conic's domain.
    pub domain: L,
}

/// The part of [`newton_step`] before its division.
#[inline(always)]
pub(crate) fn newton_eval<L: Real, const THIRD: bool, const ODD: bool, const TERMS: usize>(
    a: &AsphereLanes<L>,
    d: [L; 3],
    st: &Newton<L>,
) -> NewtonEval<L> {
    let one = L::splat(1.0);
    let [x, y, z] = along(st.p, d, st.u);
    let s = x.fma(x, y * y);
    let (pp, q, r) = a.poly_r::<ODD, TERMS>(s);
    let w = z - pp;
    let m = (-a.k1c).fma(w, one);
    // G / 2 = c s / 2 + w (k1c w / 2 - 1); G' / 2 = c (r . d) - m w',
    // w' = dz - Q (r . d)
    let g = a.half_c.fma(s, w * a.half_k1c.fma(w, -one));
    let rd = x.fma(d[0], y * d[1]);
    let wp = (-q).fma(rd, d[2]);
    let gp = a.c.fma(rd, -(m * wp));
    let gpp = if THIRD {
        // G'' / 2 = c rho^2 - m w'' + k1c w'^2, -w'' = Q rho^2 + V rd^2
        let rho2 = d[0].fma(d[0], d[1] * d[1]);
        let minus_wpp = q.fma(rho2, a.v_at::<ODD, TERMS>(s, r) * rd * rd);
        (a.k1c * wp).fma(wp, m.fma(minus_wpp, a.c * rho2))
    } else {
        L::splat(0.0)
    };
    NewtonEval { g, gp, gpp, q, m, domain: (-a.k1c2).fma(s, one) }
}

/// The part of [`newton_step`] from its division on: the step, the lanes'
/// verdicts, the state updated.
#[inline(always)]
pub(crate) fn newton_finish<L: Real, const THIRD: bool>(st: &mut Newton<L>, ev: &NewtonEval<L>) {
    let one = L::splat(1.0);
    let NewtonEval { g, gp, gpp, q, m, domain } = *ev;
    let tol = L::splat(NEWTON_TOLERANCE_MM);
    let (du, done_now) = if THIRD {
        let inv = one / gp;
        let t = g * inv;
        let ht = L::splat(0.5) * gpp * inv * t;
        let du = t.fma(ht, t);
        let at = t.abs();
        // 100 h^2 |t|^3 <= tol
        let estimate = (ht * ht * at).le(L::splat(NEWTON_TOLERANCE_MM / 100.0)) & at.le(L::splat(ESTIMATE_FROM_MM));
        (du, du.abs().le(tol) | estimate)
    } else {
        let du = g / gp;
        (du, du.abs().le(tol))
    };
    let bad = domain.is_neg() | !du.is_finite();
    let active = !(st.converged | st.missed);
    let now = active & !bad & done_now;
    let step = active & !bad;
    st.u = L::select(step, st.u - du, st.u);
    if !THIRD {
        // the normal at the last evaluation (a third-order step's hit
        // evaluates its own)
        st.q = L::select(step, q, st.q);
        st.m = L::select(step, m, st.m);
    }
    st.missed = st.missed | (active & bad);
    st.converged = st.converged | now;
}

/// Whether any lane is still iterating.
#[inline(always)]
pub(crate) fn newton_running<L: Real>(st: &Newton<L>) -> bool {
    (!(st.converged | st.missed)).any()
}

/// The hit after the iteration, with the normal there.
#[inline(always)]
pub(crate) fn newton_hit<L: Real, const THIRD: bool, const ODD: bool, const TERMS: usize>(
    a: &AsphereLanes<L>,
    d: [L; 3],
    st: &Newton<L>,
) -> AsphereHit<L> {
    let [x, y, z] = along(st.p, d, st.u);
    // a step the estimate ended may be up to ESTIMATE_FROM_MM long: the
    // normal is evaluated again at the hit (otherwise the last evaluation,
    // at most the tolerance away, is the hit's)
    let r2 = x.fma(x, y * y);
    let (m, q) = if THIRD {
        let (pp, q) = a.poly::<ODD, TERMS>(r2);
        ((-a.k1c).fma(z - pp, L::splat(1.0)), q)
    } else {
        (st.m, st.q)
    };
    let cq = m.fma(q, a.c);
    hit_with_normal(d, st, [-(x * cq), -(y * cq), m], r2)
}

/// The hit of the iteration `st` with its normal `n` and its `r2`
/// ([`newton_hit`]'s): the point from the ray again, the verdicts from the
/// state and `n`'s `m`, so that the batch keeps only the normal and `r2`
/// between its loops.
#[inline(always)]
pub(crate) fn hit_with_normal<L: Real>(d: [L; 3], st: &Newton<L>, n: [L; 3], r2: L) -> AsphereHit<L> {
    let [x, y, z] = along(st.p, d, st.u);
    let near = !n[2].le(L::splat(0.0));
    let missed = st.missed;
    AsphereHit { t: st.u, x, y, z, r2, n, ok: !missed & near, converged: st.converged & !missed }
}

/// Intersects one ray `p + t d` (unit `d`, the asphere's frame) with the
/// asphere `a`: [`newton_start`], then [`newton_step`] until the ray has
/// left the iteration or [`MAX_NEWTON_STEPS`] were taken.
#[inline(always)]
pub(crate) fn meet_asphere(a: &AsphereLanes<f64>, p: [f64; 3], d: [f64; 3]) -> AsphereHit<f64> {
    macro_rules! go {
        ($third:literal, $odd:literal, $terms:literal) => {
            meet::<$third, $odd, $terms>(a, p, d)
        };
    }
    by_asphere_kind!(a, go)
}

/// `$go!(THIRD, ODD, TERMS)` with the kernel's constants for the asphere
/// `$a` (an [`AsphereLanes`]): the one list of the kinds of asphere that
/// get code of their own, for the one-ray path ([`meet_asphere`]) and the
/// batch (`batch.rs`), so that both take the same steps.
macro_rules! by_asphere_kind {
    ($a:expr, $go:ident) => {
        match ($a.third_order(), $a.odd(), $a.chain_terms()) {
            (false, _, _) => $go!(false, false, 0),
            (true, false, 4) => $go!(true, false, 4),
            (true, false, 5) => $go!(true, false, 5),
            (true, false, 6) => $go!(true, false, 6),
            (true, false, _) => $go!(true, false, 8),
            (true, true, 5) => $go!(true, true, 5),
            (true, true, _) => $go!(true, true, 8),
        }
    };
}
pub(crate) use by_asphere_kind;

/// [`meet_asphere`] for a surface whose [`AsphereLanes::third_order`],
/// [`AsphereLanes::odd`] and [`AsphereLanes::chain_terms`] are `THIRD`,
/// `ODD` and `TERMS`.
#[inline(always)]
fn meet<const THIRD: bool, const ODD: bool, const TERMS: usize>(
    a: &AsphereLanes<f64>,
    p: [f64; 3],
    d: [f64; 3],
) -> AsphereHit<f64> {
    let mut st = newton_start(a, p, d);
    for _ in 0..MAX_NEWTON_STEPS {
        if !newton_running(&st) {
            break;
        }
        newton_step::<f64, THIRD, ODD, TERMS>(a, d, &mut st);
    }
    newton_hit::<f64, THIRD, ODD, TERMS>(a, d, &st)
}

/// An asphere step for one ray: shift into the surface's frame, intersect
/// ([`meet_asphere`]), clip by the clear aperture, refract at the unit
/// normal. `REFRACT` must be the step's `refract`. (The batch runs the same
/// stages over a chunk: `batch.rs`.)
#[inline(always)]
pub(crate) fn asphere_step<const REFRACT: bool>(
    s: &StepLanes<f64>,
    a: &AsphereLanes<f64>,
    l: Lane<f64>,
) -> StepOut<f64> {
    let p = [l.px, l.py, l.pz - s.shift];
    let d = [l.dx, l.dy, l.dz];
    asphere_carry::<f64, REFRACT>(s, &meet_asphere(a, p, d), d, l.opl)
}

/// The rest of an asphere step after the hit `h` of the ray of direction
/// `d` and path length `opl`: clip, refract at the unit normal, add the
/// path.
#[inline(always)]
pub(crate) fn asphere_carry<L: Real, const REFRACT: bool>(
    s: &StepLanes<L>,
    h: &AsphereHit<L>,
    d: [L; 3],
    opl: L,
) -> StepOut<L> {
    let inside = s.inside_r2(h.r2);
    let ([dx, dy, dz], through) = if REFRACT {
        // at the normal as it comes, not unit: one square root fewer
        let [nx, ny, nz] = h.n;
        let q = nz.fma(nz, nx.fma(nx, ny * ny));
        let g = d[2].fma(nz, d[0].fma(nx, d[1] * ny));
        let (root, through) = snell_root_unnormalised::<L, REFRACT>(s, g, q);
        (refract_scaled(d, h.n, s.mu, g, root, L::splat(1.0) / q), through)
    } else {
        (d, L::Mask::all_true())
    };
    let next = Lane { px: h.x, py: h.y, pz: h.z, dx, dy, dz, opl: s.n_before.fma(h.t, opl) };
    StepOut { next, verdict: Verdict::with_convergence(h.ok, h.converged, inside, through) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::surface::sag;

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    }

    /// A conic of k = 0 is the sphere: the hit agrees with the sphere's sag
    /// and lies on the surface to 1e-12 mm; a paraboloid's hit lies on z =
    /// c r^2 / 2.
    #[test]
    fn hits_lie_on_the_surface() {
        let sphere = AsphereLanes::<f64>::of(1.0 / 40.0, &Asphere::new(0.0, &[], &[]).unwrap(), f64::INFINITY);
        let para = AsphereLanes::<f64>::of(1.0 / 40.0, &Asphere::new(-1.0, &[], &[]).unwrap(), f64::INFINITY);
        let poly = Asphere::new(-0.7, &[1e-4, -3e-7, 2e-10], &[]).unwrap();
        let polyl = AsphereLanes::<f64>::of(1.0 / 40.0, &poly, f64::INFINITY);
        let odd = Asphere::new(0.0, &[], &[1e-3, 0.0, -2e-6]).unwrap();
        let oddl = AsphereLanes::<f64>::of(-1.0 / 60.0, &odd, f64::INFINITY);
        for (i, h0) in [0.0, 1.0, 5.0, 12.0, 20.0].iter().enumerate() {
            let p = [*h0, 0.3 * i as f64, -25.0];
            let d = unit([0.05, -0.02, 1.0]);
            let hs = meet_asphere(&sphere, p, d);
            assert!(hs.ok && hs.converged);
            let r = (hs.x * hs.x + hs.y * hs.y).sqrt();
            assert!((hs.z - sag(1.0 / 40.0, r).unwrap()).abs() < 1e-12);
            let hp = meet_asphere(&para, p, d);
            let r = (hp.x * hp.x + hp.y * hp.y).sqrt();
            assert!((hp.z - r * r / 80.0).abs() < 1e-12);
            let hq = meet_asphere(&polyl, p, d);
            let r = (hq.x * hq.x + hq.y * hq.y).sqrt();
            assert!(hq.converged && (hq.z - poly.sag(1.0 / 40.0, r).unwrap()).abs() < 1e-12);
            let ho = meet_asphere(&oddl, p, d);
            let r = (ho.x * ho.x + ho.y * ho.y).sqrt();
            assert!(ho.converged && (ho.z - odd.sag(-1.0 / 60.0, r).unwrap()).abs() < 1e-12);
        }
    }

    /// The third-order steps and their error estimate end on the surface:
    /// over mild to strong even aspheres, odd ones, and rays at every
    /// height and slope, each hit lies on the sag to 1e-12 mm, where a plain
    /// Newton iteration run to 1e-15 mm puts it to 1e-11 mm.
    #[test]
    fn the_error_estimate_ends_on_the_surface() {
        let mut next = crate::trace::uniform(0x0123_4567_89ab_cdef);
        // the last two: odd terms from r^3 (a phone lens's surface, and one
        // of a camera's size)
        let phone = [0.0, 0.0, -0.04388, -0.02555, 0.0516, -0.04307, -0.02831, 0.03162, 0.0463, -0.04877];
        let cases = [
            (1.0 / 30.0, Asphere::new(-0.01, &[0.0, 1e-9, 1e-13], &[]).unwrap(), 3.0),
            (1.0 / 40.0, Asphere::new(-0.7, &[1e-4, -3e-7, 2e-10], &[]).unwrap(), 3.0),
            (1.0 / 8.0, Asphere::new(1.5, &[0.0, -2e-3, 1e-4, -3e-6], &[]).unwrap(), 3.0),
            (-1.0 / 12.0, Asphere::new(-3.0, &[2e-3, 5e-5, -1e-6, 1e-8], &[]).unwrap(), 3.0),
            (1.0 / -2.182, Asphere::new(1.105, &[], &phone).unwrap(), 1.1338),
            (1.0 / 25.0, Asphere::new(-0.5, &[], &[0.0, 0.0, 2e-4, -1e-5, 3e-7]).unwrap(), 3.0),
        ];
        let mut worst = 0.0f64;
        for (c, asph, sd) in &cases {
            let lanes = AsphereLanes::<f64>::of(*c, asph, sd * sd);
            assert!(lanes.third_order());
            for _ in 0..4000 {
                let p = [2.0 * sd * (next() - 0.5), 2.0 * sd * (next() - 0.5), -3.0 * next() - 0.1];
                let d = unit([0.4 * (next() - 0.5), 0.4 * (next() - 0.5), 1.0]);
                let h = meet_asphere(&lanes, p, d);
                if !(h.ok && h.converged) {
                    continue;
                }
                let r = (h.x * h.x + h.y * h.y).sqrt();
                let on = (h.z - asph.sag(*c, r).unwrap()).abs();
                assert!(on < 1e-12, "off the surface by {on:e}");
                // a plain Newton iteration on the sag, to 1e-15
                let mut t = h.t;
                for _ in 0..50 {
                    let (x, y, z) = (p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]);
                    let r = (x * x + y * y).sqrt();
                    let f = z - asph.sag(*c, r).unwrap();
                    let fp = d[2] - asph.slope(*c, r).unwrap() * (x * d[0] + y * d[1]) / r.max(1e-300);
                    let dt = f / fp;
                    t -= dt;
                    if dt.abs() < 1e-15 {
                        break;
                    }
                }
                worst = worst.max((t - h.t).abs());
            }
        }
        assert!(worst < 1e-11, "{worst:e}");
    }

    /// The 35 mm f/2's asphere (an r^4 term 0.3 mm from its base sphere at
    /// the rim): from its rings' conics (`zones.rs`) every ray through the
    /// aperture at up to 25 degrees ends in one third-order step, on the
    /// surface to 1e-12 mm; from its sphere's root most take two.
    #[test]
    fn rings_start_a_strong_asphere_one_step_from_its_hit() {
        let canon = Asphere::new(0.0, &[0.0, -1.49529e-05, 4.91763e-09, -4.11063e-11], &[]).unwrap();
        let c = 1.0 / -91.82;
        let ringed = AsphereLanes::<f64>::of(c, &canon, 11.9 * 11.9);
        let plain = AsphereLanes::<f64>::of(c, &canon, f64::INFINITY);
        assert!(ringed.start.zones.is_some() && plain.start.zones.is_none());
        let (one_ringed, one_plain) =
            one_step_rays::<false, 4>(&canon, c, 11.9, [&ringed, &plain], (11.5, 25f64.to_radians(), 0.5), 0x5eed);
        assert_eq!(one_ringed, 2000, "rays taking one step from the rings");
        assert!(one_plain < 200, "{one_plain} of 2000 took one step from the sphere");
        let steps = steps_to_hit::<false, 4>;
        // a ray far outside the aperture misses the outermost ring's conic
        // (an ellipsoid 17 mm across): it starts from the sphere's root, as
        // without rings
        let (p, d) = ([0.0, 50.0, -0.5], [0.0, 0.0, 1.0]);
        let (p32, d32) = ([0.0, 50.0, -0.5], [0.0, 0.0, 1.0]);
        let ring = conic_root_of(&start_conic(&ringed.start, p32, d32), p32, d32, true);
        assert!(ring.disc < 0.0, "the ring's conic is met");
        let (start, own) = (start_root(&ringed.start, p32, d32), start_root(&plain.start, p32, d32));
        assert!(
            start.disc >= 0.0 && start.far.to_bits() == own.far.to_bits() && start.qc.to_bits() == own.qc.to_bits()
        );
        let (_, h) = steps(&ringed, p, d);
        let (_, g) = steps(&plain, p, d);
        assert!(
            h.ok && h.converged && h.t.to_bits() == g.t.to_bits(),
            "{} {} {} against {}",
            h.ok,
            h.converged,
            h.t,
            g.t
        );
    }

    /// The phone lens's rear asphere (k = -3.707, odd terms r^3 to r^10,
    /// 2.93 mm clear radius: a wavy field flattener): its rays take
    /// third-order steps from its rings' conics (osculating conics and
    /// tangent paraboloids), many one step at up to 17 degrees; from its
    /// base conic almost every ray takes two or more. Too many of 32 rings
    /// miss it by more than 1e-4 mm, so it has 128. Every hit lies on the
    /// sag to 1e-12 mm and where the base conic's start puts it.
    #[test]
    fn rings_start_a_wavy_odd_asphere() {
        let phone = Asphere::new(
            -3.707,
            &[],
            &[0.0, 0.0, 0.001767, -0.04652, 0.01625, -0.003522, -0.0007106, 0.0003825, 6.271e-05, -2.631e-05],
        )
        .unwrap();
        let (c, sd) = (1.0 / 1.509, 2.9297);
        let ringed = AsphereLanes::<f64>::of(c, &phone, sd * sd);
        let plain = AsphereLanes::<f64>::of(c, &phone, f64::INFINITY);
        assert!(ringed.third_order() && ringed.odd() && ringed.chain_terms() == 5);
        let zones = ringed.start.zones.as_ref().expect("rings");
        assert_eq!(zones.count(), super::super::zones::FINE_ZONES);
        assert!(zones.own_conics() > 100, "{} rings with their own conic", zones.own_conics());
        let (one_ringed, one_plain) =
            one_step_rays::<true, 5>(&phone, c, sd, [&ringed, &plain], (0.98 * sd, 0.3, 0.2), 0xfee1);
        // 1261 and 5 of 2000 when written (126 of the 128 rings with a
        // conic of their own; 983 from 32 rings)
        assert!(one_ringed > 1150, "{one_ringed} of 2000 took one step from the rings");
        assert!(one_plain < 40, "{one_plain} of 2000 took one step from the base conic");
    }

    /// The third-order steps a ray `p + t d` takes to its hit on `a`
    /// (`ODD` and `TERMS` its [`AsphereLanes::odd`] and
    /// [`AsphereLanes::chain_terms`]), and the hit.
    fn steps_to_hit<const ODD: bool, const TERMS: usize>(
        a: &AsphereLanes<f64>,
        p: [f64; 3],
        d: [f64; 3],
    ) -> (usize, AsphereHit<f64>) {
        let mut st = newton_start(a, p, d);
        let mut n = 0;
        while newton_running(&st) && n < MAX_NEWTON_STEPS {
            newton_step::<f64, true, ODD, TERMS>(a, d, &mut st);
            n += 1;
        }
        (n, newton_hit::<f64, true, ODD, TERMS>(a, d, &st))
    }

    /// 2,000 rays that meet `asph` (base curvature `c`, clear radius `sd`)
    /// inside its aperture, each through a point within `reach` of the axis
    /// on the plane `before` mm in front of the vertex, up to `tilt` rad
    /// off the axis: how many end in one step from `ringed`'s start and from
    /// `plain`'s. Each hit lies on the sag to 1e-12 mm and within 1e-11 mm
    /// of where the plain start puts it.
    /// The start is made in f32 from the ray moved to near the vertex plane
    /// ([`to_vertex_plane`]): rays of the 35 mm f/2's asphere that start 1 m
    /// and 10 m away end in one step from the rings, as those starting
    /// 0.5 mm away do (from the ray's own start, f32 rounded 1e4 mm to
    /// 1e-3 mm and 42 of 2,000 took one step at 1 m, 3 at 10 m).
    #[test]
    fn a_far_ray_starts_as_near_as_a_close_one() {
        let canon = Asphere::new(0.0, &[0.0, -1.49529e-05, 4.91763e-09, -4.11063e-11], &[]).unwrap();
        let c = 1.0 / -91.82;
        let ringed = AsphereLanes::<f64>::of(c, &canon, 11.9 * 11.9);
        let plain = AsphereLanes::<f64>::of(c, &canon, f64::INFINITY);
        for before in [0.5, 1e3, 1e4] {
            let (one, _) = one_step_rays::<false, 4>(&canon, c, 11.9, [&ringed, &plain], (11.5, 0.4, before), 0x5eed);
            assert_eq!(one, 2000, "{before} mm away");
        }
    }

    fn one_step_rays<const ODD: bool, const TERMS: usize>(
        asph: &Asphere,
        c: f64,
        sd: f64,
        [ringed, plain]: [&AsphereLanes<f64>; 2],
        (reach, tilt, before): (f64, f64, f64),
        seed: u64,
    ) -> (usize, usize) {
        let mut next = crate::trace::uniform(seed);
        let (mut rays, mut one_ringed, mut one_plain) = (0, 0, 0);
        while rays < 2000 {
            let (r, phi) = (reach * next().sqrt(), std::f64::consts::TAU * next());
            let (th, psi) = (tilt * next(), std::f64::consts::TAU * next());
            let d = [th.sin() * psi.cos(), th.sin() * psi.sin(), th.cos()];
            // from `before` mm ahead of the vertex plane, through (r, phi)
            // on it
            let p = [r * phi.cos() - before * d[0] / d[2], r * phi.sin() - before * d[1] / d[2], -before];
            let (n, h) = steps_to_hit::<ODD, TERMS>(ringed, p, d);
            let (m, g) = steps_to_hit::<ODD, TERMS>(plain, p, d);
            if !(h.ok && h.converged) || h.x.hypot(h.y) > sd {
                continue;
            }
            rays += 1;
            let on = (h.z - asph.sag(c, h.x.hypot(h.y)).unwrap()).abs();
            assert!(on < 1e-12 && (h.t - g.t).abs() < 1e-11, "off by {on:e}, {:e} from the plain start", h.t - g.t);
            one_ringed += usize::from(n == 1);
            one_plain += usize::from(m == 1);
        }
        (one_ringed, one_plain)
    }

    /// The front root is where the ray crosses the conic in its direction
    /// of travel: on the conic, its normal's part along the ray of the sign
    /// of `dz`, for rays going either way, from inside and outside an oblate
    /// ellipsoid, a sphere and a hyperboloid.
    #[test]
    fn the_front_root_is_crossed_in_the_direction_of_travel() {
        let mut next = crate::trace::uniform(0xf0);
        for (c, k) in [(1.0 / 20.0, 0.0), (-1.0 / 20.0, 0.0), (1.0 / 15.0, 4.0), (-1.0 / 15.0, 4.0), (1.0 / 10.0, -5.0)]
        {
            let mut met = 0;
            for _ in 0..500 {
                let (th, psi) = (0.6 * next(), std::f64::consts::TAU * next());
                let sigma = if next() < 0.5 { -1.0 } else { 1.0 };
                let d = [th.sin() * psi.cos(), th.sin() * psi.sin(), sigma * th.cos()];
                let p = [6.0 * (next() - 0.5), 6.0 * (next() - 0.5), -sigma * (0.5 + 3.0 * next())];
                let q = conic_root_of(&StartConic { c, kc: k * c, k1c: (1.0 + k) * c, pz: p[2] }, p, d, true);
                let t = -q.qc / q.far;
                if q.disc < 0.0 || !t.is_finite() {
                    continue;
                }
                met += 1;
                let [x, y, z] = [p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]];
                let g = c * (x * x + y * y) + k * c * z * z - 2.0 * z + c * z * z;
                assert!(g.abs() < 1e-12, "c {c} k {k}: G = {g:e} at t {t}");
                let n = [-c * x, -c * y, 1.0 - (1.0 + k) * c * z];
                let along = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
                assert!(along * sigma > 0.0, "c {c} k {k}: crossed against the ray ({along}, dz {})", d[2]);
            }
            assert!(met > 300, "c {c} k {k}: {met} rays met");
        }
    }

    /// A strong hyperboloid (k = -222, a phone lens's) has its second sheet
    /// just in front of the vertex: the start takes the vertex's sheet.
    #[test]
    fn the_vertex_sheet_of_a_strong_hyperboloid_is_met() {
        let h = AsphereLanes::<f64>::of(1.0 / 5.694, &Asphere::new(-222.1, &[], &[]).unwrap(), f64::INFINITY);
        for y in [0.0, 0.5, 1.5] {
            let hit = meet_asphere(&h, [0.0, y, -0.1], [0.0, 0.0, 1.0]);
            assert!(hit.ok && hit.converged, "y {y}");
            let want = Asphere::new(-222.1, &[], &[]).unwrap().sag(1.0 / 5.694, y).unwrap();
            assert!((hit.z - want).abs() < 1e-12, "y {y}: {} vs {want}", hit.z);
        }
    }

    /// A ray outside a hyperbola-free ellipsoid's reach misses; a surface
    /// Newton cannot follow (a wildly oscillating polynomial) is reported as
    /// not converged, not as a hit.
    #[test]
    fn misses_and_non_convergence_are_typed() {
        let ell = AsphereLanes::<f64>::of(1.0 / 10.0, &Asphere::new(3.0, &[], &[]).unwrap(), f64::INFINITY);
        let h = meet_asphere(&ell, [8.0, 0.0, -5.0], [0.0, 0.0, 1.0]);
        assert!(!h.ok);
        let wild = Asphere::new(0.0, &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e3], &[]).unwrap();
        let w = AsphereLanes::<f64>::of(0.0, &wild, f64::INFINITY);
        let h = meet_asphere(&w, [1.2, 0.0, -5.0], unit([0.9, 0.0, 0.2]));
        assert!(!(h.ok && h.converged), "t {}", h.t);
    }
}
