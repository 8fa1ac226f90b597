//! Ray fans: transverse ray error against pupil coordinate, tangential
//! (y error against py) and sagittal (x error against px), relative to the
//! chief ray, on an image plane.

use super::bundle::Bundle;
use super::launch::{Aim, Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
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
    /// Field angle (y), degrees (object at infinity), or `None` for a finite object.
    pub field_deg: Option<f64>,
    /// The field's x angle, degrees, for a field with an x component at
    /// infinity ([`Field::Angles`]); `None` (and not written) otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field_x_deg: Option<f64>,
    /// Which plane the fans are on: `"image_surface"` (the prescription's
    /// own, its last thickness), `"paraxial"` or `"film"` (a distance given).
    pub image_plane: &'static str,
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
    /// The design's vignetting factors the fans were launched with (the
    /// nearest design field's), where it has any: px and py are then the
    /// coordinates before them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vignetting_factors: Option<crate::model::VignettingFactors>,
}

/// Where rays are evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ImagePlane {
    /// The prescription's own image surface: its last thickness behind the
    /// last vertex (Zemax's and optiland's image surface), the default.
    #[default]
    ImageSurface,
    /// The paraxial image plane of the field's object.
    Paraxial,
    /// A film this many mm behind the last vertex.
    Film(f64),
}

impl ImagePlane {
    /// The plane's name in outputs: `"image_surface"`, `"paraxial"` or
    /// `"film"`.
    pub fn name(&self) -> &'static str {
        match self {
            ImagePlane::ImageSurface => "image_surface",
            ImagePlane::Paraxial => "paraxial",
            ImagePlane::Film(_) => "film",
        }
    }

    /// z from the first vertex of this plane for `launcher`'s object.
    pub fn z(&self, p: &Prescription, launcher: &Launcher) -> Result<f64, OpticsError> {
        match *self {
            ImagePlane::ImageSurface => Ok(p.total_track()),
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
    fan_with(p, &Launcher::new(p, field, aim)?, n, plane)
}

/// [`ray_fan`] with a launcher already made (first-order data computed once
/// by the caller). The chief ray and both fans are one batch.
pub fn fan_with(p: &Prescription, launcher: &Launcher, n: usize, plane: ImagePlane) -> Result<RayFan, OpticsError> {
    fan_traced(p, p, launcher, n, plane)
}

/// [`fan_with`] with the rays traced through `traced` (the same system at
/// another wavelength) while the launcher and the image plane are those of
/// `p` (the primary wavelength), as optical design programs do.
pub fn fan_traced(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    n: usize,
    plane: ImagePlane,
) -> Result<RayFan, OpticsError> {
    if n > 1_000_001 {
        return Err(OpticsError::BadInput {
            name: "points",
            value: n as f64,
            expected: "at most 1000001 points per fan",
        });
    }
    let field = launcher.field();
    let image_z = plane.z(p, launcher)?;
    let tracer = Tracer::forward_to_film(traced, image_z - p.last_vertex_z());
    let coords = fan_coordinates(n);
    // the design's vignetting factors at this field move the fans' rays
    // (not the chief ray) into the pupil that passes
    let vig = launcher.vignetting(p)?;
    let mut points = vec![(0.0, 0.0)];
    for &c in &coords {
        points.push(vig.apply(0.0, c));
        points.push(vig.apply(c, 0.0));
    }
    let bundle = Bundle::trace(launcher, &tracer, points)?;
    let at = |i: usize| bundle.landings[i].reached().map(|r| [r.origin.x, r.origin.y]);
    let chief = {
        let r = bundle.landings[0].chief(field)?;
        [r.origin.x, r.origin.y]
    };
    let mut tangential = Vec::with_capacity(n);
    let mut sagittal = Vec::with_capacity(n);
    for (k, &c) in coords.iter().enumerate() {
        tangential.push(match at(1 + 2 * k) {
            Some([x, y]) => TangentialPoint { py: c, x: Some(x), y: Some(y), ey: Some(y - chief[1]) },
            None => TangentialPoint { py: c, x: None, y: None, ey: None },
        });
        sagittal.push(match at(2 + 2 * k) {
            Some([x, y]) => SagittalPoint { px: c, x: Some(x), y: Some(y), ex: Some(x - chief[0]) },
            None => SagittalPoint { px: c, x: None, y: None, ex: None },
        });
    }
    let (field_x_deg, field_deg) = field.reported_angles();
    Ok(RayFan {
        field_deg,
        field_x_deg,
        image_plane: plane.name(),
        image_z,
        chief,
        tangential,
        sagittal,
        vignetted: bundle.vignetted(),
        aim_failures: bundle.aim_failures(),
        vignetting_factors: (!vig.is_none()).then_some(vig),
    })
}
