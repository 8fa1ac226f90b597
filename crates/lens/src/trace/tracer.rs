//! The tracer: a prescription laid out as a list of [steps](super::step)
//! for one direction of travel, and the one-ray entry points (a ray, a
//! ray's path, a ray's hit on one surface). The batch entry points are in
//! [`super::batch`]; both run the same step kernel, so they agree bit for
//! bit.

use super::asphere::AsphereLanes;
use super::ray::{Outcome, Ray};
use super::step::*;
use crate::coating::{Coating, ReflectanceTable};
use crate::glass::kernel::Kernel;
use crate::glass::Glass;
use crate::model::Prescription;
use glam::DVec3;
use std::sync::Arc;

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
    /// The prescription's glasses, which [`Step::glass_before`] and
    /// `glass_after` index: a batch of mixed wavelengths evaluates them
    /// per ray (`trace::spectral`).
    pub(crate) glasses: Arc<[Glass]>,
    /// Each glass's formula as the kernel evaluates it.
    pub(crate) kernels: Vec<Kernel>,
    /// Each step's asphere as the one-ray path evaluates it (`None` for the
    /// other steps), made once with the steps ([`one_ray_aspheres`]): made
    /// per ray, it cost a ray some 100-250 ns an asphere (its rings
    /// copied, its chains built).
    pub(crate) aspheres: Vec<Option<AsphereLanes<f64>>>,
    /// Each surface's coating (0-based, as [`Prescription::coating`]).
    pub(crate) coatings: Arc<[Coating]>,
    /// The wavelength the steps' indices are for, nm (the coatings'
    /// interference needs it).
    pub(crate) wavelength_nm: f64,
    /// The index before surface 0, then after each surface, at that
    /// wavelength (a reflection's other side).
    pub(crate) media: Arc<[f64]>,
    /// The coatings' reflectances tabulated at that wavelength, read by
    /// [`Self::trace_fresnel`] where given ([`Self::with_reflectances`]).
    pub(crate) reflectances: Option<Arc<ReflectanceTable>>,
    /// A shaped stop's transmission, applied by [`Self::trace_fresnel`] at
    /// each pass through its surface ([`Self::with_stop_shape`]).
    pub(crate) stop_shape: Option<StopShape>,
}

/// A stop's shape for [`Tracer::trace_fresnel`]: at each pass through
/// surface `surface` (0-based), the ray's power is multiplied by
/// `transmission(x, y)` of the point it met the surface at (global frame,
/// mm): 1 inside a polygon of blades, 0 outside, a grey level for a mask.
/// The surface's clear aperture still clips (a shape inscribed in it
/// changes nothing outside).
#[derive(Clone)]
pub struct StopShape {
    /// The stop's surface, 0-based.
    pub surface: usize,
    /// The transmission at a point of the surface, global x and y in mm.
    pub transmission: Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>,
}

impl std::fmt::Debug for StopShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StopShape").field("surface", &self.surface).finish_non_exhaustive()
    }
}

impl PartialEq for StopShape {
    /// The same surface and the same function (one `Arc`).
    fn eq(&self, other: &Self) -> bool {
        self.surface == other.surface && Arc::ptr_eq(&self.transmission, &other.transmission)
    }
}

/// Each step's asphere in the one-ray path's numbers ([`Tracer::aspheres`]),
/// from its curvature, terms, clear aperture and rings as they are now:
/// made again where a tracer's clear apertures change
/// ([`Tracer::unclipped`]).
fn one_ray_aspheres(steps: &[Step]) -> Vec<Option<AsphereLanes<f64>>> {
    steps.iter().map(|s| s.asphere.map(|a| AsphereLanes::with_zones(s.c, &a, s.sd2, s.zones))).collect()
}

impl Tracer {
    /// Object to the film at the prescription's film distance.
    pub fn forward(p: &Prescription) -> Self {
        Self::forward_to_film(p, p.film_distance())
    }

    /// Object to a film `film_distance` mm behind the last vertex (any finite
    /// value; the film is a plane without clipping).
    pub fn forward_to_film(p: &Prescription, film_distance: f64) -> Self {
        Self::forward_steps(p, 0..p.surfaces().len(), film_distance)
    }

