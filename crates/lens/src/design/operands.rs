//! Merit-function operands: what is measured on a candidate lens (each
//! through the same analysis the commands print, so an operand's value is
//! the number `lens info`, `lens spot`, `lens wavefront`, `lens mtf` or
//! `lens field` gives for that lens), its target and how it counts.

use super::spec::OperandSpec;
use super::DesignError;
use crate::analysis::bundle::Bundle;
use crate::analysis::fan::ImagePlane;
use crate::analysis::pattern::Pattern;
use crate::analysis::spot::spot_polychromatic;
use crate::analysis::wave::{mtf, stats, wavefront_auto};
use crate::analysis::{curves, Aim, Field, Launcher};
use crate::error::OpticsError;
use crate::paraxial::{imaging, FirstOrder};
use crate::trace::Tracer;
use crate::{Prescription, PrescriptionSpec};
use serde::Serialize;

/// What an operand measures. Lengths mm, angles degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "type")]
pub enum Measure {
    /// Effective focal length, mm (`lens info`).
    Efl,
    /// Paraxial f-number |EFL| / entrance-pupil diameter (`lens info`).
    FNumber,
    /// Back focal length: last vertex to the rear focal point, mm.
    BackFocus,
    /// First vertex to the image surface, mm.
    TotalTrack,
    /// Paraxial lateral magnification of the design's object (needs a
    /// finite `object_distance_mm`).
    Magnification,
    /// RMS spot radius about the centroid, mm, on the image surface, over
    /// the merit function's wavelengths with their weights (or one), Gauss
    /// rings as `lens spot --n`.
    RmsSpot {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
        /// Gauss rings.
        rings: usize,
        /// One wavelength instead of the merit's, nm.
        wavelength_nm: Option<f64>,
    },
    /// RMS wavefront error with piston and tilt removed (to centroid),
    /// waves, at the primary (or the given) wavelength, on the default
    /// pupil grid (`lens wavefront`).
    RmsWavefront {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
        /// The wavelength, nm (default the primary).
        wavelength_nm: Option<f64>,
    },
    /// Diffraction MTF at one frequency at the primary (or the given)
    /// wavelength (`lens mtf`).
    Mtf {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
        /// Cycles/mm.
        frequency_per_mm: f64,
        /// Which direction.
        orientation: Orientation,
        /// The wavelength, nm (default the primary).
        wavelength_nm: Option<f64>,
    },
    /// Distortion, percent (`lens field`).
    Distortion {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
    },
    /// x of a real ray on the image surface, mm.
    RayX {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
        /// Normalised pupil x.
        px: f64,
        /// Normalised pupil y.
        py: f64,
        /// The wavelength, nm (default the primary).
        wavelength_nm: Option<f64>,
    },
    /// y of a real ray on the image surface, mm.
    RayY {
        /// Field angle, degrees (y; [`crate::analysis::Field::at_angles`]).
        field_deg: f64,
        /// The field's x component, degrees (0: a y field).
        field_x_deg: f64,
        /// Normalised pupil x.
        px: f64,
        /// Normalised pupil y.
        py: f64,
        /// The wavelength, nm (default the primary).
        wavelength_nm: Option<f64>,
    },
    /// The axial thickness after a surface (glass or air), mm.
    CenterThickness {
        /// The surface, from 1.
        surface: usize,
    },
    /// The thickness after a surface at the larger semi-diameter of it and
    /// the next surface, mm: thickness + sag(next) - sag(this).
    EdgeThickness {
        /// The surface, from 1.
        surface: usize,
    },
}

/// The direction of an MTF operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    /// Along the meridional direction.
    Tangential,
    /// Across it.
    Sagittal,
    /// The mean of the two.
    Mean,
}

/// How an operand's value counts against its target.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Goal {
    /// The value should equal the target.
    Equal {
        /// The target.
        target: f64,
    },
    /// The value should be at least `min` and at most `max` (either may be
    /// infinite); nothing counts inside.
    Within {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
}

impl Goal {
    /// The value's distance from the goal (0 when met; signed).
    pub fn miss(&self, value: f64) -> f64 {
        match *self {
            Goal::Equal { target } => value - target,
            Goal::Within { min, .. } if value < min => value - min,
            Goal::Within { max, .. } if value > max => value - max,
            Goal::Within { .. } => 0.0,
        }
    }

