//! Field curves: distortion, tangential and sagittal field curvature,
//! longitudinal spherical aberration, and vignetting / relative
//! illumination against field angle.
//!
//! Fields are chief-ray angles. For an object at infinity that is the
//! direction of the light; for a prescription with a finite design object
//! distance (`object_distance_mm`) it is the object point whose chief ray
//! makes that angle, as [`Field::at_angle`] gives it, and the image plane is
//! that object's paraxial image plane (as optical design programs take an
//! angle field with a finite object).

use super::bundle::{launch, launch_aimed, trace_rays, Bundle, Landing};
use super::launch::{Aim, Field, Launcher};
use super::refine::{passing_nodes, BLOCK};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::{FirstOrder, ObjectDistance};
use crate::trace::{Ray, RayBatch, Tracer};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use serde::Serialize;

/// Pupil offset of the ray pairs that locate the tangential and sagittal
/// foci around the chief ray (normalised pupil units).
const DELTA: f64 = 1e-4;
/// Width of the square pupil grid used for the vignetting fraction.
const GRID: usize = 41;
/// Width of the square grid over the stop with which relative illumination
/// measures the light a bundle gathers ([`gathered`]).
const LIGHT_GRID: usize = 81;

/// Field curves at one field angle.
///
/// The paraxial image height is `S tan(theta)`, with `S` the EFL for an
/// object at infinity and `|m| D` for a finite object (m the paraxial
/// magnification, D the object's distance from the entrance pupil), which
/// tends to the EFL as the object recedes; relative illumination uses the
/// same `S`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FieldPoint {
    /// Field angle, degrees.
    pub field_deg: f64,
    /// Real chief-ray height on the paraxial image plane, mm.
    pub chief_height: f64,
    /// Paraxial image height S tan(theta), mm (S: the EFL for an object at
    /// infinity, |m| D for a finite object).
    pub paraxial_height: f64,
    /// Distortion 100 (real - paraxial) / paraxial, percent (0 on axis).
    pub distortion_percent: f64,
    /// Tangential focus: z distance from the paraxial image plane where
    /// neighbouring tangential rays cross, mm (+ toward the image).
    pub tangential_focus: f64,
    /// Sagittal focus, likewise, mm.
    pub sagittal_focus: f64,
    /// Fraction of a square pupil grid that reaches the image (1 = no
    /// vignetting).
    pub unvignetted_fraction: f64,
    /// Image irradiance relative to the axis for a uniformly bright object:
    /// the light the field's bundle gathers against the axis's (its beam's
    /// cross-section for an object at infinity, its projected solid angle
    /// for a finite object, over the rays that pass, the real stop's image
    /// measured as it is: pupil growth off the axis, its cos theta and
    /// vignetting), times S^2 sin(theta) / (h dh/dtheta) with h(theta) the
    /// real chief-ray height (over cos^3 theta more for a finite object; S as
    /// for `paraxial_height`). The cos^4 law for a thin lens stopped at
    /// itself.
    pub relative_illumination: f64,
}

/// One zone of longitudinal spherical aberration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SphericalZone {
    /// Normalised pupil radius.
    pub pupil: f64,
    /// Where the zone's ray crosses the axis, mm from the paraxial focus
    /// (+ toward the image).
    pub longitudinal: f64,
}

/// Field curves of a prescription.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldCurves {
    /// Largest field analysed, degrees.
    pub max_field_deg: f64,
    /// z of the paraxial image plane, mm from the first vertex.
    pub image_z: f64,
    /// Curves against field.
    pub fields: Vec<FieldPoint>,
    /// Longitudinal spherical aberration against pupil radius.
    pub spherical: Vec<SphericalZone>,
}

