//! Colour: how focus, image height, spots and fans change with wavelength.
//!
//! As in optical design programs, the pupils and the image plane are those
//! of the primary wavelength: rays of every wavelength are launched from the
//! primary wavelength's entrance pupil and land on its paraxial image
//! plane. The system's shortest and longest wavelengths (F and C by
//! default) bound the colour errors:
//!
//! - **axial colour**: paraxial image distance at the shortest wavelength
//!   minus that at the longest (mm; negative: blue focuses nearer the lens,
//!   undercorrected);
//! - **secondary spectrum**: paraxial image distance at the primary minus
//!   the mean of those at the shortest and longest (mm): for an achromat,
//!   whose F and C foci coincide, the distance from their common focus to
//!   the d focus;
//! - **focal shift**: paraxial image distance at each wavelength of
//!   400-700 nm minus that of the primary;
//! - **lateral colour**: real chief rays of the shortest and longest
//!   wavelengths, height at the shortest minus height at the longest on the
//!   primary image plane, against field.

use super::bundle::trace_rays;
use super::fan::{fan_traced, ImagePlane, RayFan};
use super::launch::{Aim, Field, Launcher};
use super::pattern::Pattern;
use super::spot::spot_traced;
use crate::error::OpticsError;
use crate::glass::{LINE_D_NM, LINE_G_NM};
use crate::model::Prescription;
use crate::paraxial::{imaging::imaging, FirstOrder, ObjectDistance};
use crate::trace::Tracer;
use serde::Serialize;

/// The wavelengths of the focal-shift curve: 400-700 nm (within every
/// glass's data), every 5 nm.
pub const FOCAL_SHIFT_NM: [f64; 2] = [400.0, 700.0];
/// Step of the focal-shift curve, nm.
pub const FOCAL_SHIFT_STEP_NM: f64 = 5.0;
/// Fields of the lateral-colour curve, from 0 to the largest field.
pub const LATERAL_FIELDS: usize = 21;
/// Rings of the polychromatic spot (Gauss pattern) per wavelength.
pub const SPOT_RINGS: usize = 8;
/// Points of each fan.
pub const FAN_POINTS: usize = 41;

/// One point of the focal-shift curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FocalShiftPoint {
    /// Wavelength, nm.
    pub wavelength_nm: f64,
    /// Effective focal length at this wavelength, mm.
    pub efl: f64,
    /// Paraxial image distance from the last vertex, mm.
    pub image_distance: f64,
    /// `image_distance` minus the primary wavelength's, mm (+ away from the
    /// lens).
    pub focal_shift: f64,
}

/// Lateral colour at one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LateralColourPoint {
    /// Field angle, degrees.
    pub field_deg: f64,
    /// Height (y) of each system wavelength's real chief ray on the primary
    /// image plane, mm, in the order of `wavelengths_nm`.
    pub chief_y: Vec<f64>,
    /// Shortest wavelength's height minus the longest's, mm.
    pub lateral_colour: f64,
}

/// A glass of the system with its dispersion figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GlassUse {
    /// `VENDOR:NAME` (`MODEL:nd/vd` for a model glass).
    pub glass: String,
    /// The surfaces (1-based) after which it lies.
    pub surfaces: Vec<usize>,
    /// Index at the d line.
    pub nd: f64,
    /// Abbe number (nd - 1) / (nF - nC).
    pub vd: f64,
    /// Relative partial dispersion (ng - nF) / (nF - nC); `None` where the
    /// glass has no data at the g line.
    pub partial_dispersion_gf: Option<f64>,
}

/// One wavelength's share of the polychromatic spot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WavelengthSpot {
    /// Wavelength, nm.
    pub wavelength_nm: f64,
    /// Centroid on the primary image plane, mm.
    pub centroid: [f64; 2],
    /// RMS radius about its own centroid, mm.
    pub rms_radius: f64,
    /// Rays that reached the plane.
    pub rays: usize,
    /// Hits on the plane (x, y, mm), for pictures.
    #[serde(skip)]
    pub hits: Vec<[f64; 2]>,
}

/// The polychromatic spot at one field: every system wavelength, equal
/// weight each, on the primary image plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolychromaticSpot {
    /// Field angle, degrees.
    pub field_deg: f64,
    /// z of the primary paraxial image plane, mm from the first vertex.
    pub image_z: f64,
    /// Centroid of all wavelengths together, mm.
    pub centroid: [f64; 2],
    /// RMS radius of all wavelengths about their common centroid, mm.
    pub rms_radius: f64,
    /// Each wavelength.
    pub wavelengths: Vec<WavelengthSpot>,
}

/// One wavelength's fans (launched and evaluated as the primary's).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WavelengthFan {
    /// Wavelength, nm.
    pub wavelength_nm: f64,
    /// The fans.
    pub fan: RayFan,
}