    /// The target as a table shows it: `50`, `>= 0.5`, `<= 3`, `0.5 to 3`.
    pub fn describe(&self) -> String {
        let n = crate::error::num;
        match *self {
            Goal::Equal { target } => n(target),
            Goal::Within { min, max } if max == f64::INFINITY => format!(">= {}", n(min)),
            Goal::Within { min, max } if min == f64::NEG_INFINITY => format!("<= {}", n(max)),
            Goal::Within { min, max } => format!("{} to {}", n(min), n(max)),
        }
    }
}

/// One operand: a measure, its goal and its weight.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Operand {
    /// What is measured.
    #[serde(flatten)]
    pub measure: Measure,
    /// What it should be.
    pub goal: Goal,
    /// Its weight (>= 0).
    pub weight: f64,
}

impl Operand {
    /// The operand of `o` (the `index`-th of the file, from 0), checked
    /// against `spec` (surfaces exist, keys belong to the type, numbers
    /// are finite and meetable).
    pub fn from_spec(o: &OperandSpec, index: usize, spec: &PrescriptionSpec) -> Result<Operand, DesignError> {
        let what = format!("operand {} ({})", index + 1, o.kind);
        let bad = |why: String| DesignError::Operand { what: what.clone(), why };
        let uses: &[&str] = match o.kind.as_str() {
            "efl" | "f_number" | "back_focus" | "total_track" | "magnification" => &[],
            "rms_spot" => &["field_deg", "field_x_deg", "rings", "wavelength_nm"],
            "rms_wavefront" | "distortion" => &["field_deg", "field_x_deg", "wavelength_nm"],
            "mtf" => &["field_deg", "field_x_deg", "frequency_per_mm", "orientation", "wavelength_nm"],
            "ray_x" | "ray_y" => &["field_deg", "field_x_deg", "px", "py", "wavelength_nm"],
            "center_thickness" | "edge_thickness" => &["surface"],
            other => {
                return Err(bad(format!(
                    "unknown type \"{other}\": one of efl, f_number, back_focus, total_track, magnification, rms_spot, rms_wavefront, mtf, distortion, ray_x, ray_y, center_thickness, edge_thickness"
                )))
            }
        };
        let given = [
            ("field_deg", o.field_deg.is_some()),
            ("field_x_deg", o.field_x_deg.is_some()),
            ("surface", o.surface.is_some()),
            ("wavelength_nm", o.wavelength_nm.is_some() && o.kind != "distortion"),
            ("frequency_per_mm", o.frequency_per_mm.is_some()),
            ("orientation", o.orientation.is_some()),
            ("px", o.px.is_some()),
            ("py", o.py.is_some()),
            ("rings", o.rings.is_some()),
        ];
        if o.kind == "distortion" && o.wavelength_nm.is_some() {
            return Err(bad("distortion is the primary wavelength's: leave out \"wavelength_nm\"".into()));
        }
        if let Some((key, _)) = given.iter().find(|(k, g)| *g && !uses.contains(k)) {
            return Err(bad(format!("\"{key}\" does not apply to {}", o.kind)));
        }
        let finite = |name: &str, x: Option<f64>| -> Result<(), DesignError> {
            match x {
                Some(v) if !v.is_finite() => Err(bad(format!("\"{name}\" must be a finite number, not {v}"))),
                _ => Ok(()),
            }
        };
        for (name, x) in [
            ("target", o.target),
            ("min", o.min),
            ("max", o.max),
            ("weight", o.weight),
            ("field_deg", o.field_deg),
            ("field_x_deg", o.field_x_deg),
            ("wavelength_nm", o.wavelength_nm),
            ("frequency_per_mm", o.frequency_per_mm),
            ("px", o.px),
            ("py", o.py),
        ] {
            finite(name, x)?;
        }
        let (field_deg, field_x_deg) = (o.field_deg.unwrap_or(0.0), o.field_x_deg.unwrap_or(0.0));
        for (key, a) in [("field_deg", field_deg), ("field_x_deg", field_x_deg)] {
            if a.abs() >= 90.0 {
                return Err(bad(format!("{key} {a}: a field angle lies within +-90 deg of the axis")));
            }
        }
        if let Some(nm) = o.wavelength_nm {
            if nm <= 0.0 {
                return Err(bad(format!("wavelength {nm} nm: give a wavelength above 0")));
            }
        }
        let surface = |need_next: bool| -> Result<usize, DesignError> {
            let n = spec.surfaces.len();
            match o.surface {
                None => Err(bad("give \"surface\" (numbered from 1)".into())),
                Some(s) if s == 0 || s > n => Err(bad(format!("surface {s}: the prescription has surfaces 1 to {n}"))),
                Some(s) if need_next && s == n => Err(bad(format!(
                    "surface {s} is the last: the space after it reaches the image, which has no edge; give a surface before it"
                ))),
                Some(s) => Ok(s),
            }
        };
        let measure = match o.kind.as_str() {
            "efl" => Measure::Efl,
            "f_number" => Measure::FNumber,
            "back_focus" => Measure::BackFocus,
            "total_track" => Measure::TotalTrack,
            "magnification" => {
                if spec.object_distance_mm.is_none() {
                    return Err(bad("the prescription's object is at infinity (no \"object_distance_mm\"): magnification is 0 whatever the variables".into()));
                }
                Measure::Magnification
            }
            "rms_spot" => {
                let rings = o.rings.unwrap_or(12);
                if !(1..=200).contains(&rings) {
                    return Err(bad(format!("rings {rings}: give 1 to 200 Gauss rings")));
                }
                Measure::RmsSpot { field_deg, field_x_deg, rings, wavelength_nm: o.wavelength_nm }
            }
            "rms_wavefront" => Measure::RmsWavefront { field_deg, field_x_deg, wavelength_nm: o.wavelength_nm },
            "mtf" => {
                let frequency_per_mm = match o.frequency_per_mm {
                    Some(f) if f > 0.0 => f,
                    Some(f) => return Err(bad(format!("frequency {f} cycles/mm: give a frequency above 0"))),
                    None => return Err(bad("give \"frequency_per_mm\" (cycles/mm)".into())),
                };
                let orientation = match o.orientation.as_deref() {
                    None | Some("mean") => Orientation::Mean,
                    Some("tangential") => Orientation::Tangential,
                    Some("sagittal") => Orientation::Sagittal,
                    Some(x) => {
                        return Err(bad(format!("orientation \"{x}\": one of tangential, sagittal, mean")));
                    }
                };
                Measure::Mtf { field_deg, field_x_deg, frequency_per_mm, orientation, wavelength_nm: o.wavelength_nm }
            }
            "distortion" => Measure::Distortion { field_deg, field_x_deg },
            "ray_x" | "ray_y" => {
                let (px, py) = (o.px.unwrap_or(0.0), o.py.unwrap_or(0.0));
                if px * px + py * py > 1.0 + 1e-12 {
                    return Err(bad(format!("pupil point ({px}, {py}) lies outside the unit pupil")));
                }
                if o.kind == "ray_x" {
                    Measure::RayX { field_deg, field_x_deg, px, py, wavelength_nm: o.wavelength_nm }
                } else {
                    Measure::RayY { field_deg, field_x_deg, px, py, wavelength_nm: o.wavelength_nm }
                }
            }
            "center_thickness" => Measure::CenterThickness { surface: surface(false)? },
            "edge_thickness" => {
                let s = surface(true)?;
                let (a, b) = (&spec.surfaces[s - 1], &spec.surfaces[s]);
                if a.semi_diameter.is_none() && b.semi_diameter.is_none() {
                    return Err(bad(format!(
                        "surfaces {s} and {} have no semi_diameter: the edge is where the larger one ends; give one",
                        s + 1
                    )));
                }
                Measure::EdgeThickness { surface: s }
            }
            _ => unreachable!("the kinds are matched above"),
        };
        let goal = match (o.target, o.relation.as_deref(), o.min, o.max) {
            (Some(_), _, Some(_), _) | (Some(_), _, _, Some(_)) => {
                return Err(bad("give either \"target\" (with \"kind\") or \"min\" / \"max\", not both".into()));
            }
            (None, Some(_), _, _) => return Err(bad("\"kind\" needs a \"target\"".into())),
            (Some(t), None | Some("="), _, _) => Goal::Equal { target: t },
            (Some(t), Some("<"), _, _) => Goal::Within { min: f64::NEG_INFINITY, max: t },
            (Some(t), Some(">"), _, _) => Goal::Within { min: t, max: f64::INFINITY },
            (Some(_), Some(k), _, _) => return Err(bad(format!("kind \"{k}\": one of \"=\", \"<\", \">\""))),
            (None, None, Some(a), Some(b)) if a > b => return Err(bad(format!("min {a} is above max {b}"))),
            (None, None, min, max) if min.is_some() || max.is_some() => {
                Goal::Within { min: min.unwrap_or(f64::NEG_INFINITY), max: max.unwrap_or(f64::INFINITY) }
            }
            (None, None, _, _) => match measure {
                Measure::RmsSpot { .. } | Measure::RmsWavefront { .. } | Measure::Distortion { .. } => {
                    Goal::Equal { target: 0.0 }
                }
                Measure::Mtf { .. } => Goal::Equal { target: 1.0 },
                _ => return Err(bad("give a \"target\" (or \"min\" / \"max\")".into())),
            },
        };
        meetable(&measure, &goal).map_err(bad)?;
        let weight = o.weight.unwrap_or(1.0);
        if weight < 0.0 {
            return Err(bad(format!("weight {weight}: give a weight of 0 or more")));
        }
        Ok(Operand { measure, goal, weight })
    }

