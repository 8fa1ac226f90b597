//! The paraxial ghost list: each two-reflection ghost's focus, height and
//! blur on the image plane, and its irradiance relative to the primary
//! image's, from the y-nu trace along the ghost's path.
//!
//! Along a path that turns back, indices carry the direction of travel:
//! N = n travelling +z, -n travelling -z. Refraction (and reflection, N' =
//! -N) is then one rule, `N' u' = N u - y c (N' - N)`, with `u = dy/dz`
//! the slope in the global frame and transfer `y += u (z' - z)` between
//! vertices; an ideal surface bends by `N' u' = N u - y n / f` either way.

use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::FirstOrder;
use serde::Serialize;

/// One ghost of the list (`lens ghosts --json`: `ghosts: [...]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GhostFocus {
    /// The two surfaces, numbered from 1, i < j: light reflects at j, then
    /// at i.
    pub surfaces: [usize; 2],
    /// Where the ghost's paraxial marginal ray (object at infinity, from
    /// the entrance pupil's rim) crosses the axis after leaving the lens,
    /// z in mm from the first vertex; `None` (null) when it leaves parallel
    /// (the ghost is afocal).
    pub focus_z_mm: Option<f64>,
    /// The ghost's paraxial chief ray (through the entrance pupil's centre
    /// at the field angle) on the image plane (the film), mm; the primary
    /// image's is `FirstOrder`'s.
    pub image_height_mm: f64,
    /// The ghost's marginal-ray radius on the image plane, mm: the radius
    /// of its blur disc for a point source.
    pub radius_mm: f64,
    /// The ghost's irradiance relative to the primary image's for a
    /// uniformly bright scene (light entering the whole entrance pupil from
    /// every direction): `R_i R_j (T_ghost / T_primary) (h / h_g)^2`, with
    /// R and T the surfaces' reflectances and transmittances at normal
    /// incidence and the primary wavelength (coatings included), and h,
    /// h_g the primary's and the ghost's image heights per unit field
    /// slope. `None` (null) where the ghost images every field point to
    /// the same place (h_g = 0: its irradiance then depends on the scene's
    /// extent).
    pub intensity: Option<f64>,
    /// R_i R_j, the two reflectances at normal incidence and the primary
    /// wavelength.
    pub reflectance: f64,
}

/// One event of a path: a surface met at its vertex z, travelling from
/// signed index `n` into signed index `n2`, with paraxial power `phi`.
#[derive(Debug, Clone, Copy)]
struct Event {
    z: f64,
    n: f64,
    n2: f64,
    phi: f64,
}

/// The events of the path through `p` that reflects at `reflect` = (j,
/// i) (0-based; `None`: the primary path), with the fraction of power
/// the path keeps at normal incidence at `nm` (coatings included).
fn events(p: &Prescription, reflect: Option<(usize, usize)>, nm: f64) -> (Vec<Event>, f64) {
    let s = p.surfaces();
    let z = p.vertex_z();
    let mut out = Vec::new();
    let mut keep = 1.0;
    // one surface k met travelling +z (`forward`), refracted or reflected
    let mut meet = |k: usize, forward: bool, reflect: bool| {
        let (nb, na) = (p.index_before(k), s[k].ior);
        let (from, to) = if forward { (nb, na) } else { (na, nb) };
        let sign = if forward { 1.0 } else { -1.0 };
        let n = sign * from;
        let n2 = if reflect { -n } else { sign * to };
        let phi = match s[k].paraxial {
            Some(f) => from / f,
            None => s[k].vertex_curvature() * (n2 - n),
        };
        if from != to && s[k].paraxial.is_none() {
            let r = p.coating(k).reflectance(from, to, 1.0, nm, !forward);
            keep *= if reflect { r } else { 1.0 - r };
        }
        out.push(Event { z: z[k], n, n2, phi });
    };
    match reflect {
        None => (0..s.len()).for_each(|k| meet(k, true, false)),
        Some((j, i)) => {
            (0..j).for_each(|k| meet(k, true, false));
            meet(j, true, true);
            (i + 1..j).rev().for_each(|k| meet(k, false, false));
            meet(i, false, true);
            (i + 1..s.len()).for_each(|k| meet(k, true, false));
        }
    }
    (out, keep)
}

