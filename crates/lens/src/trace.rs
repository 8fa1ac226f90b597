//! Exact (real-ray) tracing through a prescription, one ray at a time.
//!
//! A [`Tracer`] is a prescription laid out for one direction of travel: a list
//! of steps, each a surface in its own local frame. A ray is carried from frame
//! to frame by a shift along z, intersected by [`crate::intersect`], clipped by
//! the clear aperture and refracted by [`crate::refract`]. The batch tracer in
//! [`crate::batch`] runs the same per-surface kernel, so both agree bit for bit.

use crate::intersect::{intersect_lanes, LaneHit};
use crate::prescription::Prescription;
use crate::ray::{Outcome, Ray};
use crate::refract::refract_lanes;
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

/// The state of one ray in a step's local frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lane {
    pub px: f64,
    pub py: f64,
    pub pz: f64,
    pub dx: f64,
    pub dy: f64,
    pub dz: f64,
    pub opl: f64,
}

/// Carries one ray across one step: shift into the frame, intersect, clip,
/// refract. Returns the new state and the outcome kind. On a miss the ray
/// keeps its direction and stays where it was (in the new frame); when
/// blocked or totally reflected it moves to the hit and keeps its direction.
#[inline(always)]
pub(crate) fn step_lane<const REFRACT: bool>(s: &Step, l: Lane) -> (Lane, u64) {
    let (l, h) = shift_and_hit(s, l);
    finish_lane::<REFRACT>(s, l, h)
}

/// First half of a step: the ray moved into the step's frame, and its hit.
#[inline(always)]
pub(crate) fn shift_and_hit(s: &Step, l: Lane) -> (Lane, LaneHit) {
    let l = Lane { pz: l.pz - s.shift, ..l };
    (l, intersect_lanes(s.c, l.px, l.py, l.pz, l.dx, l.dy, l.dz))
}

/// Second half of a step: clip by the clear aperture, refract, classify.
/// `l` is already in the step's frame.
#[inline(always)]
pub(crate) fn finish_lane<const REFRACT: bool>(s: &Step, l: Lane, h: LaneHit) -> (Lane, u64) {
    let r2 = h.x.mul_add(h.x, h.y * h.y);
    let inside = r2 <= s.sd2;
    let (ndx, ndy, ndz, through) = if REFRACT {
        let d = refract_lanes(l.dx, l.dy, l.dz, -s.c * h.x, -s.c * h.y, 1.0 - s.c * h.z, s.mu);
        (d.x, d.y, d.z, d.ok)
    } else {
        (l.dx, l.dy, l.dz, true)
    };
    let kind = if !h.ok {
        MISSED
    } else if !inside {
        BLOCKED
    } else if !through {
        TIR
    } else {
        PASSED
    };
    let passed = kind == PASSED;
    let out = Lane {
        px: if h.ok { h.x } else { l.px },
        py: if h.ok { h.y } else { l.py },
        pz: if h.ok { h.z } else { l.pz },
        dx: if passed { ndx } else { l.dx },
        dy: if passed { ndy } else { l.dy },
        dz: if passed { ndz } else { l.dz },
        opl: if h.ok { s.n_before.mul_add(h.t, l.opl) } else { l.opl },
    };
    (out, kind)
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
    fn walk_fastest(&self, ray: Ray, visit: impl FnMut(&Step, &Lane, u64)) -> Outcome {
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
    fn walk_fma(&self, ray: Ray, visit: impl FnMut(&Step, &Lane, u64)) -> Outcome {
        self.walk(ray, visit)
    }

    /// Traces one ray and also returns the global point where it met each
    /// surface (and the film), in order, up to where it stopped: the path a
    /// layout drawing shows. The outcome is that of [`Self::trace`].
    pub fn trace_path(&self, ray: Ray) -> (Vec<DVec3>, Outcome) {
        let mut path = vec![ray.origin];
        let visit = |s: &Step, l: &Lane, kind: u64| {
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
        let visit = |s: &Step, l: &Lane, kind: u64| {
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
    fn walk(&self, ray: Ray, mut visit: impl FnMut(&Step, &Lane, u64)) -> Outcome {
        let mut l = Lane {
            px: ray.origin.x,
            py: ray.origin.y,
            pz: ray.origin.z,
            dx: ray.direction.x,
            dy: ray.direction.y,
            dz: ray.direction.z,
            opl: 0.0,
        };
        for (k, s) in self.steps.iter().enumerate() {
            let (next, kind) = if s.refract { step_lane::<true>(s, l) } else { step_lane::<false>(s, l) };
            l = next;
            visit(s, &l, kind);
            if kind != PASSED {
                return self.outcome(l, k, kind);
            }
        }
        self.outcome(l, self.steps.len() - 1, PASSED)
    }

    /// Builds the outcome of a ray whose state `l` is in the frame of step `k`.
    pub(crate) fn outcome(&self, l: Lane, k: usize, kind: u64) -> Outcome {
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
    }
}