    /// The operand's type as the design file writes it.
    pub fn name(&self) -> &'static str {
        match self.measure {
            Measure::Efl => "efl",
            Measure::FNumber => "f_number",
            Measure::BackFocus => "back_focus",
            Measure::TotalTrack => "total_track",
            Measure::Magnification => "magnification",
            Measure::RmsSpot { .. } => "rms_spot",
            Measure::RmsWavefront { .. } => "rms_wavefront",
            Measure::Mtf { .. } => "mtf",
            Measure::Distortion { .. } => "distortion",
            Measure::RayX { .. } => "ray_x",
            Measure::RayY { .. } => "ray_y",
            Measure::CenterThickness { .. } => "center_thickness",
            Measure::EdgeThickness { .. } => "edge_thickness",
        }
    }

    /// Where it is measured, for tables: `field 14 deg`, `surface 2`.
    pub fn place(&self) -> String {
        let f = crate::error::num;
        let field = |x: f64, y: f64| match x {
            0.0 => format!("field {} deg", f(y)),
            _ => format!("field x {} deg, y {} deg", f(x), f(y)),
        };
        match self.measure {
            Measure::RmsSpot { field_deg, field_x_deg, .. }
            | Measure::RmsWavefront { field_deg, field_x_deg, .. }
            | Measure::Distortion { field_deg, field_x_deg } => field(field_x_deg, field_deg),
            Measure::Mtf { field_deg, field_x_deg, frequency_per_mm, orientation, .. } => {
                let o = match orientation {
                    Orientation::Tangential => " T",
                    Orientation::Sagittal => " S",
                    Orientation::Mean => "",
                };
                format!("{}, {}/mm{o}", field(field_x_deg, field_deg), f(frequency_per_mm))
            }
            Measure::RayX { field_deg, field_x_deg, px, py, .. }
            | Measure::RayY { field_deg, field_x_deg, px, py, .. } => {
                format!("{}, pupil ({}, {})", field(field_x_deg, field_deg), f(px), f(py))
            }
            Measure::CenterThickness { surface } | Measure::EdgeThickness { surface } => format!("surface {surface}"),
            _ => String::new(),
        }
    }
}

