//! Paraxial imaging of an on-axis object: image distance, magnification,
//! working f-number; the inverse (the object in focus for a film); and the
//! thick-lens model.

use super::{trace, FirstOrder, ObjectDistance, ZERO};
use crate::error::OpticsError;
use crate::model::Prescription;
use serde::Serialize;

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