/// Computes the field curves at `n` fields from 0 to `max_field_deg`
/// (default: the largest field whose chief ray reaches the image, found by
/// search, at most 89 degrees).
pub fn field_curves(
    p: &Prescription,
    max_field_deg: Option<f64>,
    n: usize,
    aim: Aim,
) -> Result<FieldCurves, OpticsError> {
    // fields along +y stand for every azimuth only in a symmetric lens
    if p.is_tilted() {
        return Err(OpticsError::NotCoaxial {
            analysis: "field curves (field curvature and distortion against field)",
        });
    }
    let first = FirstOrder::of(p)?;
    let geometry = Geometry::of(p, &first)?;
    let image_z = geometry.image_z;
    let tracer = Tracer::forward_to_film(p, geometry.film);
    let base = Launcher::with_first(p, &first, geometry.field(0.0), aim)?;
    let max = match max_field_deg {
        Some(m) if m.is_finite() && m > 0.0 && m < 90.0 => m,
        Some(m) => {
            return Err(OpticsError::BadInput {
                name: "max field",
                value: m,
                expected: "an angle in degrees between 0 and 90",
            })
        }
        None => largest_field(&base, &tracer, &geometry),
    };
    if n > 10_000 {
        return Err(OpticsError::BadInput { name: "fields", value: n as f64, expected: "at most 10000 fields" });
    }
    let n = n.max(2);
    let open_stop = Tracer::forward_without_stop(p);
    let tracers = Tracers { to_film: &tracer, open_stop: &open_stop };
    let on_axis = vignetting(&base, &tracers)?;
    // relative illumination fills the real stop whatever the aim asked for
    let real = Launcher::with_first(p, &first, geometry.field(0.0), Aim::Real)?;
    let light = Light { on_axis: gathered(&real, &tracer)?, real };
    // the fields on all cores, in order (each field's numbers do not
    // depend on the others or on the thread count)
    let fields = (0..n)
        .into_par_iter()
        .map(|k| field_point(&base, &tracers, &geometry, max * k as f64 / (n - 1) as f64, on_axis, &light))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(FieldCurves { max_field_deg: max, image_z, fields, spherical: spherical(&tracer, &first, &geometry) })
}

/// What an angle field means for a prescription: its object (at infinity,
/// or the design's finite object distance), the paraxial image plane of that
/// object, and the scale S of the paraxial image height S tan(theta).
struct Geometry {
    /// The design object distance d, mm in front of the first vertex, and
    /// the paraxial entrance pupil's z, if the object is finite.
    finite: Option<(f64, f64)>,
    /// Distance of the paraxial image plane from the last vertex, mm.
    film: f64,
    /// z of the paraxial image plane, mm from the first vertex.
    image_z: f64,
    /// Paraxial image height per unit tan(theta), mm.
    scale: f64,
}

impl Geometry {
    fn of(p: &Prescription, first: &FirstOrder) -> Result<Self, OpticsError> {
        match p.object_distance_mm() {
            Some(d) if d.is_finite() => {
                let object = ObjectDistance::from_mm(d)?;
                let im = crate::paraxial::imaging(p, first, object)?;
                // the object's distance from the entrance pupil
                let to_pupil = d + first.entrance_pupil.z;
                Ok(Self {
                    finite: Some((d, first.entrance_pupil.z)),
                    film: im.image_distance,
                    image_z: p.last_vertex_z() + im.image_distance,
                    scale: (im.magnification * to_pupil).abs(),
                })
            }
            _ => Ok(Self { finite: None, film: first.bfl, image_z: p.last_vertex_z() + first.bfl, scale: first.efl }),
        }
    }

    /// The field of chief-ray angle `deg`, degrees.
    fn field(&self, deg: f64) -> Field {
        match self.finite {
            Some((d, z_ep)) => Field::from_angle(Some(d), z_ep, deg),
            None => Field::Angle(deg),
        }
    }
}

/// The largest field angle (degrees, at most 89) whose chief ray and the
/// four rays next to it reach `p`'s paraxial image plane, for its design
/// object: the field curves' default range, and a safe default for other
/// analyses over field.
pub fn largest_field_deg(p: &Prescription, aim: Aim) -> Result<f64, OpticsError> {
    let first = FirstOrder::of(p)?;
    let geometry = Geometry::of(p, &first)?;
    let tracer = Tracer::forward_to_film(p, geometry.film);
    let base = Launcher::with_first(p, &first, geometry.field(0.0), aim)?;
    Ok(largest_field(&base, &tracer, &geometry))
}