    /// [`Self::forward_to_film`] with every clear aperture, the stop's too,
    /// left open: where the rays of the whole pupil would go (the
    /// pupil's extent in image space, whatever vignettes it).
    pub fn forward_to_film_open(p: &Prescription, film_distance: f64) -> Self {
        let t = Self::forward_to_film(p, film_distance);
        let n = t.steps.len();
        t.unclipped(0..n)
    }

    /// From object space through surfaces `range.start` to `range.end - 1`
    /// only (0-based; clamped to the prescription), and on to the film at
    /// the prescription's film distance when the range ends at the last
    /// surface. Rays start and end in the global frame, so a trace can stop
    /// at a surface and go on from there: `forward_range(p, 0..k)` then
    /// `forward_range(p, k..n)` is the whole forward trace (equal to
    /// [`Self::forward`] to within rounding of the frame change at surface
    /// k).
    pub fn forward_range(p: &Prescription, range: std::ops::Range<usize>) -> Self {
        Self::forward_steps(p, range, p.film_distance())
    }

    /// The steps of [`Self::forward_range`] with the film `film_distance`
    /// mm behind the last vertex.
    fn forward_steps(p: &Prescription, range: std::ops::Range<usize>, film_distance: f64) -> Self {
        let z = p.vertex_z();
        let s = p.surfaces();
        let placed_at = p.placements();
        let hi = range.end.min(s.len());
        let lo = range.start.min(hi);
        let mut steps: Vec<Step> = (lo..hi)
            .map(|i| {
                let before = (p.index_before(i), i.checked_sub(1).and_then(|k| s[k].glass));
                let shift = if i == lo { z[i] } else { s[i - 1].thickness };
                placed(surface_step(&s[i], i, before, (s[i].ior, s[i].glass), shift, z[i]), placed_at[i])
            })
            .collect();
        if hi < s.len() {
            return Tracer::with_glasses(steps, p);
        }
        let last = s.len() - 1;
        steps.push(Step {
            c: 0.0,
            sd2: f64::INFINITY,
            mu: 1.0,
            n_before: s[last].ior,
            n_after: s[last].ior,
            glass_before: s[last].glass.map_or(NO_GLASS, |g| g as u32),
            glass_after: s[last].glass.map_or(NO_GLASS, |g| g as u32),
            shift: if steps.is_empty() { z[last] + film_distance } else { film_distance },
            vertex_z: z[last] + film_distance,
            surface: s.len(),
            refract: false,
            reflect: false,
            shape: PLANE,
            asphere: None,
            zones: None,
            focal: 0.0,
            frame: None,
        });
        Tracer::with_glasses(steps, p)
    }

