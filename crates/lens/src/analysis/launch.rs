//! Pupil coordinates and ray aiming: how the rays of a field ([`Field`],
//! in field.rs) enter the system.

use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::{imaging, FirstOrder};
use crate::trace::ray::{Outcome, Ray};
use crate::trace::Tracer;
use glam::{DVec2, DVec3};

use super::field::check_field;
pub use super::field::Field;

/// How a pupil coordinate becomes a ray.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Aim {
    /// Through (px, py) x the paraxial entrance-pupil radius on the paraxial
    /// entrance-pupil plane.
    #[default]
    Paraxial,
    /// Solved by Newton iteration so that the real ray meets the stop at
    /// (px, py) x the stop radius (wide-angle and fisheye lenses).
    Real,
    /// Paraxial where that is good enough, real where it is not: real when
    /// the paraxial chief ray misses the stop's centre by more than
    /// [`AUTO_TOLERANCE`] of the stop radius, or a paraxial rim ray does not
    /// reach the stop surface. Resolved once per field by the launcher.
    Auto,
}

/// How far (a fraction of the stop radius) the paraxial chief ray may miss
/// the stop's centre before [`Aim::Auto`] aims real rays.
pub const AUTO_TOLERANCE: f64 = 0.05;

/// Launches rays of one field into a prescription.
#[derive(Debug, Clone)]
pub struct Launcher {
    field: Field,
    aim: Aim,
    first: FirstOrder,
    to_stop: Tracer,
    stop_radius: f64,
    z_start: f64,
    /// For an angle field: the direction as computed, its unit vector, and
    /// the offset from the entrance-pupil point back to the start plane
    /// (made once, not per ray).
    beam: Option<Beam>,
    /// Whether the aiming was asked as [`Aim::Auto`] (then `aim` holds what
    /// it resolved to for this field).
    auto: bool,
    /// The real chief ray's entrance-pupil point, found once for the field
    /// when a real aim first needs it ([`Self::real_chief`]).
    chief: std::sync::OnceLock<Result<DVec2, String>>,
    /// A nearby field's real chief-ray point, where the search for this
    /// field's starts when Newton from the axis fails
    /// ([`Self::at_nearby_field`]).
    chief_hint: Option<DVec2>,
}

/// A collimated beam's direction, kept with its launcher.
#[derive(Debug, Clone, Copy)]
struct Beam {
    unit: Option<DVec3>,
    back: DVec3,
}

impl Beam {
    fn of(field: Field, z_ep: f64, z_start: f64) -> Option<Beam> {
        let d = match field {
            Field::Angle(deg) => {
                let t = deg.to_radians();
                DVec3::new(0.0, t.sin(), t.cos())
            }
            Field::Angles { x_deg, y_deg } => DVec3::new(x_deg.to_radians().tan(), y_deg.to_radians().tan(), 1.0),
            Field::Height { .. } | Field::Point { .. } => return None,
        };
        Some(Beam { unit: d.try_normalize(), back: d * ((z_ep - z_start) / d.z) })
    }
}

/// Newton iterations allowed per aimed ray.
const NEWTON_STEPS: usize = 60;

impl Launcher {
    /// Prepares a launcher, computing the first-order data. Errors for an
    /// angle of 90 degrees or more, or a non-positive object distance.
    pub fn new(p: &Prescription, field: Field, aim: Aim) -> Result<Self, OpticsError> {
        Self::with_first(p, &FirstOrder::of(p)?, field, aim)
    }

    /// Prepares a launcher from first-order data already computed (a
    /// command computes them once).
    pub fn with_first(p: &Prescription, first: &FirstOrder, field: Field, aim: Aim) -> Result<Self, OpticsError> {
        check_field(field)?;
        let z_start = first.entrance_pupil.z.min(0.0) - 1.0;
        let l = Launcher {
            field,
            aim,
            first: *first,
            to_stop: Tracer::to_stop_unclipped(p),
            stop_radius: p.stop_semi_diameter(),
            z_start,
            beam: Beam::of(field, first.entrance_pupil.z, z_start),
            auto: false,
            chief: std::sync::OnceLock::new(),
            chief_hint: None,
        };
        Ok(l.resolved())
    }

