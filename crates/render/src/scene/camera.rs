//! The scene file's camera built into a [`Camera`]: its pose, the thin
//! lens's focus, the real lens loaded, resized and focused. Errors name the
//! field. Also the camera in words, and the settings that are likely
//! mistakes (a focus beyond every object, a lens that does not cover the
//! film).

use super::format::*;
use super::{v3, FieldError, Given};
use crate::camera::aperture::Aperture;
use crate::camera::{real_lens::RealLensCamera, Camera, Frame, ThinGlass};
use glam::DVec3;
use lens::error::{exact, num};
use std::path::Path;

/// The thin lens's distance to the plane in focus and to the film, m, from
/// the distance `d` (m) measured from the film: with a focal length f,
/// object and image distances s + s' = d and 1/s + 1/s' = 1/f give
/// s = d (1 + r) / 2 and s' = 2f / (1 + r), r = sqrt(1 - 4f/d) (written so
/// that no distance up to f64's largest overflows or cancels). Without a
/// focal length the model has no film: s = d.
fn lens_to_focus(d: f64, focal_length_mm: Option<f64>) -> Result<(f64, Option<f64>), (String, FieldError)> {
    let Some(f_mm) = focal_length_mm else { return Ok((d, None)) };
    let f = f_mm * 1e-3;
    if !(f.is_finite() && f > 0.0) {
        return Err(("camera.focal_length_mm".into(), "must be a positive focal length in mm".into()));
    }
    if d < 4.0 * f {
        return Err((
            "camera.focus_distance".into(),
            format!(
                "{} m from the film: a {} mm thin lens cannot focus nearer than 4f = {} m",
                exact(d),
                exact(f_mm),
                num(4.0 * f)
            )
            .into(),
        ));
    }
    let r = (1.0 - 4.0 * f / d).max(0.0).sqrt();
    Ok((0.5 * d * (1.0 + r), Some(2.0 * f / (1.0 + r))))
}

/// The distance in focus a thin or real lens camera was given, or what to
/// give (a camera built after autofocus has it).
fn given_focus(c: &CameraSpec) -> Result<f64, (String, FieldError)> {
    c.focus_distance().ok_or_else(|| {
        ("camera.focus_distance".to_string(), "give focus_distance (m) or focus_on (a shape's name or a pixel)".into())
    })
}

/// A real lens camera's prescription as the scene asks for it: loaded,
/// its stop resized for `f_number` or `stop_semi_diameter`, not yet
/// focused.
pub(super) fn load_lens(c: &CameraSpec, dir: &Path, given: &Given) -> Result<lens::Prescription, (String, FieldError)> {
    let CameraSpec::Lens { prescription, f_number, stop_semi_diameter, coating, .. } = c else {
        return Err(("camera.type".into(), "not a real lens camera".into()));
    };
    let mut lens = match given.lens {
        Some(p) => p.clone(),
        None => lens::Prescription::load(dir.join(prescription))
            .map_err(|e| ("camera.prescription".to_string(), e.into()))?,
    };
    if let Some(n) = f_number {
        lens = lens::analysis::aperture::with_f_number(&lens, *n)
            .map_err(|e| ("camera.f_number".to_string(), e.into()))?;
    }
    if let Some(sd) = stop_semi_diameter {
        lens = lens.with_stop_semi_diameter(*sd).map_err(|e| ("camera.stop_semi_diameter".to_string(), e.into()))?;
    }
    if let Some(c) = coating {
        let c = c.coating().map_err(|e| ("camera.coating".to_string(), e.into()))?;
        lens = lens.with_coatings(Some(c));
    }
    Ok(lens)
}

/// How a real lens is focused when not paraxially on the camera's
/// `focus_distance`: autofocus's real-ray best focus.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RealFocus {
    /// The whole lens moved: the film this far behind the last vertex, mm.
    Film(f64),
    /// The prescription's focus group moved this far toward the image, mm
    /// (the film stays).
    Group(f64),
}

