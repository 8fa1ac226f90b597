//! Cameras: a pinhole, a thin lens and a real lens prescription. Each maps a
//! film position (u, v in [0, 1], v down) and two aperture uniforms to a
//! scene ray and a weight (0 when the ray is blocked inside the lens).

pub mod aperture;
pub mod pupil;
pub mod real_lens;

use crate::geometry::Ray;
use aperture::Aperture;
use glam::DVec3;

/// Why a camera could not be built. The lens crate's error is kept as the
/// source.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// The look-at point equals the position.
    #[error("camera look_at equals position: move one of them")]
    LookAtPosition,
    /// The up direction is parallel to the viewing direction.
    #[error("camera up is parallel to the viewing direction: change up")]
    UpParallel,
    /// A sensor size that is not two positive lengths.
    #[error("sensor_mm = [{width}, {height}]: give two positive sizes in mm")]
    Sensor {
        /// Width, mm.
        width: f64,
        /// Height, mm.
        height: f64,
    },
    /// The lens cannot be focused or set up as asked.
    #[error(transparent)]
    Optics(#[from] lens::OpticsError),
    /// No ray from the film centre passes the lens.
    #[error("no ray from the film centre passes the lens: check the stop and clear apertures")]
    NoLight,
}

/// One camera sample: a film position (u, v in [0, 1], v down) and two
/// aperture uniforms in [0, 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSample {
    /// Film position (u, v).
    pub film: (f64, f64),
    /// Aperture uniforms.
    pub aperture: (f64, f64),
}

/// An orthonormal camera frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Position, m.
    pub origin: DVec3,
    /// Viewing direction.
    pub forward: DVec3,
    /// Image right.
    pub right: DVec3,
    /// Image up.
    pub up: DVec3,
}

impl Frame {
    /// From a position, a look-at point and an up hint. Errors when the
    /// directions are degenerate.
    pub fn look_at(position: DVec3, target: DVec3, up: DVec3) -> Result<Self, CameraError> {
        let forward = (target - position).try_normalize().ok_or(CameraError::LookAtPosition)?;
        let right = forward.cross(up).try_normalize().ok_or(CameraError::UpParallel)?;
        Ok(Frame { origin: position, forward, right, up: right.cross(forward) })
    }
}

/// A camera.
#[derive(Debug, Clone)]
pub enum Camera {
    /// Ideal pinhole.
    Pinhole {
        /// Frame.
        frame: Frame,
        /// tan(vertical fov / 2).
        tan_half: f64,
        /// Width / height.
        aspect: f64,
    },
    /// Cook-style thin lens.
    ThinLens {
        /// Frame (the lens centre).
        frame: Frame,
        /// tan(vertical fov / 2).
        tan_half: f64,
        /// Width / height.
        aspect: f64,
        /// Aperture radius, m.
        radius: f64,
        /// Distance to the plane in focus, m.
        focus: f64,
        /// Aperture shape.
        aperture: Aperture,
        /// Focal shortening at the rim (fraction).
        focus_shift: f64,
    },
    /// Real lens.
    Real(Box<real_lens::RealLensCamera>),
}

impl Camera {
    /// The camera ray through film position (u, v) with aperture sample
    /// `a`, and its weight.
    pub fn ray(&self, u: f64, v: f64, a: (f64, f64)) -> Option<(Ray, f64)> {
        match self {
            Camera::Pinhole { frame, tan_half, aspect } => {
                let d = pinhole_dir(frame, *tan_half, *aspect, u, v);
                Some((Ray { origin: frame.origin, dir: d }, 1.0))
            }
            Camera::ThinLens { frame, tan_half, aspect, radius, focus, aperture, focus_shift } => {
                let d = pinhole_dir(frame, *tan_half, *aspect, u, v);
                if *radius == 0.0 {
                    return Some((Ray { origin: frame.origin, dir: d }, 1.0));
                }
                let (ax, ay) = aperture.sample(a);
                let rho = (ax * ax + ay * ay).sqrt();
                // the study's trick: focus nearer for samples far from the centre
                let f = focus * (1.0 - focus_shift * rho);
                let p_focus = frame.origin + d * (f / d.dot(frame.forward));
                let o = frame.origin + frame.right * (ax * radius) + frame.up * (ay * radius);
                let dir = (p_focus - o).normalize();
                Some((Ray { origin: o, dir }, 1.0))
            }
            Camera::Real(c) => c.ray(u, v, a),
        }
    }

    /// The camera rays of a batch of samples, with their weights (`None`
    /// where the lens blocks the ray): a real lens traces them all as one
    /// batch through the lens crate's batch tracer.
    pub fn rays(&self, samples: &[CameraSample], out: &mut Vec<Option<(Ray, f64)>>) {
        match self {
            Camera::Real(c) => c.rays(samples, out),
            _ => {
                out.clear();
                out.extend(samples.iter().map(|s| self.ray(s.film.0, s.film.1, s.aperture)));
            }
        }
    }
}

/// The pinhole direction through film position (u, v).
fn pinhole_dir(f: &Frame, tan_half: f64, aspect: f64, u: f64, v: f64) -> DVec3 {
    let sx = (2.0 * u - 1.0) * tan_half * aspect;
    let sy = (1.0 - 2.0 * v) * tan_half;
    (f.forward + f.right * sx + f.up * sy).normalize()
}
