//! Circle of confusion: the real blur of defocused on-axis points, beside the
//! thin-lens prediction.

use crate::analysis::focus::AxialBundle;
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::focus::film_distance_with;
use crate::paraxial::{FirstOrder, ObjectDistance};
use serde::Serialize;

/// The blur of one object distance on the film.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CocRow {
    /// Object distance S2, mm in front of the first vertex (`None` =
    /// infinity).
    pub distance: Option<f64>,
    /// Geometric (full) blur diameter on the film, mm.
    pub geo_diameter: f64,
    /// RMS blur diameter (twice the RMS radius), mm.
    pub rms_diameter: f64,
    /// Thin-lens prediction C = A |S2 - S1| / S2 * f / (S1 - f), mm, with
    /// f = EFL and A = entrance-pupil diameter.
    pub thin_lens_diameter: f64,
    /// Fraction of the entrance-pupil radius whose rays pass (1 = none
    /// vignetted).
    pub pupil_fill: f64,
}

/// A circle-of-confusion table for a lens focused at S1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CocTable {
    /// Focus distance S1, mm in front of the first vertex (`None` =
    /// infinity).
    pub focus_distance: Option<f64>,
    /// Film distance that focuses S1 exactly (paraxial), mm behind the last
    /// vertex.
    pub film_distance: f64,
    /// EFL used by the thin-lens formula, mm.
    pub efl: f64,
    /// Entrance-pupil diameter used by the thin-lens formula, mm.
    pub entrance_pupil_diameter: f64,
    /// z of the entrance pupil, mm from the first vertex: the thin-lens
    /// formula treats it as if it were at the first vertex.
    pub entrance_pupil_z: f64,
    /// One row per object distance.
    pub rows: Vec<CocRow>,
}

/// Focuses `p` on an object `s1` mm away (`f64::INFINITY` for infinity; film
/// solved exactly) and measures
/// the real blur of on-axis objects at `distances` (mm; `f64::INFINITY` for
/// infinity) from a full-aperture bundle: geometric diameter from a dense
/// meridional fan, RMS diameter by Gauss–Legendre quadrature over the pupil.
pub fn circle_of_confusion(p: &Prescription, s1: f64, distances: &[f64]) -> Result<CocTable, OpticsError> {
    let focus = ObjectDistance::from_mm(s1).map_err(|_| OpticsError::BadInput {
        name: "focus distance",
        value: s1,
        expected: "a positive distance in mm in front of the first vertex, or infinity",
    })?;
    let first = FirstOrder::of(p)?;
    let film = film_distance_with(p, &first, focus)?;
    let (f, a) = (first.efl, first.entrance_pupil.diameter);
    let mut rows = Vec::with_capacity(distances.len());
    for &s2 in distances {
        let object = ObjectDistance::from_mm(s2)?;
        let bundle = AxialBundle::trace(p, &first, object, film)?;
        // C = A |S2 - S1| / S2 * f / (S1 - f), and its limits at infinity
        let thin = match (focus, object) {
            (ObjectDistance::Finite(s1), ObjectDistance::Infinity) => a * f / (s1 - f),
            (ObjectDistance::Finite(s1), ObjectDistance::Finite(s2)) => a * (s2 - s1).abs() / s2 * f / (s1 - f),
            (ObjectDistance::Infinity, ObjectDistance::Finite(s2)) => a * f / s2,
            (ObjectDistance::Infinity, ObjectDistance::Infinity) => 0.0,
        };
        rows.push(CocRow {
            distance: match object {
                ObjectDistance::Infinity => None,
                ObjectDistance::Finite(d) => Some(d),
            },
            geo_diameter: 2.0 * bundle.geo_radius,
            rms_diameter: 2.0 * bundle.rms_at(0.0),
            thin_lens_diameter: thin.abs(),
            pupil_fill: bundle.fill,
        });
    }
    Ok(CocTable {
        focus_distance: match focus {
            ObjectDistance::Infinity => None,
            ObjectDistance::Finite(d) => Some(d),
        },
        film_distance: film,
        efl: f,
        entrance_pupil_diameter: a,
        entrance_pupil_z: first.entrance_pupil.z,
        rows,
    })
}