/// The camera of the scene file (a real lens's prescription as `given`, or
/// loaded from its file; its pupil bounds as `given`, or made). A real
/// lens is focused on `focus_distance` paraxially, by its focus group when
/// it names one (the film stays) or else as a whole (the film moves), or
/// as `real` says (autofocus's real-ray best focus).
pub(super) fn build_camera(
    c: &CameraSpec,
    film: &FilmSpec,
    dir: &Path,
    given: &Given,
    real: Option<RealFocus>,
) -> Result<Camera, (String, FieldError)> {
    let aspect = film.width as f64 / film.height as f64;
    let pose = |p: &Pose| -> Result<Frame, (String, FieldError)> {
        if ![p.position, p.look_at, p.up].iter().flatten().all(|x| x.is_finite()) {
            return Err(("camera".into(), "position, look_at and up must be finite".into()));
        }
        Frame::look_at(v3(p.position), v3(p.look_at), v3(p.up)).map_err(|e| ("camera.look_at".into(), e.into()))
    };
    let fov = |f: f64| -> Result<f64, (String, FieldError)> {
        if f.is_finite() && f > 0.0 && f < 180.0 {
            Ok((f.to_radians() / 2.0).tan())
        } else {
            Err(("camera.fov_deg".into(), format!("{}: a field of view between 0 and 180 degrees", exact(f)).into()))
        }
    };
    match c {
        CameraSpec::Pinhole { fov_deg, .. } => {
            Ok(Camera::Pinhole { frame: pose(&c.pose())?, tan_half: fov(*fov_deg)?, aspect })
        }
        CameraSpec::ThinLens {
            fov_deg,
            aperture,
            f_number,
            focal_length_mm,
            aperture_shape,
            focus_shift,
            glass,
            ..
        } => {
            let diameter = match (aperture, f_number, focal_length_mm) {
                (Some(a), None, _) => *a,
                (None, Some(n), Some(_)) if !(n.is_finite() && *n >= 0.5) => {
                    return Err((
                        "camera.f_number".into(),
                        format!("{}: give an f-number of 0.5 or more", exact(*n)).into(),
                    ))
                }
                (None, Some(n), Some(f)) => f / n * 1e-3,
                (None, None, _) => 0.0,
                _ => {
                    return Err((
                        "camera.aperture".into(),
                        "give either aperture (m) or f_number with focal_length_mm".into(),
                    ))
                }
            };
            if !(diameter.is_finite() && diameter >= 0.0) {
                return Err(("camera.aperture".into(), format!("{}: a diameter >= 0 m", exact(diameter)).into()));
            }
            let focus_distance = &given_focus(c)?;
            if !(focus_distance.is_finite() && *focus_distance > 0.0) {
                return Err(("camera.focus_distance".into(), "must be a positive distance in m".into()));
            }
            if !(focus_shift.is_finite() && (0.0..1.0).contains(focus_shift)) {
                return Err(("camera.focus_shift".into(), "must be in [0, 1)".into()));
            }
            let (focus, film_distance) = lens_to_focus(*focus_distance, *focal_length_mm)?;
            let glass = match (glass, focal_length_mm) {
                (None, _) => None,
                (Some(_), None) => {
                    return Err((
                        "camera.glass".into(),
                        "a thin lens's glass needs focal_length_mm (the focal length at the d line)".into(),
                    ))
                }
                (Some(name), Some(f_mm)) => {
                    let (glass, nd) = super::find_glass(name).map_err(|e| ("camera.glass".to_string(), e.into()))?;
                    let film_distance = film_distance.unwrap_or(f_mm * 1e-3);
                    Some(ThinGlass { glass, nd, focal_length: f_mm * 1e-3, film_distance })
                }
            };
            Ok(Camera::ThinLens {
                frame: pose(&c.pose())?,
                tan_half: fov(*fov_deg)?,
                aspect,
                radius: diameter / 2.0,
                focus,
                glass,
                // filled in once the scene's lamps are known
                lamps: Default::default(),
                aperture: Aperture::from_spec(aperture_shape, dir)
                    .map_err(|e| ("camera.aperture_shape".into(), e.into()))?,
                focus_shift: *focus_shift,
            })
        }
        CameraSpec::Lens { sensor_mm, aperture_shape, .. } => {
            let lens = load_lens(c, dir, given)?;
            let aperture =
                Aperture::from_spec(aperture_shape, dir).map_err(|e| ("camera.aperture_shape".into(), e.into()))?;
            let frame = pose(&c.pose())?;
            if lens.is_tilted() {
                return Err(("camera".to_string(), FieldError::Camera(crate::camera::CameraError::Tilted)));
            }
            let optics = |e: lens::OpticsError| ("camera".to_string(), FieldError::Camera(e.into()));
            let real = match real {
                Some(r) => r,
                None if lens.focus_group().is_some() => RealFocus::Group(
                    lens::paraxial::focus_group_shift_for_focus(&lens, given_focus(c)? * 1e3).map_err(optics)?,
                ),
                None => RealFocus::Film(
                    lens::paraxial::film_for_focus_from_film(&lens, given_focus(c)? * 1e3).map_err(optics)?,
                ),
            };
            let (lens, film) = match real {
                RealFocus::Film(f) => (lens, f),
                RealFocus::Group(shift) => {
                    let moved = lens.with_focus_group_shift(shift).map_err(optics)?;
                    let f = moved.film_distance();
                    (moved, f)
                }
            };
            let cam = RealLensCamera::with_film_distance(frame, &lens, film, *sensor_mm, aperture, given.pupil)
                .map_err(|e| ("camera".to_string(), e.into()))?;
            Ok(Camera::Real(Box::new(cam)))
        }
    }
}

