//! Paraxial (first-order) optics by the y-nu trace: focal lengths, cardinal
//! points, pupils, f-numbers, conjugates.
//!
//! At surface i of curvature c between indices n and n':
//! power `phi = c (n' - n)`, refraction `n' u' = n u - y phi`, transfer
//! `y_next = y + t u'`. Angles `u` are slopes dy/dz (paraxial: tan = angle).
//! Object space is air (n = 1).

use crate::error::OpticsError;
use crate::prescription::Prescription;
use serde::Serialize;

/// Where the object is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjectDistance {
    /// Object at infinity (collimated light).
    Infinity,
    /// Object on the axis this many mm in front of the first vertex
    /// (at z = -distance); must be positive and finite.
    Finite(f64),
}

impl ObjectDistance {
    /// From a distance in mm: `f64::INFINITY` means infinity.
    pub fn from_mm(d: f64) -> Result<Self, OpticsError> {
        if d == f64::INFINITY {
            Ok(Self::Infinity)
        } else if d.is_finite() && d > 0.0 {
            Ok(Self::Finite(d))
        } else {
            Err(OpticsError::BadInput {
                name: "object_distance",
                value: d,
                expected: "a positive distance in mm in front of the first vertex (or infinity)",
            })
        }
    }
}

/// A paraxial ray traced through every surface.
#[derive(Debug, Clone, PartialEq)]
pub struct ParaxialRay {
    /// Height at each surface's vertex plane, mm.
    pub y: Vec<f64>,
    /// Slope after each surface (dy/dz in the medium behind it).
    pub u: Vec<f64>,
}

impl ParaxialRay {
    /// Height at the last surface, mm.
    pub fn last_y(&self) -> f64 {
        *self.y.last().unwrap_or(&0.0)
    }
    /// Slope in image space.
    pub fn last_u(&self) -> f64 {
        *self.u.last().unwrap_or(&0.0)
    }
}

/// Traces a paraxial ray that has height `y1` mm at the first vertex plane
/// and slope `u0` in object space.
pub fn trace(p: &Prescription, y1: f64, u0: f64) -> ParaxialRay {
    let s = p.surfaces();
    let mut y = Vec::with_capacity(s.len());
    let mut u_out = Vec::with_capacity(s.len());
    let (mut h, mut u) = (y1, u0);
    for (i, surf) in s.iter().enumerate() {
        if i > 0 {
            h += s[i - 1].thickness * u;
        }
        let n = p.index_before(i);
        let n2 = surf.ior;
        let phi = surf.curvature * (n2 - n);
        u = (n * u - h * phi) / n2;
        y.push(h);
        u_out.push(u);
    }
    ParaxialRay { y, u: u_out }
}

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

/// Relative threshold below which a quantity that should be non-zero is taken
/// as zero (power of an afocal system, image vergence of an object at the
/// front focal plane): 1e-12 of its natural scale.
const ZERO: f64 = 1e-12;

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
        let scale: f64 = s.iter().map(|x| x.curvature.abs() * (x.ior - 1.0).abs().max(1.0)).sum::<f64>();
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

/// Paraxial imaging of an on-axis object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Imaging {
    /// Image distance from the last vertex, mm (positive behind it).
    pub image_distance: f64,
    /// Lateral magnification (0 for an object at infinity; negative for an
    /// inverted real image).
    pub magnification: f64,
    /// Paraxial working f-number 1 / (2 n' |u'|) of the marginal ray through
    /// the edge of the entrance pupil.
    pub working_f_number: f64,
}