/// The field angle (degrees, the sign of `height_mm`) whose image is
/// `height_mm` from the axis, for `p`'s design object: paraxially, S
/// tan(theta) = h on the paraxial image plane (S the EFL for an object at
/// infinity, |m| times the object's distance from the entrance pupil for a
/// finite one), or where the real chief ray meets `p`'s own image plane
/// (its film, the last thickness: Zemax's image surface) (`real`, bisection
/// to 1e-12 degrees up to the largest field whose chief ray and its
/// neighbours reach that plane). How a Zemax field given as a paraxial or a
/// real image height (`FTYP 2`, `3`) becomes an angle. Errors where no
/// field the chief ray reaches has that height.
pub fn field_deg_for_image_height(p: &Prescription, height_mm: f64, real: bool) -> Result<f64, OpticsError> {
    if !height_mm.is_finite() {
        return Err(OpticsError::BadInput {
            name: "image height",
            value: height_mm,
            expected: "a finite height in mm",
        });
    }
    let first = FirstOrder::of(p)?;
    let geometry = Geometry::of(p, &first)?;
    let h = height_mm.abs();
    if h == 0.0 {
        return Ok(0.0);
    }
    let deg = if real {
        let tracer = Tracer::forward_to_film(p, p.film_distance());
        let base = Launcher::with_first(p, &first, geometry.field(0.0), Aim::Real)?;
        let top = largest_field(&base, &tracer, &geometry);
        let at = |deg: f64| chief_height(&base, &tracer, geometry.field(deg)).map(f64::abs);
        if at(top)? < h {
            return Err(OpticsError::BadInput {
                name: "real image height",
                value: height_mm,
                expected: "a height the chief ray reaches (the largest field it reaches images nearer the axis)",
            });
        }
        let (mut lo, mut hi) = (0.0, top);
        while hi - lo > 1e-12 {
            let mid = 0.5 * (lo + hi);
            if at(mid)? < h {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    } else {
        (h / geometry.scale).atan().to_degrees()
    };
    Ok(deg.copysign(height_mm))
}

/// The field angle (degrees, the sign of `height_mm`) of the object point
/// `height_mm` from the axis in `p`'s design object plane: the angle of its
/// chief ray to the paraxial entrance pupil, as a Zemax object-height field
/// (`FTYP 1`) means. Errors for an object at infinity (which has no heights).
pub fn field_deg_for_object_height(p: &Prescription, height_mm: f64) -> Result<f64, OpticsError> {
    let first = FirstOrder::of(p)?;
    match Geometry::of(p, &first)?.finite {
        // the object point below the axis (negative height) has the
        // positive chief-ray angle; the file's height keeps its own sign
        Some((d, z_ep)) if height_mm.is_finite() => {
            Ok(Field::Height { object_distance: d, height: -height_mm }.angle_deg(z_ep))
        }
        Some(_) => {
            Err(OpticsError::BadInput { name: "object height", value: height_mm, expected: "a finite height in mm" })
        }
        None => Err(OpticsError::BadInput {
            name: "object height",
            value: height_mm,
            expected: "an object at a finite distance (an object at infinity has field angles, not heights)",
        }),
    }
}

/// Distortion at one field, percent: 100 (h - h_p) / h_p with h the real
/// chief-ray height on the paraxial image plane and h_p the paraxial image
/// height (EFL tan(theta) for an angle, m x height for a finite object).
/// 0 on axis.
pub fn distortion(p: &Prescription, field: Field, aim: Aim) -> Result<f64, OpticsError> {
    let launcher = Launcher::new(p, field, aim)?;
    let image_z = launcher.paraxial_image_z(p)?;
    let tracer = Tracer::forward_to_film(p, image_z - p.last_vertex_z());
    let first = launcher.first_order();
    let paraxial = match field {
        Field::Angle(deg) => first.efl * deg.to_radians().tan(),
        Field::Height { height, .. } => crate::paraxial::imaging(p, first, field.object())?.magnification * height,
        Field::Angles { x_deg, y_deg } => {
            // radial: the chief ray's point along the paraxial image point's direction
            let hp = first.efl * DVec2::new(x_deg.to_radians().tan(), y_deg.to_radians().tan());
            return radial_distortion(chief(&launcher, &tracer)?, hp);
        }
        Field::Point { x, y, .. } => {
            let m = crate::paraxial::imaging(p, first, field.object())?.magnification;
            return radial_distortion(chief(&launcher, &tracer)?, m * DVec2::new(x, y));
        }
    };
    let h = chief(&launcher, &tracer)?[1];
    Ok(if paraxial == 0.0 { 0.0 } else { 100.0 * (h - paraxial) / paraxial })
}

/// Distortion, percent, of a chief ray landing at `h` (mm) whose paraxial
/// image point is `hp`: the chief point's component along `hp` against
/// `|hp|` (a y field's signed height ratio, in any direction).
fn radial_distortion(h: [f64; 2], hp: DVec2) -> Result<f64, OpticsError> {
    let r2 = hp.length_squared();
    Ok(if r2 == 0.0 { 0.0 } else { 100.0 * (DVec2::from(h).dot(hp) - r2) / r2 })
}

/// The chief ray's point on the tracer's image plane.
fn chief(launcher: &Launcher, tracer: &Tracer) -> Result<[f64; 2], OpticsError> {
    let r = Bundle::trace(launcher, tracer, vec![(0.0, 0.0)])?.landings[0].chief(launcher.field())?;
    Ok([r.origin.x, r.origin.y])
}

fn chief_height(base: &Launcher, tracer: &Tracer, field: Field) -> Result<f64, OpticsError> {
    Ok(chief(&base.at_field(field)?, tracer)?[1])
}

/// The chief ray and its four neighbours (the focus-locating pairs).
const PROBES: [(f64, f64); 5] = [(0.0, 0.0), (0.0, DELTA), (0.0, -DELTA), (DELTA, 0.0), (-DELTA, 0.0)];

fn field_point(
    base: &Launcher,
    tracers: &Tracers,
    geometry: &Geometry,
    deg: f64,
    on_axis: f64,
    light: &Light,
) -> Result<FieldPoint, OpticsError> {
    let field = geometry.field(deg);
    let launcher = base.at_field(field)?;
    let tracer = tracers.to_film;
    let theta = deg.to_radians();
    let probes = Bundle::trace(&launcher, tracer, PROBES.to_vec())?;
    let h = probes.landings[0].chief(field)?.origin.y;
    let paraxial = geometry.scale * theta.tan();
    let distortion = if deg == 0.0 { 0.0 } else { 100.0 * (h - paraxial) / paraxial };
    let pair = |a: usize, b: usize, tangential: bool| -> Result<f64, OpticsError> {
        match (probes.landings[a].reached(), probes.landings[b].reached()) {
            (Some(ra), Some(rb)) => {
                let (pa, pb, sa, sb) = if tangential {
                    (ra.origin.y, rb.origin.y, ra.direction.y / ra.direction.z, rb.direction.y / rb.direction.z)
                } else {
                    (ra.origin.x, rb.origin.x, ra.direction.x / ra.direction.z, rb.direction.x / rb.direction.z)
                };
                Ok(if sa == sb { 0.0 } else { -(pa - pb) / (sa - sb) })
            }
            _ => Err(OpticsError::ChiefRayLost {
                field: field.describe(),
                why: "a ray next to the chief ray is vignetted".into(),
            }),
        }
    };
    let tangential_focus = pair(1, 2, true)?;
    let sagittal_focus = pair(3, 4, false)?;
    let fraction = vignetting(&launcher, tracers)?;
    let relative_illumination = if deg == 0.0 {
        1.0
    } else {
        // dh/dtheta by a central difference of the chief-ray height; a
        // backward one where the field just beyond is lost (the last field)
        let step = (0.01f64).min(deg / 2.0);
        // (the neighbouring fields' chief rays searched from this one's)
        let near = |d: f64| chief(&launcher.at_nearby_field(geometry.field(d))?, tracer).map(|c| c[1]);
        let hm = near(deg - step)?;
        let dh = match near(deg + step) {
            Ok(hp) => (hp - hm) / (2.0 * step.to_radians()),
            Err(_) => (h - hm) / step.to_radians(),
        };
        // the light the bundle gathers against the axis's (the pupil's
        // growth, its cos theta and vignetting), times the image area per
        // unit of object (solid angle for infinity, area for a finite object)
        // (the field's own launcher where it aims real rays: the real chief
        // ray found once)
        let gathers = match launcher.aim() {
            Aim::Real => gathered(&launcher, tracer)?,
            _ => gathered(&light.real.at_nearby_field(field)?, tracer)?,
        };
        let ratio = gathers / light.on_axis;
        let slant = if geometry.finite.is_some() { theta.cos().powi(-3) } else { 1.0 };
        let f = geometry.scale;
        let ri = ratio * f * f * theta.sin() * slant / (dh * h).abs();
        // no light (or none measurable): 0, not -0 or NaN
        if ri.is_finite() && ri > 0.0 {
            ri
        } else {
            0.0
        }
    };
    Ok(FieldPoint {
        field_deg: deg,
        chief_height: h,
        paraxial_height: paraxial,
        distortion_percent: distortion,
        tangential_focus,
        sagittal_focus,
        unvignetted_fraction: fraction / on_axis.max(f64::MIN_POSITIVE),
        relative_illumination,
    })
}

/// What relative illumination compares every field with: a launcher that
/// aims real rays at the stop, and the light the axial bundle gathers.
struct Light {
    real: Launcher,
    on_axis: f64,
}

/// The light a field's bundle gathers, up to a constant factor: for an
/// object at infinity the beam's cross-section across its direction (mm^2:
/// its area on the entrance-pupil plane times cos theta), for a finite
/// object point the projected solid angle of its rays, over the rays that
/// reach the image. The rays cross the entrance-pupil plane on a
/// [`LIGHT_GRID`] x [`LIGHT_GRID`] grid over the box that rays aimed at 32
/// points of the stop's rim span there (10% wider): the real stop's image,
/// so that a pupil that grows off the axis (a retrofocus wide angle's) is
/// measured as it is. Each passing ray counts its cell's area (for a finite
/// object, as the solid angle it subtends projected: area cos^4 / D^2, D
/// the object's distance from that plane). No rim point that aims: no light.
fn gathered(launcher: &Launcher, tracer: &Tracer) -> Result<f64, OpticsError> {
    let field = launcher.field();
    let z_ep = launcher.first_order().entrance_pupil.z;
    let on_plane = |r: &Ray| (r.origin + r.direction * ((z_ep - r.origin.z) / r.direction.z)).truncate();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    // the rim's 32 points aimed together (real aiming in lock step)
    let rim: Vec<(f64, f64)> = (0..32)
        .map(|k| {
            let (s, c) = (std::f64::consts::TAU * k as f64 / 32.0).sin_cos();
            (c, s)
        })
        .collect();
    for (&(c, s), e) in rim.iter().zip(launcher.aim_many(&rim)) {
        if let Ok(r) = e.and_then(|e| launcher.ray_from_pupil(c, s, e)) {
            let e = on_plane(&r);
            (lo, hi) = (lo.min(e), hi.max(e));
        }
    }
    if !(lo.x < hi.x && lo.y < hi.y && lo.is_finite() && hi.is_finite()) {
        return Ok(0.0);
    }
    let margin = 0.1 * (hi - lo);
    let (lo, hi) = (lo - margin, hi + margin);
    let n = LIGHT_GRID;
    let cell = (hi - lo) / n as f64;
    let ray = |k: usize| launcher.ray_through(lo + cell * DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5));
    let weight = |r: &Ray| match field {
        Field::Angle(_) | Field::Angles { .. } => 1.0,
        Field::Height { object_distance, .. } | Field::Point { object_distance, .. } => {
            r.direction.z.powi(4) / (z_ep + object_distance).powi(2)
        }
    };
    // which rays pass, traced in batches: the grid's coarse nodes, then the
    // blocks the light's edge crosses
    let pass = passing_nodes(
        n,
        |_| true,
        |ks| {
            let mut batch = RayBatch::with_capacity(ks.len());
            for &k in ks {
                match ray(k) {
                    Some(r) => batch.push(r),
                    None => batch.push_skipped(),
                }
            }
            tracer.trace_soa(&mut batch);
            batch.status.iter().map(|s| *s == 0).collect()
        },
    );
    let passing = (0..n * n).filter(|&k| pass[k]);
    let sum: f64 = match field {
        // (each ray's weight 1: the count, without forming the rays again)
        Field::Angle(_) | Field::Angles { .. } => passing.count() as f64,
        Field::Height { .. } | Field::Point { .. } => passing.filter_map(|k| ray(k).map(|r| weight(&r))).sum(),
    };
    let cos = match field {
        Field::Angle(deg) => deg.to_radians().cos(),
        Field::Angles { x_deg, y_deg } => {
            1.0 / DVec3::new(x_deg.to_radians().tan(), y_deg.to_radians().tan(), 1.0).length()
        }
        Field::Height { .. } | Field::Point { .. } => 1.0,
    };
    Ok(sum * cell.x * cell.y * cos)
}

/// The tracers of field curves: to the paraxial image plane, and the same
/// with the stop left open.
struct Tracers<'a> {
    to_film: &'a Tracer,
    open_stop: &'a Tracer,
}