    /// The path of a ghost: object space forward to surface `second`
    /// (0-based), reflected there, back through the surfaces between to
    /// surface `first` (< `second`), reflected there, and forward through
    /// the rest of the lens to the film `film_distance` mm behind the last
    /// vertex. Every clear aperture (the stop's in both directions) clips;
    /// the reflections keep the medium (`Outcome::Reached` holds the ray on
    /// the film as for [`Self::forward`]). `None` when `first >= second`,
    /// `second` is past the last surface, or either surface is an ideal
    /// (paraxial) one, which has no glass to reflect.
    ///
    /// ```
    /// use glam::DVec3;
    /// use lens::{Prescription, Tracer, Ray};
    /// // a plate 10 mm thick: the ghost of its two faces is the axial ray
    /// // delayed by two crossings
    /// let p = Prescription::from_json_str(r#"{"surfaces": [
    ///   {"thickness": 10, "ior": 1.5, "semi_diameter": 10, "stop": true},
    ///   {"thickness": 20, "semi_diameter": 10}]}"#, "<doc>").unwrap();
    /// let ghost = Tracer::ghost(&p, 0, 1, 20.0).unwrap();
    /// let r = ghost.trace(Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z).unwrap());
    /// let (ray, opl) = match r { lens::Outcome::Reached { ray, opl } => (ray, opl), o => panic!("{o:?}") };
    /// assert!((ray.origin.z - 30.0).abs() < 1e-12);
    /// assert!((opl - (5.0 + 3.0 * 15.0 + 20.0)).abs() < 1e-12);
    /// ```
    pub fn ghost(p: &Prescription, first: usize, second: usize, film_distance: f64) -> Option<Self> {
        let s = p.surfaces();
        let n = s.len();
        if first >= second || second >= n || s[first].paraxial.is_some() || s[second].paraxial.is_some() {
            return None;
        }
        let z = p.vertex_z();
        let placed_at = p.placements();
        let medium = |i: usize| (p.index_before(i), i.checked_sub(1).and_then(|k| s[k].glass));
        let after = |i: usize| (s[i].ior, s[i].glass);
        let mut steps: Vec<Step> = Vec::with_capacity(n + 2 * (second - first) + 1);
        // forward to `second`, each step shifted by the gap before it
        for i in 0..second {
            let shift = if i == 0 { z[0] } else { s[i - 1].thickness };
            steps.push(placed(surface_step(&s[i], i, medium(i), after(i), shift, z[i]), placed_at[i]));
        }
        let reflecting = |i: usize, (n, g): (f64, Option<usize>), shift: f64| {
            let mut step = surface_step(&s[i], i, (n, g), (n, g), shift, z[i]);
            step.refract = true;
            step.reflect = true;
            placed(step, placed_at[i])
        };
        steps.push(reflecting(second, medium(second), s[second - 1].thickness));
        // back from `second` to `first`, in the media between
        for i in (first + 1..second).rev() {
            steps.push(placed(surface_step(&s[i], i, after(i), medium(i), -s[i].thickness, z[i]), placed_at[i]));
        }
        steps.push(reflecting(first, after(first), -s[first].thickness));
        // forward again from `first` to the film
        for i in first + 1..n {
            steps.push(placed(surface_step(&s[i], i, medium(i), after(i), s[i - 1].thickness, z[i]), placed_at[i]));
        }
        let mut t = Self::forward_to_film(p, film_distance);
        let film = *t.steps.last()?;
        steps.push(Step { shift: film_distance, ..film });
        t.steps = steps;
        t.aspheres = one_ray_aspheres(&t.steps);
        Some(t)
    }

    /// One surface (0-based `i`) alone, met from object space (`backward`
    /// false: travelling +z, from the medium before it) or from image
    /// space, the ray refracted through it or, with `reflect`, reflected
    /// back into its medium. Rays start and end in the global frame; no
    /// film. The event a non-sequential walk through the lens is made of
    /// (the brute-force ghost reference, `ghost::reference`). `None` past
    /// the last surface, or for a reflection at an ideal (paraxial) one.
    pub fn at_surface(p: &Prescription, i: usize, backward: bool, reflect: bool) -> Option<Self> {
        let s = p.surfaces();
        if i >= s.len() || reflect && s[i].paraxial.is_some() {
            return None;
        }
        let z = p.vertex_z();
        let before = (p.index_before(i), i.checked_sub(1).and_then(|k| s[k].glass));
        let after = (s[i].ior, s[i].glass);
        let (from, to) = if backward { (after, before) } else { (before, after) };
        let mut step = surface_step(&s[i], i, from, if reflect { from } else { to }, z[i], z[i]);
        if reflect {
            step.refract = true;
            step.reflect = true;
        }
        Some(Tracer::with_glasses(vec![placed(step, p.placement(i))], p))
    }

    /// Which steps reflect: for a tracer from [`Self::ghost`], the two
    /// reflections' step numbers (the path's order), else `None`.
    pub fn reflections(&self) -> Option<[usize; 2]> {
        let mut at = self.steps.iter().enumerate().filter(|(_, s)| s.reflect).map(|(k, _)| k);
        Some([at.next()?, at.next()?])
    }

