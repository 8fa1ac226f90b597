//! First-order properties of a prescription: focal lengths, cardinal points,
//! pupils and the paraxial f-number, from two paraxial rays.

use super::{trace, ZERO};
use crate::error::OpticsError;
use crate::model::Prescription;
use serde::Serialize;

/// A pupil: the paraxial image of the stop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pupil {
    /// Position, z in mm from the first vertex.
    pub z: f64,
    /// Diameter, mm.
    pub diameter: f64,
}

/// First-order properties of a prescription (object-independent).
///
/// Every `z` is in mm from the first vertex (+z toward the image); `bfl` is
/// from the last vertex to the rear focal point, `ffd` is the z of the front
/// focal point (signed; negative when it lies in front of the lens).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FirstOrder {
    /// Effective focal length 1/power, mm (negative for a diverging system).
    pub efl: f64,
    /// Back focal length: last vertex to the rear focal point, mm.
    pub bfl: f64,
    /// Front focal distance: z of the front focal point, mm (signed).
    pub ffd: f64,
    /// z of the front principal point, mm.
    pub front_principal_plane: f64,
    /// z of the rear principal point, mm.
    pub back_principal_plane: f64,
    /// Entrance pupil (image of the stop in object space).
    pub entrance_pupil: Pupil,
    /// Exit pupil (image of the stop in image space); `None` when the system
    /// is telecentric in image space (exit pupil at infinity).
    pub exit_pupil: Option<Pupil>,
    /// Paraxial f-number |EFL| / entrance-pupil diameter.
    pub f_number: f64,
    /// First vertex to film, mm.
    pub total_track: f64,
    /// Refractive index of image space.
    pub image_index: f64,
}

impl FirstOrder {
    /// Computes the first-order properties. Errors when the system is afocal
    /// or its entrance pupil is at infinity.
    pub fn of(p: &Prescription) -> Result<Self, OpticsError> {
        let s = p.surfaces();
        let n_img = p.image_index();
        // Ray A: parallel to the axis at unit height. Ray B: through the first
        // vertex with unit slope. Together they span every paraxial ray.
        let a = trace(p, 1.0, 0.0);
        let b = trace(p, 0.0, 1.0);
        let power = -n_img * a.last_u();
        let scale: f64 = s
            .iter()
            .map(|x| {
                x.vertex_curvature().abs() * (x.ior - 1.0).abs().max(1.0) + x.paraxial.map_or(0.0, |f| 1.0 / f.abs())
            })
            .sum::<f64>();
        if power == 0.0 || power.abs() <= ZERO * scale.max(f64::MIN_POSITIVE) {
            return Err(OpticsError::Afocal);
        }
        let efl = 1.0 / power;
        let z_last = p.last_vertex_z();
        let bfl = -a.last_y() / a.last_u();
        // Front focal point: the ray that leaves parallel. Combination
        // A*k + B has u_last = 0 => k = -uB/uA; it crosses the axis in object
        // space at z = -y1/u0 = -k.
        let ffd = b.last_u() / a.last_u();
        let rear_focal = z_last + bfl;
        let back_principal_plane = rear_focal - n_img * efl;
        let front_principal_plane = ffd + efl;
        // a power so small (a radius near 1e308 mm) that the focal points
        // lie beyond the range of f64: afocal for every purpose
        if ![efl, bfl, ffd, back_principal_plane, front_principal_plane].iter().all(|v| v.is_finite()) {
            return Err(OpticsError::Afocal);
        }

        let st = p.stop_index();
        let (ya_s, yb_s) = (a.y[st], b.y[st]);
        let stop_sd = p.stop_semi_diameter();
        if ya_s == 0.0 || ya_s.abs() <= ZERO * yb_s.abs() {
            return Err(OpticsError::PupilAtInfinity { which: "entrance" });
        }
        // Chief ray: k*A + B with zero height at the stop.
        let k = -yb_s / ya_s;
        let entrance_pupil = Pupil { z: -k, diameter: 2.0 * stop_sd / ya_s.abs() };
        let chief_y = k * a.last_y() + b.last_y();
        let chief_u = k * a.last_u() + b.last_u();
        let exit_pupil = if chief_u == 0.0 || chief_u.abs() <= ZERO * (chief_y.abs() * power.abs()) {
            None
        } else {
            let t = -chief_y / chief_u;
            // Marginal ray for an object at infinity: A scaled to the EP radius.
            let r_ep = entrance_pupil.diameter / 2.0;
            let h = r_ep * (a.last_y() + a.last_u() * t);
            Some(Pupil { z: z_last + t, diameter: 2.0 * h.abs() })
        };
        Ok(FirstOrder {
            efl,
            bfl,
            ffd,
            front_principal_plane,
            back_principal_plane,
            entrance_pupil,
            exit_pupil,
            f_number: efl.abs() / entrance_pupil.diameter,
            total_track: p.total_track(),
            image_index: n_img,
        })
    }
}
