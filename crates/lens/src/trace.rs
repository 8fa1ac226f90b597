//! Exact (real-ray) tracing through a prescription, one ray at a time.
//!
//! A [`Tracer`] is a prescription laid out for one direction of travel: a list
//! of steps, each a surface in its own local frame. A ray is carried from frame
//! to frame by a shift along z, intersected by [`crate::intersect`], clipped by
//! the clear aperture and refracted by [`crate::refract`]. The batch tracer in
//! [`crate::batch`] runs the same per-surface kernel, so both agree bit for bit.

use crate::intersect::{approach, meet_plane, meet_sphere, sphere_root, Approach, LaneHit};
use crate::lanes::{Mask, Real};
use crate::prescription::Prescription;
use crate::ray::{Outcome, Ray};
use crate::refract::{one_minus_square, snell_k};
use glam::DVec3;

/// Which way rays travel through the prescription.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// From object space through surface 1 .. n to the film.
    ObjectToImage,
    /// From the film (or image space) through surface n .. 1 into object
    /// space, as a renderer's camera rays do.
    ImageToObject,
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
    /// Subtracted from the ray's z to go from the previous frame to this one.
    pub shift: f64,
    /// Global z of this step's vertex, mm.
    pub vertex_z: f64,
    /// 0-based surface index (number of surfaces = the film).
    pub surface: usize,
    /// Whether the indices differ (otherwise the direction is kept exactly).
    pub refract: bool,
    /// How the surface is met: [`PLANE`], [`FLAT`] or [`CURVED`].
    pub shape: u8,
}

/// A plane (`c == 0`): met by [`meet_plane`], no square root.
pub(crate) const PLANE: u8 = 0;
/// A sphere with `|c| <` [`crate::intersect::CURVED`]: the rationalised root,
/// a division.
pub(crate) const FLAT: u8 = 1;
/// A sphere with `|c| >=` [`crate::intersect::CURVED`]: the root as
/// `(G - s sqrt(disc)) / c`, a multiplication.
pub(crate) const CURVED: u8 = 2;

/// The [`Step::shape`] of a surface of curvature `c`.
fn shape_of(c: f64) -> u8 {
    if c == 0.0 {
        PLANE
    } else if crate::intersect::is_curved(c) {
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

/// How a step went, per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Verdict<M> {
    /// The ray met the surface.
    pub ok: M,
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
        Verdict { ok, inside, through, passed: ok & inside & through }
    }
}

impl Verdict<bool> {
    /// The outcome kind of one ray's step.
    pub(crate) fn kind(self) -> u64 {
        kind_of(self.ok, self.inside, self.through)
    }
}

/// The outcome kind from the three tests, in the order they apply.
#[inline(always)]
pub(crate) fn kind_of(ok: bool, inside: bool, through: bool) -> u64 {
    if !ok {
        MISSED
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
    mu: L,
    mu2: L,
    one_minus_mu2: L,
    n_before: L,
    pub shift: L,
    /// `1 / c` for a [`CURVED`] sphere (0 otherwise).
    pub radius: L,
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
        }
    }

    /// Snell's `k` at this step for the squared cosine of incidence `cos2`.
    #[inline(always)]
    fn k(&self, cos2: L) -> L {
        snell_k(self.mu2, self.one_minus_mu2, cos2)
    }
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
        // a NaN root where k < 0: the ray stops there, its direction unused
        (k.sqrt(), !k.is_neg())
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
    let inside = !(s.sd2 - h.x.fma(h.x, h.y * h.y)).is_neg();
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
/// into the step's frame); one blocked or totally reflected moves to the hit
/// and keeps its direction.
#[inline(always)]
pub(crate) fn stopped(s: &Step, before: Lane<f64>, next: Lane<f64>, kind: u64) -> Lane<f64> {
    if kind == MISSED {
        Lane { pz: before.pz - s.shift, ..before }
    } else {
        Lane { dx: before.dx, dy: before.dy, dz: before.dz, ..next }
    }
}