/// Every colour figure of a system at one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Chromatic {
    /// The system's wavelengths, nm, shortest first.
    pub wavelengths_nm: Vec<f64>,
    /// The primary wavelength, nm.
    pub primary_wavelength_nm: f64,
    /// Paraxial image distance at the shortest wavelength minus at the
    /// longest, mm.
    pub axial_colour: f64,
    /// Paraxial image distance at the primary minus the mean of the
    /// shortest and longest, mm.
    pub secondary_spectrum: f64,
    /// Largest minus smallest focal shift over the curve, mm.
    pub focal_shift_range: f64,
    /// Lateral colour at the largest field (the last point of `lateral`),
    /// mm.
    pub lateral_colour: f64,
    /// The focal-shift curve.
    pub focal_shift: Vec<FocalShiftPoint>,
    /// Lateral colour from the axis to the largest field.
    pub lateral: Vec<LateralColourPoint>,
    /// The glasses, each once.
    pub glasses: Vec<GlassUse>,
    /// The polychromatic spot at the field asked for.
    pub spot: PolychromaticSpot,
    /// The fans of each system wavelength at that field.
    pub fans: Vec<WavelengthFan>,
}

/// Half the diagonal of a 36 x 24 mm frame, mm: the field a lens without
/// design fields is asked about.
const HALF_DIAGONAL_MM: f64 = 21.633;

/// The largest field [`chromatic`] plots lateral colour to when none is
/// asked: the design's own largest field where it names one, else the
/// corner of a 36 x 24 mm frame (at most 60 degrees), but 2% inside the
/// primary wavelength's last traceable field (there the other
/// wavelengths' rays, launched as the primary's, still pass).
pub fn default_max_field_deg(p: &Prescription, aim: Aim) -> Result<f64, OpticsError> {
    match p.fields_deg().iter().copied().fold(0.0, f64::max) {
        design if design > 0.0 => Ok(design),
        _ => {
            let efl = crate::paraxial::FirstOrder::of(p)?.efl.abs();
            let corner = (HALF_DIAGONAL_MM / efl).atan().to_degrees().min(60.0);
            Ok(corner.min(0.98 * crate::analysis::curves::largest_field_deg(p, aim)?))
        }
    }
}

/// The colour figures of `p` for its design object (at infinity, or at its
/// finite `object_distance_mm`, where the fields are the object points whose
/// chief rays make those angles, [`Field::at_angle`], and focus and focal
/// shift are those of that object's paraxial image); spot and fans at field
/// angle `field_deg`, lateral colour from 0 to `max_field_deg`.
/// Errors where a wavelength has no paraxial image (afocal at that
/// wavelength) or a chief ray is lost.
pub fn chromatic(p: &Prescription, field_deg: f64, max_field_deg: f64, aim: Aim) -> Result<Chromatic, OpticsError> {
    if !(max_field_deg.is_finite() && max_field_deg > 0.0 && max_field_deg < 90.0) {
        return Err(OpticsError::BadInput {
            name: "max_field_deg",
            value: max_field_deg,
            expected: "a largest field angle in degrees, above 0 and below 90",
        });
    }
    let primary = p.at_wavelength(p.primary_wavelength_nm())?;
    let mut wavelengths = p.wavelengths_nm().to_vec();
    wavelengths.sort_by(f64::total_cmp);
    wavelengths.dedup();
    let (short, long) = (wavelengths[0], wavelengths[wavelengths.len() - 1]);
    let object = ObjectDistance::from_mm(p.object_distance_mm().unwrap_or(f64::INFINITY))?;
    let image_distance = |nm: f64| -> Result<(f64, f64), OpticsError> {
        let q = p.at_wavelength(nm)?;
        let f = FirstOrder::of(&q)?;
        Ok((f.efl, imaging(&q, &f, object)?.image_distance))
    };
    let (_, primary_image) = image_distance(primary.wavelength_nm())?;
    let (_, short_image) = image_distance(short)?;
    let (_, long_image) = image_distance(long)?;

    // the focal-shift curve over the part of 400-700 nm every glass covers
    let (lo, hi) = p
        .glasses()
        .iter()
        .fold((FOCAL_SHIFT_NM[0], FOCAL_SHIFT_NM[1]), |(lo, hi), g| (lo.max(g.range_nm[0]), hi.min(g.range_nm[1])));
    // no point where the glasses share no part of 400-700 nm
    let points = if hi >= lo { ((hi - lo) / FOCAL_SHIFT_STEP_NM).floor() as usize + 1 } else { 0 };
    let mut focal_shift = Vec::with_capacity(points);
    for k in 0..points {
        let nm = (lo + k as f64 * FOCAL_SHIFT_STEP_NM).min(hi);
        let (efl, d) = image_distance(nm)?;
        focal_shift.push(FocalShiftPoint { wavelength_nm: nm, efl, image_distance: d, focal_shift: d - primary_image });
    }
    let (smin, smax) = focal_shift
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), f| (a.min(f.focal_shift), b.max(f.focal_shift)));

    let first = FirstOrder::of(&primary)?;
    let launcher_at = |deg: f64| Launcher::with_first(&primary, &first, Field::at_angle(&primary, &first, deg), aim);
    let traced: Vec<Prescription> = wavelengths.iter().map(|&nm| p.at_wavelength(nm)).collect::<Result<_, _>>()?;

    // lateral colour: real chief rays of every wavelength on the primary
    // image plane
    let mut lateral = Vec::with_capacity(LATERAL_FIELDS);
    for k in 0..LATERAL_FIELDS {
        let deg = max_field_deg * k as f64 / (LATERAL_FIELDS - 1) as f64;
        let launcher = launcher_at(deg)?;
        let image_z = launcher.paraxial_image_z(&primary)?;
        let ray = launcher.ray(0.0, 0.0)?;
        let mut chief_y = Vec::with_capacity(traced.len());
        for q in &traced {
            let tracer = Tracer::forward_to_film(q, image_z - q.last_vertex_z());
            chief_y.push(trace_rays(&tracer, &[ray])[0].chief(launcher.field())?.origin.y);
        }
        let lateral_colour = chief_y[0] - chief_y[chief_y.len() - 1];
        lateral.push(LateralColourPoint { field_deg: deg, chief_y, lateral_colour });
    }

    // the spot and the fans at the field asked for
    let launcher = launcher_at(field_deg)?;
    let mut spots = Vec::with_capacity(traced.len());
    let mut fans = Vec::with_capacity(traced.len());
    for (q, &nm) in traced.iter().zip(&wavelengths) {
        let s = spot_traced(&primary, q, &launcher, Pattern::Gauss, SPOT_RINGS, ImagePlane::Paraxial)?;
        spots.push((nm, s));
        fans.push(WavelengthFan {
            wavelength_nm: nm,
            fan: fan_traced(&primary, q, &launcher, FAN_POINTS, ImagePlane::Paraxial)?,
        });
    }
    let spot = polychromatic(field_deg, &spots);

    Ok(Chromatic {
        primary_wavelength_nm: primary.wavelength_nm(),
        axial_colour: short_image - long_image,
        secondary_spectrum: primary_image - 0.5 * (short_image + long_image),
        focal_shift_range: if focal_shift.is_empty() { 0.0 } else { smax - smin },
        lateral_colour: lateral.last().map_or(0.0, |l| l.lateral_colour),
        wavelengths_nm: wavelengths,
        focal_shift,
        lateral,
        glasses: glass_uses(p)?,
        spot,
        fans,
    })
}

