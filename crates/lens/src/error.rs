//! Typed errors of the library. Each message says what to change.

use crate::model::Finding;
use std::path::PathBuf;

/// Why a prescription could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// File that failed.
        path: PathBuf,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// The JSON is malformed or has a field of the wrong type, an unknown field
    /// or a missing one. `line` and `column` are 1-based, as serde reports them.
    #[error("{origin}: line {line}, column {column}: {message}")]
    Json {
        /// File name or `<string>`.
        origin: String,
        /// 1-based line of the problem.
        line: usize,
        /// 1-based column of the problem.
        column: usize,
        /// serde's description.
        message: String,
    },
    /// A pbrt `.dat` file has a line that is not four numbers.
    #[error("{origin}: line {line}: {message}")]
    Dat {
        /// File name or `<string>`.
        origin: String,
        /// 1-based line of the problem.
        line: usize,
        /// What is wrong and what to change.
        message: String,
    },
    /// A Zemax file has something that cannot be read or is not supported.
    #[error("{origin}: {}{message}", if *line > 0 { format!("line {line}: ") } else { String::new() })]
    Zemax {
        /// File name.
        origin: String,
        /// 1-based line (0: the file as a whole).
        line: usize,
        /// What is wrong and what to change.
        message: String,
    },
    /// A CODE V `.seq` file has something that cannot be read or is not
    /// supported.
    #[error("{origin}: {}{message}", if *line > 0 { format!("line {line}: ") } else { String::new() })]
    CodeV {
        /// File name.
        origin: String,
        /// 1-based line (0: the file as a whole).
        line: usize,
        /// What is wrong and what to change.
        message: String,
    },
    /// A glass catalogue the file names cannot be read.
    #[error("{origin}: glass_catalogs: {source}")]
    Glass {
        /// The prescription file.
        origin: String,
        /// What is wrong with the catalogue.
        source: crate::glass::GlassError,
    },
    /// The file parsed, but the prescription is not physically valid.
    #[error("{origin}: invalid prescription:\n{}", list(findings))]
    Invalid {
        /// File name or `<string>`.
        origin: String,
        /// Every finding (errors and warnings).
        findings: Vec<Finding>,
    },
}

fn list(findings: &[Finding]) -> String {
    findings.iter().map(|f| format!("  {f}")).collect::<Vec<_>>().join("\n")
}

/// A length or number for a message: up to 6 significant digits, in
/// scientific notation when very large or small, `infinity` for infinity.
pub fn num(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 { "infinity".into() } else { "-infinity".into() };
    }
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if (1e-4..1e7).contains(&a) {
        let digits = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.4e}")
    }
}

/// A number as given, for echoing a user's value in a message: its
/// shortest exact form (`706.5188`, `0.1`), in scientific notation when
/// very large or small (`1e308`, not 309 digits), so never more than 17
/// significant digits; `infinity` for infinity.
pub fn exact(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 { "infinity".into() } else { "-infinity".into() };
    }
    if x == 0.0 || !x.is_finite() || (1e-4..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A number in a text report: printed as `f64` prints it (width,
/// precision, `+` and alignment honoured: `{:>14.6}`) while it is below
/// 1e9 in size, in scientific notation of the same precision above (1e308
/// is `1.000000e308`, not 309 digits); without a precision, as [`exact`]
/// (so 1e-300 is not 300 zeros).
///
/// ```
/// use lens::error::Fixed;
/// assert_eq!(format!("{:.3}", Fixed(2.5)), "2.500");
/// assert_eq!(format!("{:>12.2}", Fixed(1e308)), "    1.00e308");
/// assert_eq!(format!("{}", Fixed(1e-300)), "1e-300");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixed(pub f64);

impl std::fmt::Display for Fixed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        let s = match f.precision() {
            Some(p) if x.is_finite() && x.abs() >= 1e9 => {
                if f.sign_plus() {
                    format!("{x:+.p$e}")
                } else {
                    format!("{x:.p$e}")
                }
            }
            Some(_) => return std::fmt::Display::fmt(&x, f),
            None if f.sign_plus() && x >= 0.0 => format!("+{}", exact(x)),
            None => exact(x),
        };
        let pad = f.width().unwrap_or(0).saturating_sub(s.chars().count());
        let (before, after) = match f.align() {
            Some(std::fmt::Alignment::Left) => (0, pad),
            Some(std::fmt::Alignment::Center) => (pad / 2, pad - pad / 2),
            _ => (pad, 0),
        };
        write!(f, "{}{s}{}", " ".repeat(before), " ".repeat(after))
    }
}