/// [`step_lanes`] with the step's `refract` flag and shape turned into the
/// kernel's constants.
#[inline(always)]
pub(crate) fn step_dispatch<L: Real>(s: &Step, k: &StepLanes<L>, l: Lane<L>) -> StepOut<L> {
    match (s.refract, s.shape) {
        (true, PLANE) => step_lanes::<L, true, PLANE>(k, l),
        (true, FLAT) => step_lanes::<L, true, FLAT>(k, l),
        (true, _) => step_lanes::<L, true, CURVED>(k, l),
        (false, PLANE) => step_lanes::<L, false, PLANE>(k, l),
        (false, FLAT) => step_lanes::<L, false, FLAT>(k, l),
        (false, _) => step_lanes::<L, false, CURVED>(k, l),
    }
}

/// A prescription laid out for tracing in one direction. Cheap to build;
/// build once and trace many rays.
///
/// ```
/// use glam::DVec3;
/// use lens::{Prescription, Tracer, Ray};
/// let p = Prescription::from_json_str(r#"{"surfaces": [
///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
/// let tracer = Tracer::forward(&p);
/// let ray = Ray::new(DVec3::new(0.0, 1.0, -10.0), DVec3::Z).unwrap();
/// let on_film = tracer.trace(ray).reached().unwrap();
/// assert!(on_film.origin.y.abs() < 0.01); // near the focus of a 100 mm lens
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Tracer {
    pub(crate) steps: Vec<Step>,
    direction: Direction,
}

impl Tracer {
    /// Object to the film at the prescription's film distance.
    pub fn forward(p: &Prescription) -> Self {
        Self::forward_to_film(p, p.film_distance())
    }

    /// Object to a film `film_distance` mm behind the last vertex (any finite
    /// value; the film is a plane without clipping).
    pub fn forward_to_film(p: &Prescription, film_distance: f64) -> Self {
        let z = p.vertex_z();
        let s = p.surfaces();
        let mut steps: Vec<Step> = s
            .iter()
            .enumerate()
            .map(|(i, surf)| {
                let n1 = p.index_before(i);
                surface_step(surf, i, n1, surf.ior, if i == 0 { 0.0 } else { s[i - 1].thickness }, z[i])
            })
            .collect();
        let last = s.len() - 1;
        steps.push(Step {
            c: 0.0,
            sd2: f64::INFINITY,
            mu: 1.0,
            n_before: s[last].ior,
            shift: film_distance,
            vertex_z: z[last] + film_distance,
            surface: s.len(),
            refract: false,
            shape: PLANE,
        });
        Tracer { steps, direction: Direction::ObjectToImage }
    }

    /// From image space (the film) back to object space. The ray starts in
    /// the global frame; the outcome `Reached` holds it at the first surface
    /// with its object-space direction.
    pub fn reverse(p: &Prescription) -> Self {
        let z = p.vertex_z();
        let s = p.surfaces();
        let n = s.len();
        let steps = (0..n)
            .rev()
            .map(|i| {
                let shift = if i == n - 1 { z[i] } else { -s[i].thickness };
                surface_step(&s[i], i, s[i].ior, p.index_before(i), shift, z[i])
            })
            .collect();
        Tracer { steps, direction: Direction::ImageToObject }
    }

    /// Object space to the stop surface, with no clear aperture clipping:
    /// the outcome `Reached` holds the ray at its hit on the stop surface.
    /// Used to aim real rays at the stop.
    pub fn to_stop_unclipped(p: &Prescription) -> Tracer {
        let mut t = Tracer::forward(p);
        t.steps.truncate(p.stop_index() + 1);
        for s in &mut t.steps {
            s.sd2 = f64::INFINITY;
        }
        t
    }

    /// Direction of travel.
    pub fn direction(&self) -> Direction {
        self.direction
    }

    /// Number of ray-surface steps per ray (surfaces, plus the film going
    /// forward).
    pub fn step_count(&self) -> usize {
        self.steps.len()
    }

    /// Traces one ray (global frame) and classifies how it ended.
    pub fn trace(&self, ray: Ray) -> Outcome {
        self.walk_fastest(ray, |_, _, _| {})
    }

    /// [`Self::walk`] with hardware fused multiply-add where the CPU has it.
    #[inline(always)]
    fn walk_fastest(&self, ray: Ray, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> Outcome {
        #[cfg(target_arch = "x86_64")]
        if simd_fma() {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            return unsafe { self.walk_fma(ray, visit) };
        }
        self.walk(ray, visit)
    }

    /// [`Self::walk`] compiled with hardware fused multiply-add. The kernel
    /// uses `mul_add` everywhere, which is exactly rounded with or without
    /// the instruction, so this only changes the speed, never the bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn walk_fma(&self, ray: Ray, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> Outcome {
        self.walk(ray, visit)
    }

