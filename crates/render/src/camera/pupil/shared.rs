//! Exit-pupil bounds shared by the frames of a sequence (see the module
//! above: several films, one set of coordinates).

use super::PupilTables;
use crate::camera::aperture::Aperture;
use lens::Prescription;
use std::sync::Arc;

/// A spectral render samples at most 360-830 nm, within the glasses'
/// data: the pupil bounds hold both ends (none for a lens without glasses).
pub(crate) fn bounded_ends(p: &Prescription) -> Vec<f64> {
    if !p.is_dispersive() {
        return vec![];
    }
    let (lo, hi) = crate::spectrum::cie::range_through(p.glasses());
    if lo < hi {
        vec![lo, hi]
    } else {
        vec![]
    }
}

/// Exit-pupil bounds made once for a frame sequence's films: every frame
/// of a focus pull draws its samples from the same regions, so a sample's
/// aperture uniforms aim it alike in every frame and the noise pattern
/// stays put. The bounds hold the passing targets of films at the range's
/// ends and middle, grown (as for the film radii between a bin's probed
/// radii) by a quarter of their spread.
#[derive(Debug, Clone)]
pub struct SharedPupil {
    pub(crate) tables: Arc<PupilTables>,
    /// The film the bounds' coordinates belong to, and the paraxial exit
    /// pupil (z, mm from the first vertex).
    pub(crate) z_ref: f64,
    pub(crate) z_xp: Option<f64>,
    /// The films bounded, mm behind the last vertex (least, greatest).
    films_mm: (f64, f64),
    /// What the bounds were made for: the lens's stop, the sensor, the
    /// aperture shape.
    stop_sd: f64,
    sensor: [f64; 2],
    aperture: Aperture,
    /// The lens's spacings but the last (a moved focus group changes two).
    spacings: Vec<f64>,
}

impl SharedPupil {
    /// Bounds for `p` (as the camera gets it, before focusing) with films
    /// from `films_mm.0` to `films_mm.1` mm behind its last vertex.
    pub fn new(p: &Prescription, aperture: &Aperture, sensor: [f64; 2], films_mm: (f64, f64)) -> Self {
        let (lo, hi) = (films_mm.0.min(films_mm.1), films_mm.0.max(films_mm.1));
        let z = p.last_vertex_z();
        let z_films = [z + lo, z + 0.5 * (lo + hi), z + hi];
        let z_ref = z_films[1];
        let z_xp = lens::paraxial::FirstOrder::of(p).ok().and_then(|f| f.exit_pupil).map(|x| x.z);
        let half_diag = 0.5 * (sensor[0].hypot(sensor[1]));
        let tables = PupilTables::build(p, aperture, &z_films, z_ref, z, half_diag, &bounded_ends(p));
        SharedPupil {
            z_ref,
            z_xp,
            tables: Arc::new(tables),
            films_mm: (lo, hi),
            stop_sd: p.stop_semi_diameter(),
            sensor,
            aperture: aperture.clone(),
            spacings: spacings(p),
        }
    }

    /// Whether these bounds serve a camera of `p`, `aperture` and `sensor`
    /// with its film `film_mm` behind the last vertex.
    pub(crate) fn holds(&self, p: &Prescription, aperture: &Aperture, sensor: [f64; 2], film_mm: f64) -> bool {
        let slack = 1e-9 * film_mm.abs().max(1.0);
        p.stop_semi_diameter() == self.stop_sd
            && spacings(p) == self.spacings
            && sensor == self.sensor
            && *aperture == self.aperture
            && film_mm >= self.films_mm.0 - slack
            && film_mm <= self.films_mm.1 + slack
    }
}

/// A lens's spacings, all but the film's.
fn spacings(p: &Prescription) -> Vec<f64> {
    let s = p.surfaces();
    s[..s.len() - 1].iter().map(|x| x.thickness).collect()
}