/// A surface's clear aperture in words: its semi-diameter, or that it has
/// none (a ray then stops there only by missing the surface or by total
/// internal reflection).
pub fn clear_aperture(semi_diameter: Option<f64>) -> String {
    match semi_diameter {
        Some(sd) => format!("semi-diameter {} mm", num(sd)),
        None => "no clear aperture given: the rays miss the surface or are totally reflected there".into(),
    }
}

fn object(d: &Option<f64>) -> String {
    match d {
        Some(d) => format!("object at {} mm", num(*d)),
        None => "object at infinity".into(),
    }
}

/// Why a first-order (paraxial) or focusing computation has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpticsError {
    /// A glass has no index at a wavelength asked for.
    #[error(transparent)]
    Glass(#[from] crate::glass::GlassError),
    /// The system has no optical power (afocal): no focal length or focus.
    #[error("the system is afocal (zero optical power): it has no focal length, focal points or focus")]
    Afocal,
    /// The object is at (or within a millionth of a focal length of) the
    /// front focal plane, so the image is at infinity and no film distance
    /// focuses it.
    #[error("the object at {} mm is at the front focal plane (front focal point at z = {} mm): its image is at infinity; move the object away from the focal plane", num(*object_distance), num(*ffd))]
    ImageAtInfinity {
        /// Object distance in mm in front of the first vertex.
        object_distance: f64,
        /// Signed front focal distance (z of the front focal point), mm.
        ffd: f64,
    },
    /// The image is virtual or lies before the last vertex: no film can record it.
    #[error("{}: {}", object(object_distance), no_real_image(*image_distance, *ffd, *efl))]
    NoRealImage {
        /// Object distance in mm in front of the first vertex (`None`:
        /// infinity).
        object_distance: Option<f64>,
        /// Paraxial image distance from the last vertex (<= 0), mm.
        image_distance: f64,
        /// Signed front focal distance, mm.
        ffd: f64,
        /// Effective focal length, mm.
        efl: f64,
    },
    /// The real rays of an object focus nowhere a film can be: their least
    /// RMS spot lies at or before the last vertex (an object just beyond
    /// the front focal point, whose paraxial image is far away while the
    /// real bundle is wildly aberrated).
    #[error("{}: its paraxial image is {} mm behind the last vertex, but the real rays' best focus is at {} mm, not behind the lens; move the object farther from the front focal point", object(object_distance), num(*film_distance), num(*best_focus))]
    NoRealFocus {
        /// Object distance in mm in front of the first vertex (`None`:
        /// infinity).
        object_distance: Option<f64>,
        /// Paraxial film distance, mm.
        film_distance: f64,
        /// Film distance of least RMS spot, mm (<= 0).
        best_focus: f64,
    },
    /// No real object is in focus for this film distance.
    #[error("a film {} mm behind the last vertex brings no real object into focus: {}", num(*film_distance), no_real_object(*film_distance, *bfl))]
    NoRealObject {
        /// Film distance from the last vertex, mm.
        film_distance: f64,
        /// Back focal length, mm.
        bfl: f64,
    },
    /// An input value is out of its domain.
    #[error("{name} = {}: expected {expected}", num(*value))]
    BadInput {
        /// The argument's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// An f-number faster than the clear apertures let through.
    #[error("f/{} is faster than the clear apertures allow: surface {surface} ({}) limits the on-axis bundle to f/{}; ask for f/{} or slower, or enlarge that surface's semi_diameter", num(*asked), clear_aperture(*semi_diameter), num(*fastest), num(*fastest))]
    FNumberTooFast {
        /// The f-number asked for.
        asked: f64,
        /// The fastest paraxial f-number the clear apertures allow.
        fastest: f64,
        /// 1-based number of the limiting surface.
        surface: usize,
        /// Its semi-diameter, mm (`None`: it has none, and the rays miss it
        /// or are totally reflected there).
        semi_diameter: Option<f64>,
    },
    /// A prescription changed by a command (a resized stop) is no longer
    /// valid.
    #[error("the resized stop makes the prescription invalid: {findings}")]
    Resized {
        /// The validation errors, in words.
        findings: String,
    },
    /// A focus distance (measured from the film) nearer than the lens can
    /// focus, or inside the lens.
    #[error("a plane {} mm in front of the film cannot be focused: the lens and film span {} mm and a lens focuses no nearer than about 4 focal lengths from the film; focus farther away", num(*distance), num(*lens_length))]
    FocusTooNear {
        /// Distance from the film, mm.
        distance: f64,
        /// First vertex to film, mm, at the last focus tried.
        lens_length: f64,
    },
    /// The focus group cannot move that far: a gap beside it would close.
    #[error("the focus group cannot move {} mm: the gaps before and after it are {} and {} mm; focus farther away", num(*shift), num(*before), num(*after))]
    FocusGroupTravel {
        /// The shift asked for, mm toward the image.
        shift: f64,
        /// The gap before the group, mm, as designed.
        before: f64,
        /// The gap after the group, mm, as designed.
        after: f64,
    },
    /// The stop is imaged at infinity on one side (telecentric), so that pupil
    /// has no finite position.
    #[error("the {which} pupil is at infinity (the system is telecentric in {which} space)")]
    PupilAtInfinity {
        /// `"entrance"` or `"exit"`.
        which: &'static str,
    },
    /// Real-ray aiming did not converge on the requested stop point.
    #[error("real aiming did not converge for pupil point ({}, {}) at {field}: {why}; try --aim paraxial or a smaller field", num(*px), num(*py))]
    AimingFailed {
        /// Normalised pupil x.
        px: f64,
        /// Normalised pupil y.
        py: f64,
        /// The field, in words.
        field: String,
        /// What went wrong.
        why: String,
    },
    /// The chief ray of a field does not reach the image plane.
    #[error("the chief ray at {field} does not reach the image: {why}")]
    ChiefRayLost {
        /// The field, in words.
        field: String,
        /// Its outcome, in words.
        why: String,
    },
    /// An analysis that relies on the lens being symmetric about its axis
    /// was asked of a lens with decentred or tilted surfaces.
    #[error("{analysis} assumes a lens symmetric about its axis, and this one has decentred or tilted surfaces: use the fans, spots and wave analyses, which trace the moved surfaces, or remove the motions")]
    NotCoaxial {
        /// The analysis, in words.
        analysis: &'static str,
    },
    /// A field with an x component was given where only fields along y
    /// are defined.
    #[error("{what} is defined for fields along y only, and {field} has an x component: give the field in y (a lens symmetric about its axis images an x field as the y field of the same angle, turned)")]
    YFieldOnly {
        /// What is y-only, in words.
        what: &'static str,
        /// The field, in words.
        field: String,
    },
    /// No real ray of the on-axis bundle reaches the film.
    #[error("no real ray reaches the image: {why}")]
    NoRealRays {
        /// What blocked the bundle.
        why: String,
    },
    /// A pupil grid too coarse for the wavefront: neighbouring samples
    /// differ by more than half a wave, so maps, fits and PSFs would alias.
    #[error("the wavefront at {field} changes by {} waves between neighbouring samples of the {grid} x {grid} pupil grid (more than half a wave, so its map, fits and PSF would alias); sample the pupil with a grid of at least {suggest}", num(*waves))]
    PupilUndersampled {
        /// The field, in words.
        field: String,
        /// The grid width used.
        grid: usize,
        /// The largest step between neighbouring samples, waves.
        waves: f64,
        /// A grid width that keeps the step under half a wave.
        suggest: usize,
    },
}

fn no_real_image(image_distance: f64, ffd: f64, efl: f64) -> String {
    if efl < 0.0 {
        return format!(
            "a diverging system (EFL {} mm) forms only virtual images of real objects (image {} mm from the last vertex); no film can record it",
            num(efl),
            num(image_distance)
        );
    }
    format!(
        "the image is virtual or in front of the last vertex ({} mm from it); move the object beyond the front focal point (farther than {} mm in front of the first vertex)",
        num(image_distance),
        num(-ffd)
    )
}

fn no_real_object(film: f64, bfl: f64) -> String {
    if film < bfl {
        format!("the rear focal point is {} mm behind the last vertex; use a film distance of at least that", num(bfl))
    } else {
        format!("the rear focal point is {} mm behind the last vertex", num(bfl))
    }
}