/// Refuses goals no lens can meet.
fn meetable(m: &Measure, g: &Goal) -> Result<(), String> {
    let (lo, hi) = match *g {
        Goal::Equal { target } => (target, target),
        Goal::Within { min, max } => (min, max),
    };
    let never = |why: &str| Err(format!("{} {why}", g.describe()));
    match m {
        Measure::Efl if lo == 0.0 && hi == 0.0 => never("mm: a focal length of 0 is no lens"),
        Measure::FNumber if hi < 0.5 => {
            never("is faster than f/0.5, the limit of any lens in air (sin of the image-space angle <= 1)")
        }
        Measure::RmsSpot { .. } | Measure::RmsWavefront { .. } if hi < 0.0 => {
            never("is below 0: an RMS is never negative")
        }
        Measure::Mtf { .. } if lo > 1.0 || hi < 0.0 => never("lies outside 0 to 1, where an MTF lies"),
        Measure::CenterThickness { .. } | Measure::EdgeThickness { .. } if hi < 0.0 => {
            never("mm is negative: surfaces would cross")
        }
        _ => Ok(()),
    }
}

/// Why an operand has no value.
enum Why {
    Optics(OpticsError),
    Edge(String),
}

impl From<OpticsError> for Why {
    fn from(e: OpticsError) -> Self {
        Why::Optics(e)
    }
}

impl From<crate::glass::GlassError> for Why {
    fn from(e: crate::glass::GlassError) -> Self {
        Why::Optics(e.into())
    }
}

/// A candidate lens ready to be measured: the prescription at its primary
/// wavelength, its first-order data, and its file form (for thicknesses).
pub struct Candidate<'a> {
    /// The validated lens.
    pub lens: &'a Prescription,
    /// Its first-order data.
    pub first: FirstOrder,
    /// The prescription as written.
    pub spec: &'a PrescriptionSpec,
    /// The merit function's wavelengths and weights, nm.
    pub waves: &'a [(f64, f64)],
}