    /// Traces one ray as [`Self::trace`] and also returns the fraction of
    /// its power that takes this path: the product over the surfaces it
    /// meets of the reflectance (where the step reflects) or the
    /// transmittance 1 - R (where it refracts), each for unpolarised light
    /// at the ray's angle of incidence, through the surface's coating
    /// ([`Prescription::coating`]) at the tracer's wavelength (its
    /// prescription's [`Prescription::wavelength_nm`]). 1 for a surface
    /// between equal indices. A ray that stopped keeps the product up to
    /// the step before. The weight is 0 where the ray met a surface (or the
    /// film) behind itself, which sequential tracing allows (it follows the
    /// line) but light does not: a ghost path that turns back past the
    /// film, say.
    ///
    /// The angle of incidence comes from the directions before and after
    /// the step: `n2 d2 - n1 d1` lies along the normal (for a reflection
    /// `d2 - d1`), so the weight needs no surface normal and holds on
    /// aspheres and tilted surfaces alike. With a shaped stop
    /// ([`Self::with_stop_shape`]) the weight also carries the shape's
    /// transmission at each pass through the stop (a ghost's path may pass
    /// it three times).
    pub fn trace_fresnel(&self, ray: Ray) -> (Outcome, f64) {
        let (l, k, kind, weight) = self.fresnel_walk(Lane::of_ray(&ray));
        (self.outcome(l, k, kind), weight)
    }

    /// [`Self::walk_lane`] of one ray from `l` with its Fresnel weight
    /// ([`Self::trace_fresnel`]).
    pub(crate) fn fresnel_walk(&self, l: Lane<f64>) -> (Lane<f64>, usize, u64, f64) {
        let mut weight = 1.0;
        let mut before = DVec3::new(l.dx, l.dy, l.dz);
        let mut opl = l.opl;
        let visit = |s: &Step, l: &Lane<f64>, kind: u64| {
            if kind != PASSED {
                return;
            }
            weight = self.passed_weight(weight, s, before, opl, l);
            opl = l.opl;
            before = DVec3::new(l.dx, l.dy, l.dz);
        };
        let (l, k, kind) = self.walk_lane_fastest(l, visit);
        (l, k, kind, weight)
    }

    /// A ray's Fresnel weight `weight` carried across step `s`, which it
    /// passed: from its direction `before` the step and path length
    /// `opl_before`, to `l` after it. 0 where it met the surface behind
    /// itself (its path shrank: sequential tracing follows the line both
    /// ways, light does not); times the stop shape's transmission at a
    /// pass through the stop; times the surface's reflectance or
    /// transmittance at the angle of incidence. One function for the
    /// one-ray and the batch paths, so that they agree bit for bit.
    #[inline(always)]
    pub(crate) fn passed_weight(&self, weight: f64, s: &Step, before: DVec3, opl_before: f64, l: &Lane<f64>) -> f64 {
        let mut weight = if l.opl < opl_before { 0.0 } else { weight };
        if let Some(shape) = &self.stop_shape {
            if s.surface == shape.surface {
                weight *= (shape.transmission)(l.px, l.py);
            }
        }
        if s.surface >= self.coatings.len() {
            return weight;
        }
        let after = DVec3::new(l.dx, l.dy, l.dz);
        // light met the surface from its image side (travelling -z): the
        // layers in reverse, and a reflection's other side before it
        let backward = before.z < 0.0;
        let n2 = match (s.reflect, backward) {
            (false, _) => s.n_after,
            (true, false) => self.media[s.surface + 1],
            (true, true) => self.media[s.surface],
        };
        let n1 = s.n_before;
        let along = if s.reflect { after - before } else { n2 * after - n1 * before };
        let norm = along.length();
        if (s.reflect || n1 != n2) && norm > 0.0 {
            let cos1 = (before.dot(along) / norm).abs().min(1.0);
            let tabled = self.reflectances.as_ref().and_then(|t| t.get(s.surface, backward, cos1));
            let r = tabled
                .unwrap_or_else(|| self.coatings[s.surface].reflectance(n1, n2, cos1, self.wavelength_nm, backward));
            weight *= if s.reflect { r } else { 1.0 - r };
        }
        weight
    }

    /// The coatings' reflectances of this tracer's lens, tabulated at its
    /// wavelength, for [`Self::with_reflectances`]: build once and share
    /// among the tracers of one lens and wavelength.
    pub fn reflectance_table(&self) -> ReflectanceTable {
        ReflectanceTable::new(&self.coatings, &self.media, self.wavelength_nm)
    }

