//! Autofocus: the camera's focus found by tracing the scene, at a pixel
//! (the camera's central ray through its centre: a real lens's chief ray)
//! or toward a named shape (the ray from the camera position toward its
//! centre, on the shape's own surface, whatever stands before it). The
//! depth found is the distance along the axis from the camera position;
//! a thin lens is focused there by its own rule; a real lens's film is
//! moved (unit focusing) to the real-ray best focus of a point at that
//! distance (the least RMS spot of the real on-axis bundle, as `lens
//! focus` finds it), not the paraxial focus.

use super::camera::RealFocus;
use super::format::{CameraSpec, FilmSpec, FocusOn};
use super::{camera, v3, FieldError, Given};
use crate::camera::{Camera, Frame};
use crate::geometry::{Ray, Shape};
use glam::DVec3;
use lens::error::num;
use lens::paraxial::ObjectDistance;
use std::ops::Range;
use std::path::Path;

/// The focus autofocus found.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Autofocus {
    /// The camera's `focus_distance` in its own convention (thin lens: from
    /// the film with a focal length, from the lens without; real lens: from
    /// the film to the point focused on), m.
    pub distance_m: f64,
    /// How a real lens is focused at the real-ray best focus.
    pub real: Option<RealFocus>,
    /// What was focused on, in words, for the render's closing line.
    pub note: String,
}

type Problem = (String, FieldError);

/// The field autofocus errors name.
const FIELD: &str = "camera.focus_on";

/// Iterations for a real lens's pixel target (its chief ray depends on the
/// film, which depends on the depth found): converges in 2-3.
const ROUNDS: usize = 8;

/// Finds the focus of `spec` on `target`. `shapes` are the scene's
/// primitives and `named` the primitives of each named shape.
pub(crate) fn autofocus(
    spec: &CameraSpec,
    film: &FilmSpec,
    dir: &Path,
    given: &Given,
    target: &FocusOn,
    shapes: &[Shape],
    named: &[(String, Range<usize>)],
) -> Result<Autofocus, Problem> {
    let bad = |m: String| -> Problem { (FIELD.to_string(), m.into()) };
    if matches!(spec, CameraSpec::Pinhole { .. }) {
        return Err(bad("a pinhole has no focus: remove focus_on, or use a thin_lens or lens camera".into()));
    }
    let pose = spec.pose();
    let frame = Frame::look_at(v3(pose.position), v3(pose.look_at), v3(pose.up))
        .map_err(|e| ("camera.look_at".to_string(), e.into()))?;
    let (depth, what) = match target {
        FocusOn::Shape(name) => {
            let Some((_, range)) = named.iter().find(|(n, _)| n == name) else {
                let known: Vec<&str> = named.iter().map(|(n, _)| n.as_str()).collect();
                return Err(bad(format!(
                    "no shape is named \"{name}\" ({}): give a shape \"name\" and focus on it",
                    if known.is_empty() {
                        "no shape has a name".to_string()
                    } else {
                        format!("named: {}", known.join(", "))
                    }
                )));
            };
            (
                shape_depth(&frame, &shapes[range.clone()]).ok_or_else(|| {
                    bad(format!("the shape \"{name}\" is not in front of the camera: nothing there to focus on"))
                })?,
                format!("the shape \"{name}\""),
            )
        }
        FocusOn::Pixel([x, y]) => {
            let (w, h) = (film.width as f64, film.height as f64);
            if !(x.is_finite() && y.is_finite() && *x >= 0.0 && *x < w && *y >= 0.0 && *y < h) {
                return Err(bad(format!(
                    "pixel ({}, {}) is outside the {} x {} film: give a column 0..{} and a row 0..{} from the top left",
                    num(*x),
                    num(*y),
                    film.width,
                    film.height,
                    film.width - 1,
                    film.height - 1
                )));
            }
            let film_pos = ((x.floor() + 0.5) / w, (y.floor() + 0.5) / h);
            let at = format!("pixel ({}, {})", x.floor(), y.floor());
            let see = |cam: &Camera| -> Result<f64, Problem> {
                let ray = cam.central_rays(&[film_pos]).pop().flatten().ok_or_else(|| {
                    bad(format!("no ray from {at} leaves the lens (outside its image circle): choose another pixel"))
                })?;
                let f = cam.frame().copied().unwrap_or(frame);
                nearest(shapes, &ray).map(|p| (p - f.origin).dot(f.forward)).filter(|&z| z > 0.0).ok_or_else(|| {
                    bad(format!("{at} sees the background: nothing there to focus on; choose a pixel on an object"))
                })
            };
            // any focus for the first look: the thin lens's central ray
            // does not depend on it, a real lens's chief ray hardly
            let mut depth = see(&build(spec, film, dir, given, None, Some(1e6))?)?;
            if matches!(spec, CameraSpec::Lens { .. }) {
                for _ in 0..ROUNDS {
                    let real = real_focus(spec, dir, given, depth)?;
                    let next = see(&build(spec, film, dir, given, Some(real), Some(depth))?)?;
                    let done = (next - depth).abs() <= 1e-12 * depth;
                    depth = next;
                    if done {
                        break;
                    }
                }
            }
            (depth, at)
        }
    };
    match spec {
        CameraSpec::Lens { .. } => {
            let real = real_focus(spec, dir, given, depth)?;
            let how = match real {
                RealFocus::Film(f) => format!("film {} mm behind the last vertex", num(f)),
                RealFocus::Group(s) => format!("focus group moved {} mm toward the image", num(s)),
            };
            Ok(Autofocus {
                distance_m: depth,
                real: Some(real),
                note: format!("autofocus on {what}; {how}, its real-ray best focus"),
            })
        }
        CameraSpec::ThinLens { focal_length_mm, .. } => {
            let distance_m = match focal_length_mm {
                None => depth,
                Some(f_mm) => {
                    let f = f_mm * 1e-3;
                    if depth < 2.0 * f {
                        return Err(bad(format!(
                            "{what} is {} m from the lens, nearer than twice the focal length ({} m): this thin-lens \
                             camera focuses from 1:1 outward; move the camera back",
                            num(depth),
                            num(2.0 * f)
                        )));
                    }
                    depth + depth * f / (depth - f)
                }
            };
            Ok(Autofocus {
                distance_m,
                real: None,
                note: format!("autofocus on {what}, {} m from the lens", num(depth)),
            })
        }
        CameraSpec::Pinhole { .. } => unreachable!("refused above"),
    }
}