/// Fraction of a square pupil grid ([`GRID`] points across, those inside
/// the unit circle) that reaches the image at `field` (a ray that cannot be
/// aimed counts as vignetted). Found on the grid's coarse nodes and the
/// blocks where they disagree ([`passing_nodes`]); a coarse node outside the
/// circle stands for its point on the rim. Real-aimed rays meet the stop at
/// their pupil point, inside it: they are traced with the stop open (the
/// other apertures vignette them), so that the stop's own edge is no
/// boundary to refine.
fn vignetting(launcher: &Launcher, tracers: &Tracers) -> Result<f64, OpticsError> {
    let n = GRID;
    let at = |k: usize| {
        let x = -1.0 + 2.0 * (k % n) as f64 / (n - 1) as f64;
        let y = -1.0 + 2.0 * (k / n) as f64 / (n - 1) as f64;
        (x, y)
    };
    // the test of `points`' own circle
    let inside = |k: usize| {
        let (x, y) = at(k);
        x * x + y * y <= 1.0 + 1e-12
    };
    // a node outside the circle stands for its point on the rim
    let on_disc = |k: usize| {
        let (x, y) = at(k);
        let r = x.hypot(y);
        if r > 1.0 {
            (x / r, y / r)
        } else {
            (x, y)
        }
    };
    let real = launcher.aim() == Aim::Real;
    let tracer = if real { tracers.open_stop } else { tracers.to_film };
    // the entrance-pupil points real aiming has found, by node: a later
    // node's Newton run starts from its block's corners' (interpolated)
    let mut found: Vec<Option<DVec2>> = vec![None; n * n];
    let mut error = None;
    let pass = passing_nodes(n, inside, |ks| {
        let points: Vec<(f64, f64)> = ks.iter().map(|&k| on_disc(k)).collect();
        let mut batch = RayBatch::with_capacity(ks.len());
        let launched = if real {
            let starts: Vec<DVec2> = ks
                .iter()
                .zip(&points)
                .map(|(&k, &(x, y))| {
                    start_from_corners(n, k, &found, inside, at).unwrap_or_else(|| launcher.paraxial_aim(x, y))
                })
                .collect();
            launch_aimed(launcher, &points, &starts, &mut batch).map(|aims| {
                for (&k, e) in ks.iter().zip(aims) {
                    found[k] = e;
                }
            })
        } else {
            launch(launcher, points.into_iter(), &mut batch).map(|_| ())
        };
        if let Err(e) = launched {
            error = Some(e);
        }
        tracer.trace_soa(&mut batch);
        // a point aiming could not place keeps its non-zero status
        batch.status.iter().map(|s| *s == 0).chain(std::iter::repeat(false)).take(ks.len()).collect()
    });
    if let Some(e) = error {
        return Err(e);
    }
    let wanted = (0..n * n).filter(|&k| inside(k));
    let total = wanted.clone().count();
    Ok(wanted.filter(|&k| pass[k]).count() as f64 / total as f64)
}

