//! The one ray-bundle primitive every analysis is built on: a
//! [`Launcher`] (first-order data and the to-stop tracer, computed once)
//! turns the pupil points of a field into a [`RayBatch`], the batch tracer
//! traces it, and each point's result is read back as a [`Landing`]. Fans,
//! spot diagrams, field curves, vignetting and the layout's rays all go
//! through here; the on-axis bundle of the circle of confusion and the
//! real-ray focus uses [`trace_rays`] on rays it builds itself.

use super::launch::Launcher;
use crate::error::OpticsError;
use crate::trace::{Outcome, Ray, RayBatch, Tracer};
use glam::DVec2;

/// How one pupil point's ray ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Landing {
    /// It reached the end of the tracer (the image plane): the ray there.
    Reached(Ray),
    /// It stopped inside the lens (missed, blocked, totally reflected).
    Stopped(Outcome),
    /// Real aiming found no ray that meets the stop at this point.
    AimFailed,
}

impl Landing {
    /// The ray on the image plane of a field's chief ray, or the error
    /// that says why the chief ray of `field` is lost.
    pub fn chief(&self, field: super::Field) -> Result<Ray, OpticsError> {
        match self {
            Landing::Reached(r) => Ok(*r),
            Landing::Stopped(o) => Err(OpticsError::ChiefRayLost { field: field.describe(), why: describe_outcome(o) }),
            Landing::AimFailed => {
                Err(OpticsError::ChiefRayLost { field: field.describe(), why: "real aiming found no chief ray".into() })
            }
        }
    }

    /// The ray on the image plane, if it got there.
    pub fn reached(&self) -> Option<Ray> {
        match self {
            Landing::Reached(r) => Some(*r),
            _ => None,
        }
    }
}

/// Status of a ray that real aiming could not form
/// ([`RayBatch::push_skipped`]'s): the tracer leaves it alone.
const AIM_FAILED: u64 = u64::MAX;

/// A traced bundle: the pupil points and how each ray ended.
#[derive(Debug, Clone)]
pub struct Bundle {
    /// Normalised pupil coordinates (px, py), in the order given.
    pub points: Vec<(f64, f64)>,
    /// Each point's result.
    pub landings: Vec<Landing>,
}

impl Bundle {
    /// Launches rays through `points` (normalised pupil coordinates) with
    /// `launcher` and traces them with `tracer` as one batch. Points that
    /// real aiming cannot place are [`Landing::AimFailed`]; other launch
    /// errors (a ray that cannot be formed) are returned.
    pub fn trace(launcher: &Launcher, tracer: &Tracer, points: Vec<(f64, f64)>) -> Result<Self, OpticsError> {
        let mut batch = RayBatch::with_capacity(points.len());
        launch(launcher, points.iter().copied(), &mut batch)?;
        let landings = trace_batch(tracer, &mut batch)?;
        Ok(Bundle { points, landings })
    }

    /// The rays that reached the image plane, with their pupil points.
    pub fn reached(&self) -> impl Iterator<Item = ((f64, f64), Ray)> + '_ {
        self.points.iter().zip(&self.landings).filter_map(|(p, l)| l.reached().map(|r| (*p, r)))
    }

    /// How many rays did not reach the image plane (aim failures included).
    pub fn vignetted(&self) -> usize {
        self.landings.iter().filter(|l| !matches!(l, Landing::Reached(_))).count()
    }

    /// How many points real aiming could not place.
    pub fn aim_failures(&self) -> usize {
        self.landings.iter().filter(|l| matches!(l, Landing::AimFailed)).count()
    }
}