/// The camera's settings in words with their units, for the line a render
/// closes with: the kind, focal length and f-number where it has them, the
/// distance in focus, the sensor.
pub(super) fn summary(c: &CameraSpec, camera: &Camera) -> String {
    match (c, camera) {
        (CameraSpec::Pinhole { fov_deg, .. }, _) => format!("pinhole, vertical field of view {} deg", num(*fov_deg)),
        (
            CameraSpec::ThinLens { focal_length_mm, focus_distance: Some(focus_distance), .. },
            Camera::ThinLens { radius, .. },
        ) => {
            let lens = match focal_length_mm {
                Some(f) if *radius > 0.0 => format!("f = {} mm, f/{}", num(*f), num(f * 1e-3 / (2.0 * radius))),
                Some(f) => format!("f = {} mm, pinhole aperture", num(*f)),
                None => format!("aperture {} mm", num(2e3 * radius)),
            };
            format!("thin lens, {lens}, focus {} m", num(*focus_distance))
        }
        (CameraSpec::Lens { focus_distance: Some(focus_distance), sensor_mm, .. }, Camera::Real(r)) => {
            let p = r.prescription();
            let name = if p.name().is_empty() { "real lens".to_string() } else { p.name().to_string() };
            let first = match lens::paraxial::FirstOrder::of(p) {
                Ok(f) => format!("f = {} mm, f/{}", num(f.efl), num(f.f_number)),
                Err(_) => "afocal".to_string(),
            };
            format!(
                "{name}: {first}, focus {} m, sensor {} x {} mm",
                num(*focus_distance),
                num(sensor_mm[0]),
                num(sensor_mm[1])
            )
        }
        _ => String::new(),
    }
}

/// For a real lens, the share of the film's four corners from which no
/// ray passes the lens (an 8 x 8 grid of aperture samples each): the image
/// circle does not cover them.
pub(super) fn dark_corners(camera: &Camera) -> usize {
    let Camera::Real(_) = camera else { return 0 };
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    let grid = |k: usize| (k as f64 + 0.5) / 8.0;
    corners
        .iter()
        .filter(|&&(u, v)| !(0..64).any(|k| camera.ray(u, v, (grid(k % 8), grid(k / 8))).is_some_and(|(_, w)| w > 0.0)))
        .count()
}

/// Settings that render without error but are likely not what was meant:
/// a plane in focus beyond every bounded object (a distance given in mm
/// where the scene is in metres), a real lens whose image circle does not
/// cover the film.
pub(super) fn settings_warnings(spec: &CameraSpec, camera: &Camera, shapes: &[crate::geometry::Shape]) -> Vec<String> {
    let mut out = Vec::new();
    if let (Some(d), Some(frame)) = (spec.focus_distance(), camera.frame()) {
        let along = |p: DVec3| (p - frame.origin).dot(frame.forward);
        let farthest = shapes
            .iter()
            .filter_map(|s| match s {
                crate::geometry::Shape::Sphere { center, radius } => Some(along(*center) + radius),
                crate::geometry::Shape::Plane { .. } => None,
                crate::geometry::Shape::Quad { corner, u, v } => Some(
                    [*corner, *corner + *u, *corner + *v, *corner + *u + *v]
                        .map(along)
                        .into_iter()
                        .fold(f64::MIN, f64::max),
                ),
                crate::geometry::Shape::Triangle { v } => Some(v.map(along).into_iter().fold(f64::MIN, f64::max)),
            })
            .fold(f64::NEG_INFINITY, f64::max);
        if farthest > 0.0 && d > 2.0 * farthest {
            let mm = if d >= 100.0 {
                format!(" (scene lengths are metres: {} mm would be {} m)", exact(d), num(d * 1e-3))
            } else {
                String::new()
            };
            out.push(format!(
                "the plane in focus, {} m away, lies beyond every object of the scene (the farthest reaches {} m): \
                 nothing but the background is sharp{mm}",
                num(d),
                num(farthest)
            ));
        }
    }
    let dark = dark_corners(camera);
    if dark > 0 {
        out.push(format!(
            "the lens's image circle does not cover the film: no ray from {dark} of its 4 corners passes the lens, \
             and they render black (as a circular fisheye's do); to fill the frame choose a smaller sensor_mm, \
             or a lens made for this format"
        ));
    }
    out
}