/// Where real aiming's Newton run for node `k` of an `n` x `n` pupil grid
/// starts: the entrance-pupil points `found` for the corners of its block
/// (of [`BLOCK`] cells, those inside the pupil), interpolated bilinearly
/// when all four are there, else the nearest one's (`None`: no corner
/// aimed).
fn start_from_corners(
    n: usize,
    k: usize,
    found: &[Option<DVec2>],
    inside: impl Fn(usize) -> bool,
    at: impl Fn(usize) -> (f64, f64),
) -> Option<DVec2> {
    let (i, j) = (k / n, k % n);
    let span = |a: usize| {
        let lo = a / BLOCK * BLOCK;
        let hi = (lo + BLOCK).min(n - 1);
        let t = if hi > lo { (a - lo) as f64 / (hi - lo) as f64 } else { 0.0 };
        (lo, hi, t)
    };
    let ((i0, i1, ti), (j0, j1, tj)) = (span(i), span(j));
    let corners = [(i0, j0), (i0, j1), (i1, j0), (i1, j1)].map(|(a, b)| {
        let c = a * n + b;
        found[c].filter(|_| inside(c)).map(|e| (c, e))
    });
    if let [Some((_, a)), Some((_, b)), Some((_, c)), Some((_, d))] = corners {
        return Some((a * (1.0 - tj) + b * tj) * (1.0 - ti) + (c * (1.0 - tj) + d * tj) * ti);
    }
    let (x, y) = at(k);
    corners
        .into_iter()
        .flatten()
        .min_by(|(c1, _), (c2, _)| {
            let d = |c: usize| {
                let (cx, cy) = at(c);
                (cx - x).hypot(cy - y)
            };
            d(*c1).total_cmp(&d(*c2))
        })
        .map(|(_, e)| e)
}

