//! Cameras: a pinhole, a thin lens and a real lens prescription. Each maps a
//! film position (u, v in [0, 1], v down) and two aperture uniforms to a
//! scene ray and a weight (0 when the ray is blocked inside the lens).

pub mod aperture;
pub mod real_lens;

use crate::geometry::Ray;
use aperture::Aperture;
use glam::DVec3;

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
    pub fn look_at(position: DVec3, target: DVec3, up: DVec3) -> Result<Self, String> {
        let forward = (target - position).try_normalize().ok_or("camera look_at equals position: move one of them")?;
        let right =
            forward.cross(up).try_normalize().ok_or("camera up is parallel to the viewing direction: change up")?;
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
}

/// The pinhole direction through film position (u, v).
fn pinhole_dir(f: &Frame, tan_half: f64, aspect: f64, u: f64, v: f64) -> DVec3 {
    let sx = (2.0 * u - 1.0) * tan_half * aspect;
    let sy = (1.0 - 2.0 * v) * tan_half;
    (f.forward + f.right * sx + f.up * sy).normalize()
}