/// The wavelengths' spots together, each wavelength weighted equally (its
/// rays by their pupil weights).
fn polychromatic(field_deg: f64, spots: &[(f64, super::spot::SpotDiagram)]) -> PolychromaticSpot {
    // each ray's weight: its share of its own wavelength's pupil
    let weighted = || {
        spots.iter().flat_map(|(_, s)| {
            let total: f64 = s.weights.iter().sum();
            s.hits.iter().zip(&s.weights).map(move |(h, w)| (h, w / total))
        })
    };
    let mut all = [0.0; 3]; // Σw x, Σw y, Σw
    for (h, w) in weighted() {
        all[0] += w * h[0];
        all[1] += w * h[1];
        all[2] += w;
    }
    let per = spots
        .iter()
        .map(|(nm, s)| WavelengthSpot {
            wavelength_nm: *nm,
            centroid: s.centroid,
            rms_radius: s.rms_radius,
            rays: s.rays,
            hits: s.hits.iter().map(|h| [h[0], h[1]]).collect(),
        })
        .collect();
    let c = [all[0] / all[2], all[1] / all[2]];
    let ms: f64 = weighted().map(|(h, w)| w * ((h[0] - c[0]).powi(2) + (h[1] - c[1]).powi(2))).sum();
    PolychromaticSpot {
        field_deg,
        image_z: spots.first().map_or(f64::NAN, |s| s.1.image_z),
        centroid: c,
        rms_radius: (ms / all[2]).sqrt(),
        wavelengths: per,
    }
}

/// Each glass of `p` once, with its surfaces and dispersion figures.
pub fn glass_uses(p: &Prescription) -> Result<Vec<GlassUse>, OpticsError> {
    let mut out: Vec<GlassUse> = Vec::new();
    for (g, glass) in p.glasses().iter().enumerate() {
        let surfaces =
            p.surfaces().iter().enumerate().filter(|(_, s)| s.glass == Some(g)).map(|(i, _)| i + 1).collect();
        let pgf = glass.index(LINE_G_NM).ok().and(glass.partial_dispersion_gf().ok());
        out.push(GlassUse {
            glass: glass.full_name(),
            surfaces,
            nd: glass.index(LINE_D_NM)?,
            vd: glass.vd()?,
            partial_dispersion_gf: pgf,
        });
    }
    Ok(out)
}
