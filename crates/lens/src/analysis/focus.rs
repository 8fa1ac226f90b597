//! Real-ray focus: the film position of least RMS spot of the on-axis
//! bundle, beside the paraxial focus ([`crate::paraxial::focus`]), and the
//! on-axis bundle the circle of confusion also measures.

use super::bundle::{trace_rays, Landing};
use crate::analysis::quadrature::gauss_legendre;
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::focus::film_distance_with;
use crate::paraxial::{FirstOrder, ObjectDistance};
use crate::trace::ray::Ray;
use crate::trace::Tracer;
use glam::DVec3;
use serde::Serialize;

/// Gauss–Legendre nodes over the pupil area for the on-axis bundle. The
/// transverse error is a smooth odd series in the pupil radius, so 48 nodes
/// integrate its square to rounding on every shipped lens (docs/analyses.md).
pub const BUNDLE_NODES: usize = 48;

/// Result of focusing on an on-axis object.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Focus {
    /// Paraxial film distance (last vertex to the paraxial image), mm.
    pub film_distance: f64,
    /// Film distance of least RMS spot radius of the real on-axis bundle, mm.
    pub best_focus_film_distance: f64,
    /// RMS spot radius of the real bundle on the paraxial film, mm.
    pub rms_radius_at_paraxial_focus: f64,
    /// RMS spot radius of the real bundle at best focus, mm.
    pub rms_radius_at_best_focus: f64,
    /// Fraction of the entrance-pupil radius that the real bundle fills
    /// (1 when no clear aperture vignettes the on-axis bundle).
    pub pupil_fill: f64,
}

/// Focuses on `object`: the paraxial film distance and the real-ray best
/// focus beside it.
pub fn focus(p: &Prescription, object: ObjectDistance) -> Result<Focus, OpticsError> {
    let first = FirstOrder::of(p)?;
    let film = film_distance_with(p, &first, object)?;
    let bundle = AxialBundle::trace(p, &first, object, film)?;
    let (t, rms_best) = bundle.least_rms_shift();
    if !(film + t > 0.0 && (film + t).is_finite()) {
        return Err(OpticsError::NoRealFocus {
            object_distance: match object {
                ObjectDistance::Infinity => None,
                ObjectDistance::Finite(d) => Some(d),
            },
            film_distance: film,
            best_focus: film + t,
        });
    }
    Ok(Focus {
        film_distance: film,
        best_focus_film_distance: film + t,
        rms_radius_at_paraxial_focus: bundle.rms_at(0.0),
        rms_radius_at_best_focus: rms_best,
        pupil_fill: bundle.fill,
    })
}

/// Meridional rays across the pupil radius used for the geometric (largest)
/// blur radius of the on-axis bundle.
const GEO_SAMPLES: usize = 512;

/// The real on-axis bundle sampled on Gauss–Legendre rings of the entrance
/// pupil, each ring's meridional ray on a reference film plane.
pub(crate) struct AxialBundle {
    /// Per ring: quadrature weight, height on the reference film, slope dy/dz.
    rings: Vec<(f64, f64, f64)>,
    /// Fraction of the entrance-pupil radius that passes.
    pub fill: f64,
    /// Largest |y| on the reference film over a dense meridional fan, mm.
    pub geo_radius: f64,
    /// Rays traced to build the bundle (rings, fill search and fan).
    pub rays: usize,
}

impl AxialBundle {
    /// Traces the bundle from `object` to a film `film` mm behind the last vertex.
    pub fn trace(p: &Prescription, first: &FirstOrder, object: ObjectDistance, film: f64) -> Result<Self, OpticsError> {
        Self::trace_with(p, first, object, film, BUNDLE_NODES)
    }