    /// This tracer with [`Self::trace_fresnel`] reading the reflectances
    /// from `table` (interpolated, within [`crate::coating::TABLE_TOLERANCE`]
    /// of the formula) instead of evaluating each coating at every step:
    /// for many rays through one lens and wavelength (a ghost's grid of
    /// rays). A table of another wavelength or lens (other media) is not
    /// taken: the tracer is returned as it was.
    pub fn with_reflectances(mut self, table: Arc<ReflectanceTable>) -> Self {
        if table.wavelength_nm == self.wavelength_nm && table.covers(&self.coatings, &self.media) {
            self.reflectances = Some(table);
        }
        self
    }

    /// This tracer with a shaped stop: [`Self::trace_fresnel`] multiplies
    /// each ray's weight by the shape's transmission where it passes the
    /// stop's surface (see [`StopShape`]). What a ghost's path needs behind
    /// an iris of blades; [`Self::trace`] and the batch tracers keep
    /// clipping at the clear apertures alone.
    ///
    /// ```
    /// use glam::DVec3;
    /// use lens::{Prescription, Ray, Tracer};
    /// use lens::trace::StopShape;
    /// use std::sync::Arc;
    /// let p = Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
    ///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
    /// // a square stop 10 mm each side of the axis
    /// let square = StopShape { surface: 0, transmission: Arc::new(|x: f64, y: f64| f64::from(x.abs().max(y.abs()) <= 10.0)) };
    /// let t = Tracer::forward(&p).with_stop_shape(square);
    /// let at = |x: f64| t.trace_fresnel(Ray::new(DVec3::new(x, 0.0, -10.0), DVec3::Z).unwrap()).1;
    /// assert!(at(8.0) > 0.9); // inside the square and the clear aperture
    /// assert_eq!(at(-11.0), 0.0); // in the clear aperture, outside the square
    /// ```
    pub fn with_stop_shape(mut self, shape: StopShape) -> Self {
        self.stop_shape = Some(shape);
        self
    }

    /// A tracer of `steps` through the glasses of `p`.
    fn with_glasses(steps: Vec<Step>, p: &Prescription) -> Self {
        let glasses = p.glasses_shared();
        let kernels = glasses.iter().map(|g| Kernel::of(&g.dispersion)).collect();
        let aspheres = one_ray_aspheres(&steps);
        let coatings = p.coatings().into();
        let media = std::iter::once(p.index_before(0)).chain(p.surfaces().iter().map(|s| s.ior)).collect();
        Tracer {
            steps,
            glasses,
            kernels,
            aspheres,
            coatings,
            wavelength_nm: p.wavelength_nm(),
            media,
            reflectances: None,
            stop_shape: None,
        }
    }

    /// From image space (the film) back to object space. The ray starts in
    /// the global frame; the outcome `Reached` holds it at the first surface
    /// with its object-space direction.
    pub fn reverse(p: &Prescription) -> Self {
        Self::reverse_range(p, 0..p.surfaces().len())
    }

    /// From image space back through surfaces `range.end - 1` down to
    /// `range.start` only (0-based; clamped to the prescription). Rays start
    /// and end in the global frame, so a trace can stop at a surface and go
    /// on from there: `reverse_range(p, k..n)` then `reverse_range(p, 0..k)`
    /// is the whole reverse trace (equal to [`Self::reverse`] to within
    /// rounding of the frame change at surface k).
    pub fn reverse_range(p: &Prescription, range: std::ops::Range<usize>) -> Self {
        let z = p.vertex_z();
        let s = p.surfaces();
        let placed_at = p.placements();
        let hi = range.end.min(s.len());
        let lo = range.start.min(hi);
        let steps = (lo..hi)
            .rev()
            .map(|i| {
                let shift = if i == hi - 1 { z[i] } else { -s[i].thickness };
                let before = (p.index_before(i), i.checked_sub(1).and_then(|k| s[k].glass));
                placed(surface_step(&s[i], i, (s[i].ior, s[i].glass), before, shift, z[i]), placed_at[i])
            })
            .collect();
        Tracer::with_glasses(steps, p)
    }

    /// From image space back to object space with no clear aperture
    /// clipping (the stop's included): what finds a film point's chief ray,
    /// which is defined whether or not the lens vignettes it.
    pub fn reverse_unclipped(p: &Prescription) -> Tracer {
        let t = Tracer::reverse(p);
        let all = 0..t.steps.len();
        t.unclipped(all)
    }

