//! Ray fans: transverse ray error against pupil coordinate, tangential
//! (y error against py) and sagittal (x error against px), relative to the
//! chief ray, on an image plane.

use super::launch::{Aim, Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::trace::ray::Outcome;
use crate::trace::Tracer;
use serde::Serialize;

/// One point of the tangential fan. `x`, `y`, `ey` are `None` when the ray
/// is vignetted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TangentialPoint {
    /// Normalised pupil y (px = 0).
    pub py: f64,
    /// Image-plane x, mm.
    pub x: Option<f64>,
    /// Image-plane y, mm.
    pub y: Option<f64>,
    /// y minus the chief ray's y, mm.
    pub ey: Option<f64>,
}

/// One point of the sagittal fan (py = 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SagittalPoint {
    /// Normalised pupil x.
    pub px: f64,
    /// Image-plane x, mm.
    pub x: Option<f64>,
    /// Image-plane y, mm.
    pub y: Option<f64>,
    /// x minus the chief ray's x, mm.
    pub ex: Option<f64>,
}

/// A ray fan at one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RayFan {
    /// Field angle, degrees (object at infinity), or `None` for a finite object.
    pub field_deg: Option<f64>,
    /// z of the image plane used, mm from the first vertex.
    pub image_z: f64,
    /// Chief ray on the image plane, mm.
    pub chief: [f64; 2],
    /// Tangential fan, py from -1 to 1.
    pub tangential: Vec<TangentialPoint>,
    /// Sagittal fan, px from -1 to 1.
    pub sagittal: Vec<SagittalPoint>,
    /// Rays of both fans blocked by a clear aperture (including those of
    /// `aim_failures`).
    pub vignetted: usize,
    /// Rays real aiming could not place on the stop (no real ray reaches that
    /// stop point); they are reported as vignetted points.
    pub aim_failures: usize,
}

/// Where rays are evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ImagePlane {
    /// The paraxial image plane of the field's object.
    Paraxial,
    /// A film this many mm behind the last vertex.
    Film(f64),
}

impl ImagePlane {
    /// z from the first vertex of this plane for `launcher`'s object.
    pub fn z(&self, p: &Prescription, launcher: &Launcher) -> Result<f64, OpticsError> {
        match *self {
            ImagePlane::Paraxial => launcher.paraxial_image_z(p),
            ImagePlane::Film(d) if d.is_finite() => Ok(p.last_vertex_z() + d),
            ImagePlane::Film(d) => Err(OpticsError::BadInput {
                name: "film",
                value: d,
                expected: "a finite film distance in mm behind the last vertex",
            }),
        }
    }
}

/// `n` evenly spaced points on [-1, 1] (n odd includes 0; n = 1 is 0).
pub fn fan_coordinates(n: usize) -> Vec<f64> {
    if n <= 1 {
        return vec![0.0];
    }
    (0..n).map(|i| -1.0 + 2.0 * i as f64 / (n - 1) as f64).collect()
}

/// Traces the tangential and sagittal fans of `n` points at `field`.
pub fn ray_fan(p: &Prescription, field: Field, n: usize, aim: Aim, plane: ImagePlane) -> Result<RayFan, OpticsError> {
    if n > 1_000_001 {
        return Err(OpticsError::BadInput {
            name: "points",
            value: n as f64,
            expected: "at most 1000001 points per fan",
        });
    }
    let launcher = Launcher::new(p, field, aim)?;
    let image_z = plane.z(p, &launcher)?;
    let tracer = Tracer::forward_to_film(p, image_z - p.last_vertex_z());
    let chief = trace_point(&launcher, &tracer, 0.0, 0.0)?
        .ok_or_else(|| OpticsError::ChiefRayLost { field: field.describe(), why: "vignetted or missed".into() })?;
    let mut vignetted = 0;
    let mut aim_failures = 0;
    let mut point = |px: f64, py: f64| -> Result<Option<[f64; 2]>, OpticsError> {
        match trace_point(&launcher, &tracer, px, py) {
            Err(OpticsError::AimingFailed { .. }) => {
                aim_failures += 1;
                Ok(None)
            }
            other => other,
        }
    };
    let mut tangential = Vec::with_capacity(n);
    let mut sagittal = Vec::with_capacity(n);
    for c in fan_coordinates(n) {
        match point(0.0, c)? {
            Some([x, y]) => tangential.push(TangentialPoint { py: c, x: Some(x), y: Some(y), ey: Some(y - chief[1]) }),
            None => {
                vignetted += 1;
                tangential.push(TangentialPoint { py: c, x: None, y: None, ey: None })
            }
        }
        match point(c, 0.0)? {
            Some([x, y]) => sagittal.push(SagittalPoint { px: c, x: Some(x), y: Some(y), ex: Some(x - chief[0]) }),
            None => {
                vignetted += 1;
                sagittal.push(SagittalPoint { px: c, x: None, y: None, ex: None })
            }
        }
    }
    let field_deg = match field {
        Field::Angle(d) => Some(d),
        Field::Height { .. } => None,
    };
    Ok(RayFan { field_deg, image_z, chief, tangential, sagittal, vignetted, aim_failures })
}

/// Traces pupil point (px, py); `None` when vignetted.
pub(crate) fn trace_point(
    launcher: &Launcher,
    tracer: &Tracer,
    px: f64,
    py: f64,
) -> Result<Option<[f64; 2]>, OpticsError> {
    let ray = launcher.ray(px, py)?;
    Ok(match tracer.trace(ray) {
        Outcome::Reached { ray, .. } => Some([ray.origin.x, ray.origin.y]),
        _ => None,
    })
}