impl Candidate<'_> {
    /// The value of `m` for this lens, or why it has none.
    pub fn measure(&self, m: &Measure) -> Result<f64, String> {
        self.value(m).map_err(|e| match e {
            Why::Optics(e) => e.to_string(),
            Why::Edge(s) => s,
        })
    }

    fn value(&self, m: &Measure) -> Result<f64, Why> {
        let p = self.lens;
        let field = |x: f64, y: f64| Field::at_angles(p, &self.first, x, y);
        let launcher = |x: f64, y: f64| Launcher::with_first(p, &self.first, field(x, y), Aim::Auto);
        let at = |nm: Option<f64>| -> Result<Prescription, Why> {
            Ok(p.at_wavelength(nm.unwrap_or(p.primary_wavelength_nm()))?)
        };
        match *m {
            Measure::Efl => Ok(self.first.efl),
            Measure::FNumber => Ok(self.first.f_number),
            Measure::BackFocus => Ok(self.first.bfl),
            Measure::TotalTrack => Ok(p.total_track()),
            Measure::Magnification => {
                let object = crate::paraxial::ObjectDistance::from_mm(p.object_distance_mm().unwrap_or(f64::INFINITY))?;
                Ok(imaging(p, &self.first, object)?.magnification)
            }
            Measure::RmsSpot { field_deg, field_x_deg, rings, wavelength_nm } => {
                let l = launcher(field_x_deg, field_deg)?;
                let one;
                let waves = match wavelength_nm {
                    Some(nm) => {
                        one = [(nm, 1.0)];
                        &one[..]
                    }
                    None => self.waves,
                };
                Ok(spot_polychromatic(p, &l, Pattern::Gauss, rings, ImagePlane::ImageSurface, waves)?.rms_radius)
            }
            Measure::RmsWavefront { field_deg, field_x_deg, wavelength_nm } => {
                let l = launcher(field_x_deg, field_deg)?;
                let w = wavefront_auto(p, &at(wavelength_nm)?, &l, ImagePlane::ImageSurface)?;
                Ok(stats::rms_to_centroid(&w))
            }
            Measure::Mtf { field_deg, field_x_deg, frequency_per_mm, orientation, wavelength_nm } => {
                let q = at(wavelength_nm)?;
                let l = launcher(field_x_deg, field_deg)?;
                let m = mtf::mtf(p, &q, &l, ImagePlane::ImageSurface, &[frequency_per_mm])?;
                Ok(match orientation {
                    Orientation::Tangential => m.tangential[0],
                    Orientation::Sagittal => m.sagittal[0],
                    Orientation::Mean => 0.5 * (m.tangential[0] + m.sagittal[0]),
                })
            }
            Measure::Distortion { field_deg, field_x_deg } => {
                Ok(curves::distortion(p, field(field_x_deg, field_deg), Aim::Auto)?)
            }
            Measure::RayX { field_deg, field_x_deg, px, py, wavelength_nm }
            | Measure::RayY { field_deg, field_x_deg, px, py, wavelength_nm } => {
                let q = at(wavelength_nm)?;
                let l = launcher(field_x_deg, field_deg)?;
                let tracer = Tracer::forward_to_film(&q, p.film_distance());
                let landing = Bundle::trace(&l, &tracer, vec![(px, py)])?;
                let ray = landing.landings[0].reached().ok_or_else(|| OpticsError::NoRealRays {
                    why: format!("the ray through pupil ({px}, {py}) at {} is blocked", l.field().describe()),
                })?;
                Ok(if matches!(m, Measure::RayX { .. }) { ray.origin.x } else { ray.origin.y })
            }
            Measure::CenterThickness { surface } => Ok(self.spec.surfaces[surface - 1].thickness),
            Measure::EdgeThickness { surface } => {
                let (a, b) = (&self.spec.surfaces[surface - 1], &self.spec.surfaces[surface]);
                let h = a.semi_diameter.unwrap_or(0.0).max(b.semi_diameter.unwrap_or(0.0));
                let sag = |s: &crate::SurfaceSpec, which: usize| {
                    s.sag(h).ok_or_else(|| {
                        Why::Edge(format!(
                            "surface {which} does not reach the height {} mm of the pair's larger semi-diameter (its sphere is smaller): reduce the semi-diameter or the curvature",
                            crate::error::num(h)
                        ))
                    })
                };
                Ok(a.thickness + sag(b, surface + 1)? - sag(a, surface)?)
            }
        }
    }
}