    /// Object space to the stop surface, with no clear aperture clipping:
    /// the outcome `Reached` holds the ray at its hit on the stop surface.
    /// Used to aim real rays at the stop.
    pub fn to_stop_unclipped(p: &Prescription) -> Tracer {
        let mut t = Tracer::forward(p);
        t.steps.truncate(p.stop_index() + 1);
        let all = 0..t.steps.len();
        t.unclipped(all)
    }

    /// Object space to the film with the stop's clear aperture left open
    /// (the other surfaces clip as usual): what finds the aperture the
    /// other surfaces allow.
    pub fn forward_without_stop(p: &Prescription) -> Tracer {
        let stop = p.stop_index();
        Tracer::forward(p).unclipped(stop..stop + 1)
    }

    /// This tracer with the steps `range` clipping nothing, their aspheres
    /// for the one-ray path made again (their start conics depend on the
    /// clear aperture): the one place a tracer's clear apertures change.
    fn unclipped(mut self, range: std::ops::Range<usize>) -> Tracer {
        for s in &mut self.steps[range] {
            s.sd2 = f64::INFINITY;
        }
        self.aspheres = one_ray_aspheres(&self.steps);
        self
    }

    /// Traces one ray (global frame) and classifies how it ended.
    pub fn trace(&self, ray: Ray) -> Outcome {
        self.walk_fastest(ray, |_, _, _| {})
    }

    /// [`Self::walk_lane`] with hardware fused multiply-add where the CPU
    /// has it.
    #[inline(always)]
    fn walk_lane_fastest(&self, l: Lane<f64>, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> (Lane<f64>, usize, u64) {
        #[cfg(target_arch = "x86_64")]
        if simd_fma() {
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            return unsafe { self.walk_lane_fma(l, visit) };
        }
        self.walk_lane(l, visit)
    }

    /// [`Self::walk_lane`] compiled with hardware fused multiply-add. The
    /// kernel uses `mul_add` everywhere, which is exactly rounded with or
    /// without the instruction, so this only changes the speed, never the
    /// bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn walk_lane_fma(&self, l: Lane<f64>, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> (Lane<f64>, usize, u64) {
        self.walk_lane(l, visit)
    }

    /// Carries `ray` step by step until it stops, showing `visit` each
    /// step's result ([`Self::walk_lane_fastest`]), and classifies how it
    /// ended.
    #[inline(always)]
    fn walk_fastest(&self, ray: Ray, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> Outcome {
        let (l, k, kind) = self.walk_lane_fastest(Lane::of_ray(&ray), visit);
        self.outcome(l, k, kind)
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

    /// Carries one ray from `l` (global frame) step by step until it stops;
    /// returns its state in the frame of the step `k` where it stopped (the
    /// last when it passed every one) and the kind of the stop.
    #[inline(always)]
    pub(crate) fn walk_lane(&self, l: Lane<f64>, visit: impl FnMut(&Step, &Lane<f64>, u64)) -> (Lane<f64>, usize, u64) {
        self.walk_lane_by(l, StepLanes::of, visit)
    }

    /// [`Self::walk_lane`] with each step's numbers from `lanes` (the
    /// step's own, or those of the ray's wavelength).
    #[inline(always)]
    pub(crate) fn walk_lane_by(
        &self,
        mut l: Lane<f64>,
        lanes: impl Fn(&Step) -> StepLanes<f64>,
        mut visit: impl FnMut(&Step, &Lane<f64>, u64),
    ) -> (Lane<f64>, usize, u64) {
        for (k, s) in self.steps.iter().enumerate() {
            // a decentred or tilted surface is met in its own frame
            let here = s.frame.map_or(l, |f| f.enter(l));
            let out = step_dispatch(s, self.aspheres[k].as_ref(), &lanes(s), here);
            let kind = out.verdict.kind();
            let (next, stop) =
                if kind == PASSED { (out.next, false) } else { (stopped(s, here, out.next, kind), true) };
            l = s.frame.map_or(next, |f| f.leave(next));
            visit(s, &l, kind);
            if stop {
                return (l, k, kind);
            }
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
            NOT_CONVERGED => Outcome::NotConverged { surface, ray, opl },
            _ => Outcome::TotalInternalReflection { surface, ray, opl },
        }
    }
}
