//! Paraxial focus: the film distance that images an object, the object in
//! focus on a film, and the film distance that focuses a plane a given
//! distance in front of the film (what a camera's focus ring sets). The
//! real-ray best focus beside the paraxial one is an analysis
//! ([`crate::analysis::focus`]).

use super::{imaging, object_in_focus, FirstOrder, ObjectDistance};
use crate::error::OpticsError;
use crate::model::Prescription;

/// Largest image distance accepted, in focal lengths: an object so close to
/// the front focal plane that its image lies farther away (a magnification
/// over a million) has its image at infinity for every purpose.
pub const MAX_IMAGE_DISTANCE_EFL: f64 = 1e6;

/// The paraxial film distance (last vertex to image, mm) that focuses an
/// object. Errors at (or within a millionth of a focal length of) the front
/// focal plane, and where the image is not real (virtual, or in front of
/// the last vertex).
///
/// ```
/// use lens::{Prescription, paraxial::{ObjectDistance, film_distance}};
/// let p = Prescription::from_json_str(r#"{"surfaces": [
///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
/// let far = film_distance(&p, ObjectDistance::Infinity).unwrap();
/// let near = film_distance(&p, ObjectDistance::Finite(1000.0)).unwrap();
/// assert!(near > far); // nearer objects focus farther back
/// ```
pub fn film_distance(p: &Prescription, object: ObjectDistance) -> Result<f64, OpticsError> {
    film_distance_with(p, &FirstOrder::of(p)?, object)
}

/// [`film_distance`] with the first-order data already computed.
pub fn film_distance_with(p: &Prescription, first: &FirstOrder, object: ObjectDistance) -> Result<f64, OpticsError> {
    let img = imaging(p, first, object)?;
    let d = match object {
        ObjectDistance::Infinity => None,
        ObjectDistance::Finite(d) => Some(d),
    };
    if img.image_distance.abs() > MAX_IMAGE_DISTANCE_EFL * first.efl.abs() {
        return Err(OpticsError::ImageAtInfinity { object_distance: d.unwrap_or(f64::INFINITY), ffd: first.ffd });
    }
    if img.image_distance > 0.0 {
        Ok(img.image_distance)
    } else {
        Err(OpticsError::NoRealImage {
            object_distance: d,
            image_distance: img.image_distance,
            ffd: first.ffd,
            efl: first.efl,
        })
    }
}

/// The object in focus on a film `film_distance` mm behind the last vertex
/// (the inverse of [`film_distance`]).
pub fn object_distance_in_focus(p: &Prescription, film_distance: f64) -> Result<ObjectDistance, OpticsError> {
    let first = FirstOrder::of(p)?;
    object_in_focus(p, &first, film_distance)
}

/// The film distance (mm behind the last vertex) that focuses the plane
/// `distance` mm in front of the film, as a camera's focus scale measures
/// (object distance = `distance` - the lens's length - the film distance).
/// Solved by fixed-point iteration on the exact paraxial focus, from the
/// film distance for infinity. Errors when the plane is inside the lens or
/// nearer than the lens can focus.
///
/// ```
/// use lens::{Prescription, paraxial::{film_for_focus_from_film, film_distance, ObjectDistance}};
/// let p = Prescription::from_json_str(r#"{"surfaces": [
///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
/// let film = film_for_focus_from_film(&p, 2000.0).unwrap();
/// let object = 2000.0 - 3.6 - film;
/// assert!((film_distance(&p, ObjectDistance::Finite(object)).unwrap() - film).abs() < 1e-9);
/// ```
pub fn film_for_focus_from_film(p: &Prescription, distance: f64) -> Result<f64, OpticsError> {
    if !(distance.is_finite() && distance > 0.0) {
        return Err(OpticsError::BadInput {
            name: "focus distance",
            value: distance,
            expected: "a positive, finite distance in mm in front of the film",
        });
    }
    let first = FirstOrder::of(p)?;
    let z_last = p.last_vertex_z();
    let mut film = film_distance_with(p, &first, ObjectDistance::Infinity)?;
    for _ in 0..100 {
        let object = distance - z_last - film;
        if object <= 0.0 {
            return Err(OpticsError::FocusTooNear { distance, lens_length: z_last + film });
        }
        let next = film_distance_with(p, &first, ObjectDistance::Finite(object))?;
        if (next - film).abs() <= 1e-12 * film.abs().max(1.0) {
            return Ok(next);
        }
        film = next;
    }
    // the iteration contracts while the object is farther than about 4 f;
    // nearer, the plane cannot be focused from this distance
    Err(OpticsError::FocusTooNear { distance, lens_length: z_last + film })
}

/// The shift of `p`'s focus group (mm toward the image,
/// [`Prescription::with_focus_group_shift`]) that brings the image where
/// `film_at` finds it onto `p`'s own film (its last thickness, which
/// stays): the secant method from no shift, to 1e-12 mm. `film_at` gives
/// the film distance (mm behind the last vertex) at which a moved lens
/// images the object: the paraxial focus
/// ([`focus_group_shift_for_focus`]) or the real-ray best focus. Errors
/// when the lens names no focus group, when the group would close a gap,
/// or when no shift focuses.
pub fn focus_group_shift(
    p: &Prescription,
    mut film_at: impl FnMut(&Prescription) -> Result<f64, OpticsError>,
) -> Result<f64, OpticsError> {
    let film = p.film_distance();
    let mut miss = |shift: f64| -> Result<f64, OpticsError> { Ok(film_at(&p.with_focus_group_shift(shift)?)? - film) };
    let (mut x0, mut x1) = (0.0, 0.1);
    let (mut g0, mut g1) = (miss(x0)?, miss(x1)?);
    for _ in 0..100 {
        if g1.abs() <= 1e-12 * film.abs().max(1.0) {
            return Ok(x1);
        }
        if g1 == g0 {
            break;
        }
        let x2 = x1 - g1 * (x1 - x0) / (g1 - g0);
        (x0, g0) = (x1, g1);
        x1 = x2;
        g1 = miss(x1)?;
    }
    Err(OpticsError::BadInput {
        name: "focus group",
        value: x1,
        expected: "a focus group whose travel focuses the object (it does not converge: check focus_group)",
    })
}

/// [`focus_group_shift`] for the paraxial focus of a plane `distance` mm in
/// front of the film (the film and the lens's length stay, so the object
/// is `distance` - the first vertex to film distance in front of the lens).
pub fn focus_group_shift_for_focus(p: &Prescription, distance: f64) -> Result<f64, OpticsError> {
    let object = distance - p.total_track();
    if !(object > 0.0 && distance.is_finite()) {
        return Err(OpticsError::FocusTooNear { distance, lens_length: p.total_track() });
    }
    focus_group_shift(p, |q| film_distance(q, ObjectDistance::Finite(object)))
}