/// Fills `batch` (cleared first) with the rays of `launcher` through
/// `points`; a point real aiming cannot place gets a placeholder ray the
/// tracer leaves alone. Returns how many such points there were.
pub fn launch(
    launcher: &Launcher,
    points: impl Iterator<Item = (f64, f64)>,
    batch: &mut RayBatch,
) -> Result<usize, OpticsError> {
    if launcher.aim() == super::launch::Aim::Real {
        // real aiming: every point's Newton iterations together
        let points: Vec<(f64, f64)> = points.collect();
        let starts: Vec<DVec2> = points.iter().map(|&(x, y)| launcher.paraxial_aim(x, y)).collect();
        let aims = launch_aimed(launcher, &points, &starts, batch)?;
        return Ok(aims.iter().filter(|e| e.is_none()).count());
    }
    batch.clear();
    let mut failed = 0;
    for (px, py) in points {
        match launcher.paraxial_ray(px, py) {
            Some(r) => batch.push(r),
            None => {
                batch.push_skipped();
                failed += 1;
            }
        }
    }
    Ok(failed)
}

/// Fills `batch` (cleared first) with the real-aimed rays of `launcher`
/// through `points`, each point's Newton run from its entrance-pupil point
/// in `starts` (mm; [`Launcher::paraxial_aim`]'s for [`launch`]); a point
/// aiming cannot place gets a placeholder ray the tracer leaves alone.
/// Returns each point's entrance-pupil point (`None` where it failed).
pub(crate) fn launch_aimed(
    launcher: &Launcher,
    points: &[(f64, f64)],
    starts: &[DVec2],
    batch: &mut RayBatch,
) -> Result<Vec<Option<DVec2>>, OpticsError> {
    batch.clear();
    let mut aims = Vec::with_capacity(points.len());
    for (&(px, py), e) in points.iter().zip(launcher.aim_many_from(points, starts)) {
        let aim = e.as_ref().ok().copied();
        let failed = push_launched(batch, e.and_then(|e| launcher.ray_from_pupil(px, py, e)))?;
        aims.push(aim.filter(|_| !failed));
    }
    Ok(aims)
}

/// Pushes a launched ray, or for a point aiming could not place a
/// placeholder the tracer leaves alone (`true`); other errors are returned.
fn push_launched(batch: &mut RayBatch, r: Result<Ray, OpticsError>) -> Result<bool, OpticsError> {
    match r {
        Ok(r) => batch.push(r),
        Err(OpticsError::AimingFailed { .. }) => {
            batch.push_skipped();
            return Ok(true);
        }
        Err(e) => return Err(e),
    }
    Ok(false)
}

/// How a ray stopped, in words for a message: the surface numbered from 1,
/// the point in mm.
pub fn describe_outcome(o: &Outcome) -> String {
    let at = |r: &Ray| format!("({:.4}, {:.4}, {:.4}) mm", r.origin.x, r.origin.y, r.origin.z);
    match o {
        Outcome::Reached { ray, .. } => format!("reached the image at {}", at(ray)),
        Outcome::Missed { surface, ray, .. } => format!("misses surface {} (leaving {})", surface + 1, at(ray)),
        Outcome::Blocked { surface, ray, .. } => {
            format!("is blocked by the clear aperture of surface {} at {}", surface + 1, at(ray))
        }
        Outcome::TotalInternalReflection { surface, ray, .. } => {
            format!("is totally reflected at surface {} at {}", surface + 1, at(ray))
        }
        Outcome::NotConverged { surface, ray, .. } => format!(
            "has no intersection found with aspheric surface {} (Newton's iteration did not converge; leaving {})",
            surface + 1,
            at(ray)
        ),
    }
}

/// Traces `rays` as one batch and returns how each ended.
pub fn trace_rays(tracer: &Tracer, rays: &[Ray]) -> Vec<Landing> {
    let mut batch = RayBatch::with_capacity(rays.len());
    for r in rays {
        batch.push(*r);
    }
    // no status is set by hand here, so every code decodes
    trace_batch(tracer, &mut batch).unwrap_or_default()
}

fn trace_batch(tracer: &Tracer, batch: &mut RayBatch) -> Result<Vec<Landing>, OpticsError> {
    tracer.trace_soa(batch);
    (0..batch.len())
        .map(|i| {
            Ok(match batch.status[i] {
                AIM_FAILED => Landing::AimFailed,
                _ => match tracer.outcome_of(batch, i)? {
                    Outcome::Reached { ray, .. } => Landing::Reached(ray),
                    o => Landing::Stopped(o),
                },
            })
        })
        .collect()
}