    /// Traces one ray and also returns the global point where it met each
    /// surface (and the film), in order, up to where it stopped: the path a
    /// layout drawing shows. The outcome is that of [`Self::trace`].
    pub fn trace_path(&self, ray: Ray) -> (Vec<DVec3>, Outcome) {
        let mut path = vec![ray.origin];
        let visit = |s: &Step, l: &Lane<f64>, kind: u64| {
            if kind != MISSED {
                path.push(DVec3::new(l.px, l.py, l.pz + s.vertex_z));
            }
        };
        let outcome = self.walk_fastest(ray, visit);
        (path, outcome)
    }

    /// Traces one ray and also returns where it met surface `surface`
    /// (0-based; global frame), if it got that far: what a shaped stop needs,
    /// without recording the whole path.
    pub fn trace_at_surface(&self, ray: Ray, surface: usize) -> (Outcome, Option<DVec3>) {
        let mut at = None;
        let visit = |s: &Step, l: &Lane<f64>, kind: u64| {
            if s.surface == surface && kind != MISSED {
                at = Some(DVec3::new(l.px, l.py, l.pz + s.vertex_z));
            }
        };
        let outcome = self.walk_fastest(ray, visit);
        (outcome, at)
    }

    /// Carries `ray` step by step until it stops, showing `visit` each
    /// step's result.
    #[inline(always)]
    fn walk(&self, ray: Ray, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> Outcome {
        let start = Lane {
            px: ray.origin.x,
            py: ray.origin.y,
            pz: ray.origin.z,
            dx: ray.direction.x,
            dy: ray.direction.y,
            dz: ray.direction.z,
            opl: 0.0,
        };
        let (l, k, kind) = self.walk_lane(start, visit);
        self.outcome(l, k, kind)
    }

    /// Carries one ray from `l` (global frame) step by step until it stops;
    /// returns its state in the frame of the step `k` where it stopped (the
    /// last when it passed every one) and the kind of the stop.
    #[inline(always)]
    pub(crate) fn walk_lane(
        &self,
        mut l: Lane<f64>,
        mut visit: impl FnMut(&Step, &Lane<f64>, u64),
    ) -> (Lane<f64>, usize, u64) {
        for (k, s) in self.steps.iter().enumerate() {
            let out = step_dispatch(s, &StepLanes::of(s), l);
            let kind = out.verdict.kind();
            if kind != PASSED {
                l = stopped(s, l, out.next, kind);
                visit(s, &l, kind);
                return (l, k, kind);
            }
            l = out.next;
            visit(s, &l, kind);
        }
        (l, self.steps.len() - 1, PASSED)
    }

    /// Builds the outcome of a ray whose state `l` is in the frame of step `k`.
    pub(crate) fn outcome(&self, l: Lane<f64>, k: usize, kind: u64) -> Outcome {
        let z = l.pz + self.steps[k].vertex_z;
        self.classify(
            Ray { origin: DVec3::new(l.px, l.py, z), direction: DVec3::new(l.dx, l.dy, l.dz) },
            l.opl,
            k,
            kind,
        )
    }

    /// Builds the outcome of a ray (global frame) that stopped at step `k`.
    pub(crate) fn classify(&self, ray: Ray, opl: f64, k: usize, kind: u64) -> Outcome {
        let surface = self.steps[k].surface;
        match kind {
            PASSED => Outcome::Reached { ray, opl },
            MISSED => Outcome::Missed { surface, ray, opl },
            BLOCKED => Outcome::Blocked { surface, ray, opl },
            _ => Outcome::TotalInternalReflection { surface, ray, opl },
        }
    }
}

fn surface_step(surf: &crate::Surface, i: usize, n1: f64, n2: f64, shift: f64, vertex_z: f64) -> Step {
    Step {
        c: surf.curvature,
        sd2: surf.semi_diameter.map_or(f64::INFINITY, |r| r * r),
        mu: n1 / n2,
        n_before: n1,
        shift,
        vertex_z,
        surface: i,
        refract: n1 != n2,
        shape: shape_of(surf.curvature),
    }
}