    /// The same launcher for another field (the first-order data and the
    /// to-stop tracer are kept).
    pub fn at_field(&self, field: Field) -> Result<Self, OpticsError> {
        check_field(field)?;
        let l = Launcher {
            field,
            aim: if self.auto { Aim::Auto } else { self.aim },
            beam: Beam::of(field, self.first.entrance_pupil.z, self.z_start),
            chief: std::sync::OnceLock::new(),
            chief_hint: None,
            ..self.clone()
        };
        Ok(l.resolved())
    }

    /// [`Self::at_field`] for a field near this one: where this launcher has
    /// found its real chief ray, the new one's search starts from it before
    /// it walks out from the axis (a continuation of 64 Newton runs for a
    /// wide-angle lens's large fields). The chief ray found is the same to
    /// within Newton's tolerance.
    pub fn at_nearby_field(&self, field: Field) -> Result<Self, OpticsError> {
        let mut l = self.at_field(field)?;
        l.chief_hint = self.chief.get().and_then(|c| c.as_ref().ok()).copied();
        Ok(l)
    }

    /// Resolves [`Aim::Auto`] for this launcher's field: paraxial when the
    /// paraxial chief ray meets the stop within [`AUTO_TOLERANCE`] of its
    /// radius from the centre and the four rim rays reach the stop surface,
    /// real otherwise.
    fn resolved(mut self) -> Self {
        if self.aim != Aim::Auto {
            self.auto = false;
            return self;
        }
        self.auto = true;
        let r_ep = self.first.entrance_pupil.diameter / 2.0;
        let hit = |px: f64, py: f64| self.stop_hit(self.field, DVec2::new(px, py) * r_ep);
        let chief_ok = hit(0.0, 0.0).is_some_and(|h| h.length() <= AUTO_TOLERANCE * self.stop_radius);
        let rims_ok = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)].iter().all(|&(x, y)| hit(x, y).is_some());
        self.aim = if chief_ok && rims_ok { Aim::Paraxial } else { Aim::Real };
        self
    }

    /// How rays are aimed for this field ([`Aim::Auto`] resolved).
    pub fn aim(&self) -> Aim {
        self.aim
    }

    /// The field.
    pub fn field(&self) -> Field {
        self.field
    }

    /// The field's angle, degrees from the axis: the angle itself, or for
    /// an object point the angle of its chief ray to the paraxial entrance
    /// pupil (how a design file's field angles name finite-object fields).
    pub fn field_angle_deg(&self) -> f64 {
        self.field.angle_deg(self.first.entrance_pupil.z)
    }

    /// The prescription's vignetting factors for this field
    /// ([`Prescription::vignetting_at`] at its angle). The factors belong to
    /// design fields along y: a field with an x component is refused when
    /// `p` has any.
    pub fn vignetting(&self, p: &Prescription) -> Result<crate::model::VignettingFactors, OpticsError> {
        let v = p.vignetting_at(self.field_angle_deg());
        if self.field.has_x() && p.vignetting_factors().iter().any(|v| !v.is_none()) {
            return Err(OpticsError::YFieldOnly {
                what: "the prescription's vignetting factors",
                field: self.field.describe(),
            });
        }
        Ok(v)
    }

    /// First-order data of the prescription.
    pub fn first_order(&self) -> &FirstOrder {
        &self.first
    }

    /// The ray through the entrance-pupil plane at `e` (mm, x and y).
    pub(crate) fn ray_through(&self, e: DVec2) -> Option<Ray> {
        self.ray_through_at(self.field, e)
    }

    /// The ray of `field` through the entrance-pupil plane at `e`.
    fn ray_through_at(&self, field: Field, e: DVec2) -> Option<Ray> {
        let z_ep = self.first.entrance_pupil.z;
        let target = DVec3::new(e.x, e.y, z_ep);
        let object = |object_distance: f64, x: f64, y: f64| {
            let o = DVec3::new(x, y, -object_distance);
            Ray::new(o, target - o)
        };
        match field {
            Field::Angle(_) | Field::Angles { .. } => {
                // the launcher's own field: the beam made once (same bits)
                let beam = match self.beam {
                    Some(b) if field == self.field => b,
                    _ => Beam::of(field, z_ep, self.z_start)?,
                };
                let origin = target - beam.back;
                origin.is_finite().then_some(Ray { origin, direction: beam.unit? })
            }
            Field::Height { object_distance, height } => object(object_distance, 0.0, height),
            Field::Point { object_distance, x, y } => object(object_distance, x, y),
        }
    }

    /// The object-space ray for normalised pupil coordinates (px, py).
    /// Paraxial aiming never fails; real aiming reports non-convergence.
    pub fn ray(&self, px: f64, py: f64) -> Result<Ray, OpticsError> {
        let guess = self.paraxial_aim(px, py);
        let e = match self.aim {
            Aim::Paraxial => guess,
            Aim::Real | Aim::Auto => self.aim_real(px, py, guess)?,
        };
        self.ray_from_pupil(px, py, e)
    }

    /// The paraxially aimed ray of normalised pupil point (px, py) (what
    /// [`Self::ray`] gives under [`Aim::Paraxial`], to the bit), `None`
    /// where it cannot be formed: the batch launch's path, free of the
    /// error type's size.
    #[inline]
    pub(crate) fn paraxial_ray(&self, px: f64, py: f64) -> Option<Ray> {
        self.ray_through(self.paraxial_aim(px, py))
    }

    /// The object-space ray of pupil point (px, py) through the
    /// entrance-pupil point `e` its aiming found for it.
    pub(crate) fn ray_from_pupil(&self, px: f64, py: f64, e: DVec2) -> Result<Ray, OpticsError> {
        self.ray_through(e).ok_or_else(|| OpticsError::AimingFailed {
            px,
            py,
            field: self.field.describe(),
            why: "the ray cannot be formed (non-finite coordinates)".into(),
        })
    }

    /// Where the ray of `field` through EP point `e` meets the stop (no
    /// clipping).
    fn stop_hit(&self, field: Field, e: DVec2) -> Option<DVec2> {
        let r = self.ray_through_at(field, e)?;
        match self.to_stop.trace(r) {
            Outcome::Reached { ray, .. } => Some(ray.origin.truncate()),
            _ => None,
        }
    }

    /// Newton iteration on the entrance-pupil point so the real ray meets
    /// the stop at (px, py) x stop radius. Starts from the paraxial aim; where
    /// that ray cannot reach the stop (large fields of wide-angle lenses),
    /// continues from the real chief ray outward over the pupil, and the
    /// chief ray itself from the axis outward over the field.
    fn aim_real(&self, px: f64, py: f64, guess: DVec2) -> Result<DVec2, OpticsError> {
        let target = DVec2::new(px, py) * self.stop_radius;
        if let Ok(e) = self.newton(self.field, target, guess) {
            return Ok(e);
        }
        let chief = self.real_chief().map_err(|why| self.aim_error(px, py, why))?;
        if let Ok(done) = self.newton(self.field, target, chief) {
            return Ok(done);
        }
        self.continue_from_chief(px, py, chief)
    }

    /// The last resort of real aiming: from the chief ray's entrance-pupil
    /// point `chief` outward over the pupil to (px, py) in 16 steps, each
    /// solved by Newton from the last.
    fn continue_from_chief(&self, px: f64, py: f64, chief: DVec2) -> Result<DVec2, OpticsError> {
        let target = DVec2::new(px, py) * self.stop_radius;
        let steps = 16;
        let mut e = chief;
        for k in 1..=steps {
            let t = target * (k as f64 / steps as f64);
            e = self.newton(self.field, t, e).map_err(|why| self.aim_error(px, py, why))?;
        }
        Ok(e)
    }

    /// The real chief ray's entrance-pupil point, by continuation in field
    /// from the axis (where the paraxial aim is exact to first order);
    /// found once per launcher (a field's every real-aimed ray may start
    /// from it).
    fn real_chief(&self) -> Result<DVec2, String> {
        self.chief.get_or_init(|| self.find_real_chief()).clone()
    }

    /// [`Self::real_chief`] computed.
    fn find_real_chief(&self) -> Result<DVec2, String> {
        if let Ok(e) = self.newton(self.field, DVec2::ZERO, DVec2::ZERO) {
            return Ok(e);
        }
        if let Some(Ok(e)) = self.chief_hint.map(|h| self.newton(self.field, DVec2::ZERO, h)) {
            return Ok(e);
        }
        let steps = 64;
        let mut e = DVec2::ZERO;
        for k in 1..=steps {
            let field = self.field.scaled(k as f64 / steps as f64);
            e = self.newton(field, DVec2::ZERO, e)?;
        }
        Ok(e)
    }

    /// The entrance-pupil points of many pupil points at once, as
    /// [`Self::ray`] aims each (real aiming): Newton's iterations from the
    /// paraxial aims in lock step, each round's rays traced to the stop as
    /// one batch (the batch tracer gives the one-ray tracer's bits, and each
    /// point's iteration is the one [`Self::newton`] runs, so the points are
    /// those a point at a time gives); the points that fail go on from the
    /// field's real chief ray, again together, and any still failing
    /// through [`Self::aim_real`]'s continuation alone
    /// ([`Self::continue_from_chief`]).
    pub(crate) fn aim_many(&self, points: &[(f64, f64)]) -> Vec<Result<DVec2, OpticsError>> {
        let guesses: Vec<DVec2> = points.iter().map(|&(x, y)| self.paraxial_aim(x, y)).collect();
        self.aim_many_from(points, &guesses)
    }

    /// The paraxial aim of pupil point (px, py): its point on the paraxial
    /// entrance pupil, mm.
    pub(crate) fn paraxial_aim(&self, px: f64, py: f64) -> DVec2 {
        DVec2::new(px, py) * (self.first.entrance_pupil.diameter / 2.0)
    }

    /// [`Self::aim_many`] with each point's Newton run starting from
    /// `starts` (entrance-pupil points, mm) instead of its paraxial aim: a
    /// start near the answer (interpolated from aimed neighbours) takes
    /// fewer steps. The answers agree with `aim_many`'s to within Newton's
    /// tolerance.
    pub(crate) fn aim_many_from(&self, points: &[(f64, f64)], starts: &[DVec2]) -> Vec<Result<DVec2, OpticsError>> {
        let targets: Vec<DVec2> = points.iter().map(|&(x, y)| DVec2::new(x, y) * self.stop_radius).collect();
        // every point's Newton run from its start
        let mut out: Vec<Option<Result<DVec2, OpticsError>>> =
            self.newton_many(&targets, starts).into_iter().map(|r| r.map(Ok)).collect();
        let failed: Vec<usize> = (0..points.len()).filter(|&i| out[i].is_none()).collect();
        if failed.is_empty() {
            return out.into_iter().flatten().collect();
        }
        let chief = match self.real_chief() {
            Ok(chief) => chief,
            Err(why) => {
                for &i in &failed {
                    out[i] = Some(Err(self.aim_error(points[i].0, points[i].1, why.clone())));
                }
                return out.into_iter().flatten().collect();
            }
        };
        let t: Vec<DVec2> = failed.iter().map(|&i| targets[i]).collect();
        for (&i, r) in failed.iter().zip(self.newton_many(&t, &vec![chief; failed.len()])) {
            let (px, py) = points[i];
            out[i] = Some(r.map_or_else(|| self.continue_from_chief(px, py, chief), Ok));
        }
        out.into_iter().flatten().collect()
    }

    /// Where the rays of this field through the entrance-pupil points `es`
    /// meet the stop (no clipping), traced as one batch: as
    /// [`Self::stop_hit`] gives each.
    fn stop_hits(&self, es: &[DVec2]) -> Vec<Option<DVec2>> {
        thread_local! {
            /// Each thread's batch between calls: Newton's lock step calls
            /// this a few dozen times a field with small batches, whose
            /// eight arrays cost more to allocate than to trace.
            static BATCH: std::cell::RefCell<crate::trace::RayBatch> =
                std::cell::RefCell::new(crate::trace::RayBatch::with_capacity(0));
        }
        BATCH.with_borrow_mut(|batch| {
            batch.clear();
            for &e in es {
                match self.ray_through_at(self.field, e) {
                    Some(r) => batch.push(r),
                    None => batch.push_skipped(),
                }
            }
            self.to_stop.trace_soa(batch);
            (0..es.len()).map(|i| (batch.status[i] == 0).then(|| DVec2::new(batch.x[i], batch.y[i]))).collect()
        })
    }

    /// [`Self::newton`] for many targets and starts at once, in lock step:
    /// each point's iteration as `newton` runs it (the same steps, damping
    /// and ends), each round's probe and candidate rays traced together.
    /// `None` where `newton` would fail.
    fn newton_many(&self, targets: &[DVec2], starts: &[DVec2]) -> Vec<Option<DVec2>> {
        let (tol, h) = self.newton_scales(self.field);
        let n = targets.len();
        let mut e: Vec<DVec2> = starts.to_vec();
        let mut f = vec![DVec2::ZERO; n];
        let mut out: Vec<Option<DVec2>> = vec![None; n];
        // the points still iterating
        let mut live: Vec<usize> = Vec::with_capacity(n);
        for (i, hit) in self.stop_hits(&e).into_iter().enumerate() {
            if let Some(hit) = hit {
                f[i] = hit - targets[i];
                live.push(i);
            }
        }
        for _ in 0..NEWTON_STEPS {
            live.retain(|&i| {
                let done = f[i].length() <= tol;
                if done {
                    out[i] = Some(e[i]);
                }
                !done
            });
            if live.is_empty() {
                return out;
            }
            let probes: Vec<DVec2> =
                live.iter().flat_map(|&i| [e[i] + DVec2::new(h, 0.0), e[i] + DVec2::new(0.0, h)]).collect();
            let hits = self.stop_hits(&probes);
            // each live point's Newton step, or its end (a probe that
            // misses, a singular Jacobian: `newton` fails)
            let mut search: Vec<(usize, DVec2, f64)> = Vec::with_capacity(live.len());
            for (k, &i) in live.iter().enumerate() {
                let (Some(hx), Some(hy)) = (hits[2 * k], hits[2 * k + 1]) else { continue };
                if let Some(d) = newton_step(f[i], hx - targets[i], hy - targets[i], h) {
                    search.push((i, d, 1.0));
                }
            }
            // the damped steps: halve until the ray exists and the residual
            // drops, all the points' candidates traced together
            live.clear();
            while !search.is_empty() {
                let cands: Vec<DVec2> = search.iter().map(|&(i, d, step)| e[i] + d * step).collect();
                let hits = self.stop_hits(&cands);
                let mut again = Vec::with_capacity(search.len());
                for ((i, d, step), (cand, hit)) in search.into_iter().zip(cands.into_iter().zip(hits)) {
                    if let Some(hit) = hit {
                        let fc = hit - targets[i];
                        if fc.length() < f[i].length() || fc.length() <= tol {
                            (e[i], f[i]) = (cand, fc);
                            live.push(i);
                            continue;
                        }
                    }
                    let step = step * 0.5;
                    if step < 1e-6 {
                        if f[i].length() <= tol * 1e3 {
                            out[i] = Some(e[i]);
                        }
                        continue;
                    }
                    again.push((i, d, step));
                }
                search = again;
            }
            live.sort_unstable();
        }
        for i in live {
            if f[i].length() <= tol * 1e3 {
                out[i] = Some(e[i]);
            }
        }
        out
    }

    fn aim_error(&self, px: f64, py: f64, why: String) -> OpticsError {
        OpticsError::AimingFailed { px, py, field: self.field.describe(), why }
    }

    /// Newton's tolerance on the miss at the stop and its finite-difference
    /// step for `field`, mm.
    fn newton_scales(&self, field: Field) -> (f64, f64) {
        let scale = self.stop_radius.max(self.first.entrance_pupil.diameter / 2.0);
        // a far object point's own rounding moves its ray at the stop by
        // about eps times its distance: no aim can do better
        let floor = match field {
            Field::Height { object_distance, height } => 8.0 * f64::EPSILON * object_distance.hypot(height),
            Field::Point { object_distance, x, y } => 8.0 * f64::EPSILON * object_distance.hypot(x.hypot(y)),
            Field::Angle(_) | Field::Angles { .. } => 0.0,
        };
        ((1e-12 * scale.max(1.0)).max(floor), 1e-7 * scale)
    }

    fn newton(&self, field: Field, target: DVec2, start: DVec2) -> Result<DVec2, String> {
        let (tol, h) = self.newton_scales(field);
        let mut e = start;
        let mut f = self.stop_hit(field, e).ok_or("the starting ray misses a surface before the stop")? - target;
        for _ in 0..NEWTON_STEPS {
            if f.length() <= tol {
                return Ok(e);
            }
            let fx = self.stop_hit(field, e + DVec2::new(h, 0.0)).ok_or("a probe ray misses")? - target;
            let fy = self.stop_hit(field, e + DVec2::new(0.0, h)).ok_or("a probe ray misses")? - target;
            let d =
                newton_step(f, fx, fy, h).ok_or("the stop position does not depend on the aim (singular Jacobian)")?;
            // damped step: halve until the ray exists and the residual drops
            let mut step = 1.0;
            loop {
                let cand = e + d * step;
                if let Some(hit) = self.stop_hit(field, cand) {
                    let fc = hit - target;
                    if fc.length() < f.length() || fc.length() <= tol {
                        e = cand;
                        f = fc;
                        break;
                    }
                }
                step *= 0.5;
                if step < 1e-6 {
                    // at the rounding floor of the ray itself (an object far
                    // away: its point's last bits move the ray at the stop
                    // by more than the tolerance) the miss cannot shrink;
                    // accept it as the iterations' end does
                    if f.length() <= tol * 1e3 {
                        return Ok(e);
                    }
                    return Err(format!("no step reduces the miss of {:.3e} mm at the stop", f.length()));
                }
            }
        }
        if f.length() <= tol * 1e3 {
            return Ok(e);
        }
        Err(format!("{NEWTON_STEPS} iterations left a miss of {:.3e} mm at the stop", f.length()))
    }

    /// z (from the first vertex) of the paraxial image plane of this field's
    /// object.
    pub fn paraxial_image_z(&self, p: &Prescription) -> Result<f64, OpticsError> {
        let img = imaging(p, &self.first, self.field.object())?;
        Ok(p.last_vertex_z() + img.image_distance)
    }
}

/// Newton's step d solving J d = -f, J the forward differences of the miss
/// `f` at the stop to `fx` and `fy` (the misses with the aim moved by `h`
/// in x and in y); `None` for a singular Jacobian.
fn newton_step(f: DVec2, fx: DVec2, fy: DVec2, h: f64) -> Option<DVec2> {
    let (j1, j2) = ((fx - f) / h, (fy - f) / h);
    let det = j1.x * j2.y - j2.x * j1.y;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(DVec2::new(-(j2.y * f.x - j2.x * f.y) / det, -(-j1.y * f.x + j1.x * f.y) / det))
}