/// The largest field (degrees, at most 89) whose chief ray and its four
/// neighbours (the focus-locating pairs) reach the image.
fn largest_field(base: &Launcher, tracer: &Tracer, geometry: &Geometry) -> f64 {
    let ok = |deg: f64| {
        let Ok(l) = base.at_field(geometry.field(deg)) else { return false };
        Bundle::trace(&l, tracer, PROBES.to_vec()).is_ok_and(|b| b.vignetted() == 0)
    };
    let mut lo = 0.0;
    let mut hi = 89.0;
    if ok(hi) {
        return hi;
    }
    // coarse scan from the axis, then bisection at the first loss
    let mut d = 1.0;
    while d < 89.0 && ok(d) {
        lo = d;
        d += 1.0;
    }
    hi = d.min(89.0);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Longitudinal spherical aberration of the on-axis bundle at 21 zones:
/// rays through the paraxial entrance pupil at 0.05, 0.1, ... 1 of its
/// radius, parallel to the axis for an object at infinity, from the axial
/// object point for a finite one.
fn spherical(tracer: &Tracer, first: &FirstOrder, geometry: &Geometry) -> Vec<SphericalZone> {
    let r_ep = first.entrance_pupil.diameter / 2.0;
    let z_ep = first.entrance_pupil.z;
    let image_z = geometry.image_z;
    let ray = |h: f64| match geometry.finite {
        Some((d, _)) => {
            let origin = DVec3::new(0.0, 0.0, -d);
            Ray { origin, direction: (DVec3::new(0.0, h, z_ep) - origin).normalize() }
        }
        None => Ray { origin: DVec3::new(0.0, h, z_ep), direction: DVec3::Z },
    };
    let rays: Vec<Ray> = (1..=20).map(|k| ray(k as f64 / 20.0 * r_ep)).collect();
    let mut zones = vec![SphericalZone { pupil: 0.0, longitudinal: 0.0 }];
    for (k, l) in (1..=20).zip(trace_rays(tracer, &rays)) {
        if let Landing::Reached(ray) = l {
            if ray.direction.y != 0.0 {
                let z = ray.origin.z - ray.origin.y * ray.direction.z / ray.direction.y;
                zones.push(SphericalZone { pupil: k as f64 / 20.0, longitudinal: z - image_z });
            }
        }
    }
    zones
}
