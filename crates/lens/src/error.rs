//! Typed errors of the library. Each message says what to change.

use crate::validate::Finding;
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

/// Why a first-order (paraxial) or focusing computation has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpticsError {
    /// The system has no optical power (afocal): no focal length or focus.
    #[error("the system is afocal (zero optical power): it has no focal length, focal points or focus")]
    Afocal,
    /// The object is at (or numerically at) the front focal plane, so the image
    /// is at infinity and no film distance focuses it.
    #[error("object at {object_distance} mm is at the front focal plane (front focal distance {ffd} mm): its image is at infinity; move the object away from the focal plane")]
    ImageAtInfinity {
        /// Object distance in mm in front of the first vertex.
        object_distance: f64,
        /// Signed front focal distance (z of the front focal point), mm.
        ffd: f64,
    },
    /// The image is virtual or lies before the last vertex: no film can record it.
    #[error("object at {object_distance} mm forms no real image behind the last surface (image distance {image_distance} mm from the last vertex); move the object beyond the front focal point (z < {ffd} mm)")]
    NoRealImage {
        /// Object distance in mm in front of the first vertex.
        object_distance: f64,
        /// Paraxial image distance from the last vertex (<= 0), mm.
        image_distance: f64,
        /// Signed front focal distance, mm.
        ffd: f64,
    },
    /// No real object is in focus for this film distance.
    #[error("film distance {film_distance} mm brings no real object into focus (the rear focal point is {bfl} mm behind the last vertex); use a film distance of at least the back focal length")]
    NoRealObject {
        /// Film distance from the last vertex, mm.
        film_distance: f64,
        /// Back focal length, mm.
        bfl: f64,
    },
    /// An input value is out of its domain.
    #[error("{name} = {value}: {expected}")]
    BadInput {
        /// The argument's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is accepted.
        expected: &'static str,
    },
    /// The stop is imaged at infinity on one side (telecentric), so that pupil
    /// has no finite position.
    #[error("the {which} pupil is at infinity (the system is telecentric in {which} space)")]
    PupilAtInfinity {
        /// `"entrance"` or `"exit"`.
        which: &'static str,
    },
    /// Real-ray aiming did not converge on the requested stop point.
    #[error("real aiming did not converge for pupil point ({px}, {py}) at {field}: {why}; try --aim paraxial or a smaller field")]
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
    /// No real ray of the on-axis bundle reaches the film.
    #[error("no real ray of the on-axis bundle reaches the film: {why}")]
    NoRealRays {
        /// What blocked the bundle.
        why: String,
    },
}