    /// As [`Self::trace`] with `nodes` Gauss–Legendre rings.
    pub fn trace_with(
        p: &Prescription,
        first: &FirstOrder,
        object: ObjectDistance,
        film: f64,
        nodes: usize,
    ) -> Result<Self, OpticsError> {
        // one meridian stands for the whole bundle only in a symmetric lens
        if p.is_tilted() {
            return Err(OpticsError::NotCoaxial {
                analysis: "the real-ray focus of the axial bundle (focus, circle of confusion, convergence)",
            });
        }
        let tracer = Tracer::forward_to_film(p, film);
        let ep = first.entrance_pupil;
        let r_ep = ep.diameter / 2.0;
        let traced = std::cell::Cell::new(0usize);
        let z_start = ep.z.min(0.0) - 1.0;
        let make = |rho: f64| -> Option<Ray> {
            let aim = DVec3::new(0.0, rho * r_ep, ep.z);
            match object {
                ObjectDistance::Infinity => Ray::new(aim, DVec3::Z),
                ObjectDistance::Finite(d) => {
                    // the ray from the object through the aim point, started
                    // on the plane in front of the lens (an object at 1e200 mm
                    // is then as good as one at infinity, not an overflow)
                    let dir = DVec3::new(0.0, rho * r_ep / (d + ep.z), 1.0);
                    Ray::new(aim - dir * (ep.z - z_start), dir)
                }
            }
        };
        // the rays at pupil fractions `rhos`, traced as one batch; `None`
        // where a ray cannot be formed or does not reach the film
        let trace_at = |rhos: &[f64]| -> Vec<Option<Ray>> {
            traced.set(traced.get() + rhos.len());
            let made: Vec<Option<Ray>> = rhos.iter().map(|&r| make(r)).collect();
            let rays: Vec<Ray> = made.iter().flatten().copied().collect();
            let mut landed = trace_rays(&tracer, &rays).into_iter();
            made.iter()
                .map(|m| {
                    m.and_then(|_| match landed.next() {
                        Some(Landing::Reached(r)) if r.direction.z != 0.0 => Some(r),
                        _ => None,
                    })
                })
                .collect()
        };
        let ray_at = |rho: f64| trace_at(&[rho])[0];
        if ray_at(0.0).is_none() {
            return Err(OpticsError::NoRealRays { why: "the axial ray does not reach the film".into() });
        }
        // Largest pupil fraction whose meridional ray passes.
        let fill = if ray_at(1.0).is_some() {
            1.0
        } else {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if ray_at(mid).is_some() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        if fill <= 0.0 {
            return Err(OpticsError::NoRealRays { why: "every off-axis ray of the on-axis bundle is blocked".into() });
        }
        let (nodes, weights) = gauss_legendre(nodes.max(1), 0.0, fill * fill);
        let radii: Vec<f64> = nodes.iter().map(|u| u.sqrt()).collect();
        let mut rings = Vec::with_capacity(nodes.len());
        for ((rho, w), r) in radii.iter().zip(&weights).zip(trace_at(&radii)) {
            let Some(r) = r else {
                return Err(OpticsError::NoRealRays {
                    why: format!("the ray at {rho:.4} of the pupil radius is blocked inside the passing zone"),
                });
            };
            rings.push((*w, r.origin.y, r.direction.y / r.direction.z));
        }
        let fan: Vec<f64> = (0..=GEO_SAMPLES).map(|k| fill * k as f64 / GEO_SAMPLES as f64).collect();
        let geo_radius = trace_at(&fan).iter().flatten().fold(0.0f64, |g, r| g.max(r.origin.y.abs()));
        Ok(AxialBundle { rings, fill, geo_radius, rays: traced.get() })
    }

    /// Mean of y^2, y m and m^2 over the pupil area.
    fn moments(&self) -> (f64, f64, f64) {
        let total: f64 = self.rings.iter().map(|r| r.0).sum();
        let mut m = (0.0, 0.0, 0.0);
        for &(w, y, s) in &self.rings {
            m.0 += w * y * y;
            m.1 += w * y * s;
            m.2 += w * s * s;
        }
        (m.0 / total, m.1 / total, m.2 / total)
    }

    /// RMS spot radius (about the axis, which is the centroid by symmetry)
    /// on a plane `t` mm behind the reference film.
    pub fn rms_at(&self, t: f64) -> f64 {
        let (yy, ym, mm) = self.moments();
        (yy + 2.0 * t * ym + t * t * mm).max(0.0).sqrt()
    }

    /// The shift of least RMS radius (closed form: the RMS^2 is quadratic in
    /// the shift) and that radius.
    fn least_rms_shift(&self) -> (f64, f64) {
        let (_, ym, mm) = self.moments();
        let t = if mm > 0.0 { -ym / mm } else { 0.0 };
        (t, self.rms_at(t))
    }
}