/// Images an on-axis object paraxially. Errors when the image is at infinity
/// (object at the front focal plane) or the object is at the entrance pupil.
pub fn imaging(p: &Prescription, first: &FirstOrder, object: ObjectDistance) -> Result<Imaging, OpticsError> {
    let n_img = p.image_index();
    // Axial ray: from the object point, unit height at the first vertex.
    let (u0, d) = match object {
        ObjectDistance::Infinity => (0.0, f64::INFINITY),
        ObjectDistance::Finite(d) => (1.0 / d, d),
    };
    let axial = trace(p, 1.0, u0);
    let (y, u) = (axial.last_y(), axial.last_u());
    // Image vergence n'u'/y against the power: an image farther than 1e12
    // focal lengths is an image at infinity.
    if u == 0.0 || (n_img * u).abs() <= ZERO * y.abs() / first.efl.abs() {
        return Err(OpticsError::ImageAtInfinity { object_distance: d, ffd: first.ffd });
    }
    let image_distance = -y / u;
    let magnification = match object {
        ObjectDistance::Infinity => 0.0,
        ObjectDistance::Finite(_) => u0 / (n_img * u),
    };
    // Marginal ray: from the axial object point through the entrance pupil's edge.
    let r_ep = first.entrance_pupil.diameter / 2.0;
    let (y1, um) = match object {
        ObjectDistance::Infinity => (r_ep, 0.0),
        ObjectDistance::Finite(d) => {
            let span = d + first.entrance_pupil.z;
            if span.abs() <= ZERO * d.abs().max(1.0) {
                return Err(OpticsError::BadInput {
                    name: "object_distance",
                    value: d,
                    expected: "an object that is not at the entrance pupil",
                });
            }
            let um = r_ep / span;
            (um * d, um)
        }
    };
    let marginal = trace(p, y1, um);
    let working_f_number = 1.0 / (2.0 * n_img * marginal.last_u().abs());
    Ok(Imaging { image_distance, magnification, working_f_number })
}

/// The object distance (mm in front of the first vertex) that is in focus on
/// a film `film_distance` mm behind the last vertex; `Infinity` when the film
/// is at the rear focal plane. Errors where no real object is in focus.
pub fn object_in_focus(
    p: &Prescription,
    first: &FirstOrder,
    film_distance: f64,
) -> Result<ObjectDistance, OpticsError> {
    if !film_distance.is_finite() {
        return Err(OpticsError::BadInput {
            name: "film_distance",
            value: film_distance,
            expected: "a finite distance in mm behind the last vertex",
        });
    }
    // Trace backward from the axial image point: by linearity combine the
    // rays A (parallel) and B (through the first vertex) into the one that
    // crosses the axis at the film: y_last + t u_last = 0.
    let a = trace(p, 1.0, 0.0);
    let b = trace(p, 0.0, 1.0);
    let fa = a.last_y() + film_distance * a.last_u();
    let fb = b.last_y() + film_distance * b.last_u();
    // k*A + B reaches the film axis point when k fa + fb = 0.
    // Its object-space line crosses the axis at z = -k; the object is at -z.
    // The object is farther than 1e12 focal lengths: at infinity.
    if fa == 0.0 || fa.abs() * first.efl.abs() <= ZERO * fb.abs() {
        return Ok(ObjectDistance::Infinity);
    }
    let d = -fb / fa;
    if !(d.is_finite() && d > 0.0) {
        return Err(OpticsError::NoRealObject { film_distance, bfl: first.bfl });
    }
    Ok(ObjectDistance::Finite(d))
}

/// Thick-lens (cardinal point) model of a prescription, for cameras that
/// need only first-order behaviour. Distances in mm, z from the first vertex.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ThickLens {
    /// Effective focal length, mm.
    pub efl: f64,
    /// z of the front principal plane, mm.
    pub front_principal_plane: f64,
    /// z of the rear principal plane, mm.
    pub back_principal_plane: f64,
    /// Index of image space.
    pub image_index: f64,
}

impl ThickLens {
    /// The model of `p`.
    pub fn of(p: &Prescription) -> Result<Self, OpticsError> {
        let f = FirstOrder::of(p)?;
        Ok(Self {
            efl: f.efl,
            front_principal_plane: f.front_principal_plane,
            back_principal_plane: f.back_principal_plane,
            image_index: f.image_index,
        })
    }

    /// z of the image of an axial point at z = `object_z` (< front principal
    /// plane), by the Gaussian lens equation n'/s' - 1/s = 1/f measured from
    /// the principal planes. Errors at the front focal plane.
    pub fn image_z(&self, object_z: f64) -> Result<f64, OpticsError> {
        let s = object_z - self.front_principal_plane; // negative for a real object
        let vergence = 1.0 / s + 1.0 / self.efl;
        if vergence == 0.0 || vergence.abs() <= ZERO / self.efl.abs() {
            return Err(OpticsError::ImageAtInfinity {
                object_distance: -object_z,
                ffd: self.front_principal_plane - self.efl,
            });
        }
        Ok(self.back_principal_plane + self.image_index / vergence)
    }
}