/// The ray of height `y` and slope `u` at the first vertex carried along
/// `events`: its height and slope after the last (at the last event's z).
fn carry(events: &[Event], mut y: f64, mut u: f64) -> (f64, f64) {
    let mut z = 0.0;
    for e in events {
        y += u * (e.z - z);
        z = e.z;
        u = (e.n * u - y * e.phi) / e.n2;
    }
    (y, u)
}

/// The primary image's paraxial chief-ray height on the film (mm) at a
/// field `field_deg` degrees off the axis (object at infinity): the height
/// the ghosts' `image_height_mm` compares with.
pub fn image_height_mm(p: &Prescription, first: &FirstOrder, field_deg: f64) -> f64 {
    let (primary, _) = events(p, None, p.primary_wavelength_nm());
    let (y, u) = carry(&primary, -first.entrance_pupil.z, 1.0);
    (y + u * p.film_distance()) * field_deg.to_radians().tan()
}

/// The ghost list of `p` for a field `field_deg` degrees off the axis
/// (object at infinity), the primary wavelength: one entry per pair of
/// [`super::ghost_pairs`]. Errors where the lens is afocal or its entrance
/// pupil is at infinity (the list needs both), or the field is not an
/// angle below 90 degrees.
///
/// ```
/// let p = lens::Prescription::from_json_str(r#"{"surfaces": [
///   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true, "coating": "none"},
///   {"thickness": 97.2, "semi_diameter": 12.7, "coating": "none"}]}"#, "<doc>").unwrap();
/// let g = lens::ghost::ghost_list(&p, 5.0).unwrap();
/// assert_eq!(g.len(), 1);
/// assert_eq!(g[0].surfaces, [1, 2]);
/// // bare glass: ((n - 1) / (n + 1))^2 = 4.2% at each face
/// let r = (0.5168f64 / 2.5168).powi(2);
/// assert!((g[0].reflectance - r * r).abs() < 1e-15);
/// ```
pub fn ghost_list(p: &Prescription, field_deg: f64) -> Result<Vec<GhostFocus>, OpticsError> {
    if !(field_deg.is_finite() && field_deg.abs() < 90.0) {
        return Err(OpticsError::BadInput {
            name: "field_deg",
            value: field_deg,
            expected: "a field angle in degrees, between -90 and 90",
        });
    }
    let fo = FirstOrder::of(p)?;
    let nm = p.primary_wavelength_nm();
    let r_ep = fo.entrance_pupil.diameter / 2.0;
    let z_ep = fo.entrance_pupil.z;
    let film = p.film_distance();
    let slope = field_deg.to_radians().tan();
    let at_film = |(y, u): (f64, f64)| y + u * film;
    let (primary, t_primary) = events(p, None, nm);
    let h_primary = at_film(carry(&primary, -z_ep, 1.0));
    let mut out = Vec::new();
    for [i, j] in super::ghost_pairs(p) {
        let (path, keep) = events(p, Some((j, i)), nm);
        let (ym, um) = carry(&path, r_ep, 0.0);
        let h_g = at_film(carry(&path, -z_ep, 1.0));
        let r_i = p.coating(i).reflectance(p.surfaces()[i].ior, p.index_before(i), 1.0, nm, true);
        let r_j = p.coating(j).reflectance(p.index_before(j), p.surfaces()[j].ior, 1.0, nm, false);
        let focus = (um.abs() > 1e-12 * (ym.abs() / p.total_track().max(1.0)).max(1e-300))
            .then(|| p.last_vertex_z() - ym / um)
            .filter(|z| z.is_finite());
        let intensity = (h_g.abs() > 1e-9 * h_primary.abs() && t_primary > 0.0)
            .then(|| keep / t_primary * (h_primary / h_g).powi(2));
        out.push(GhostFocus {
            surfaces: [i + 1, j + 1],
            focus_z_mm: focus,
            image_height_mm: h_g * slope,
            radius_mm: at_film((ym, um)).abs(),
            intensity,
            reflectance: r_i * r_j,
        });
    }
    Ok(out)
}