/// The camera of `spec` with its focus set to `distance` (m, the spec's
/// convention) and, for a real lens, focused as `real` says.
fn build(
    spec: &CameraSpec,
    film: &FilmSpec,
    dir: &Path,
    given: &Given,
    real: Option<RealFocus>,
    distance: Option<f64>,
) -> Result<Camera, Problem> {
    let mut s = spec.clone();
    s.set_focus(distance, None);
    camera::build_camera(&s, film, dir, given, real)
}

/// A real lens focused on a point `depth` m in front of the film at the
/// real-ray best focus of that point: its focus group moved (the film and
/// the lens's length stay) when it names one, else the film distance (mm
/// behind the last vertex; fixed-point iteration: the object distance from
/// the first vertex depends on the film).
fn real_focus(spec: &CameraSpec, dir: &Path, given: &Given, depth: f64) -> Result<RealFocus, Problem> {
    let optics = |e: lens::OpticsError| -> Problem { (FIELD.to_string(), e.into()) };
    let p = camera::load_lens(spec, dir, given)?;
    if p.focus_group().is_some() {
        let object = depth * 1e3 - p.total_track();
        if object <= 0.0 {
            return Err(optics(lens::OpticsError::FocusTooNear {
                distance: depth * 1e3,
                lens_length: p.total_track(),
            }));
        }
        let shift = lens::paraxial::focus_group_shift(&p, |q| {
            lens::analysis::focus::focus(q, ObjectDistance::Finite(object)).map(|f| f.best_focus_film_distance)
        })
        .map_err(optics)?;
        return Ok(RealFocus::Group(shift));
    }
    let z_last = p.last_vertex_z();
    let mut film = lens::paraxial::film_for_focus_from_film(&p, depth * 1e3).map_err(optics)?;
    for _ in 0..50 {
        let object = depth * 1e3 - z_last - film;
        if object <= 0.0 {
            return Err(optics(lens::OpticsError::FocusTooNear { distance: depth * 1e3, lens_length: z_last + film }));
        }
        let best = lens::analysis::focus::focus(&p, ObjectDistance::Finite(object)).map_err(optics)?;
        let next = best.best_focus_film_distance;
        let done = (next - film).abs() <= 1e-12 * film.abs().max(1.0);
        film = next;
        if done {
            break;
        }
    }
    Ok(RealFocus::Film(film))
}

/// The axial depth (m from the frame's origin) of the point where the ray
/// from the camera position toward the centre of `prims`' bounds meets
/// them (their centre itself when it does not: a camera inside the
/// shape); `None` when that is not in front of the camera.
fn shape_depth(frame: &Frame, prims: &[Shape]) -> Option<f64> {
    let centre = match prims {
        [Shape::Plane { point, .. }] => *point,
        _ => {
            let (lo, hi) = prims
                .iter()
                .map(Shape::bounds)
                .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(a, b), (l, h)| {
                    (a.min(l), b.max(h))
                });
            0.5 * (lo + hi)
        }
    };
    let dir = (centre - frame.origin).try_normalize()?;
    let ray = Ray { origin: frame.origin, dir };
    let p = nearest(prims, &ray).unwrap_or(centre);
    let z = (p - frame.origin).dot(frame.forward);
    (z > 0.0 && z.is_finite()).then_some(z)
}

/// The nearest point where `ray` meets one of `prims`.
fn nearest(prims: &[Shape], ray: &Ray) -> Option<DVec3> {
    prims.iter().filter_map(|s| s.intersect(ray, 1e-9, f64::INFINITY)).min_by(|a, b| a.t.total_cmp(&b.t)).map(|h| h.p)
}
