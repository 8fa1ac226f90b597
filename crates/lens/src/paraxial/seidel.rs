//! Third-order (Seidel) aberration sums from the paraxial marginal and
//! chief rays, surface by surface (Welford, "Aberrations of Optical
//! Systems", ch. 7):
//!
//! S_I = -sum A^2 y d(u/n), S_II = -sum A Abar y d(u/n),
//! S_III = -sum Abar^2 y d(u/n), S_IV = -sum H^2 c d(1/n),
//! S_V = sum (Abar / A) (S_III + S_IV) per surface,
//!
//! with A = n (u + y c) and Abar the refraction invariants of the marginal
//! and chief rays (u the slope before the surface), d(.) the change across
//! it and H = n (ubar y - u ybar) the Lagrange invariant. The wavefront
//! coefficients follow: W040 = S_I / 8 (spherical), W131 = S_II / 2
//! (coma), W222 = S_III / 2 (astigmatism), W220 = (S_III + S_IV) / 4
//! (field curvature), W311 = S_V / 2 (distortion), in mm of optical path at
//! the pupil's rim and the field asked; W040 > 0 with the sign of
//! [`crate::analysis::wave`]'s W (a wave ahead of the reference at the rim:
//! the undercorrected spherical aberration of a positive singlet).

use super::{trace, FirstOrder, ObjectDistance};
use crate::error::OpticsError;
use crate::model::Prescription;

/// The Seidel sums of a prescription at one field and object distance.
#[derive(Debug, Clone, PartialEq)]
pub struct Seidel {
    /// Per surface: S_I to S_V, mm.
    pub surfaces: Vec<[f64; 5]>,
    /// Their sums over the surfaces, mm.
    pub sums: [f64; 5],
}

impl Seidel {
    /// The third-order spherical aberration coefficient W040 = S_I / 8, mm.
    pub fn w040(&self) -> f64 {
        self.sums[0] / 8.0
    }
}

/// The Seidel sums of `p` for `object` with the chief ray at `field_deg`
/// degrees (paraxial angle tan(field) in object space for an object at
/// infinity, through the entrance pupil's centre), the marginal ray
/// through the entrance pupil's rim.
pub fn seidel(
    p: &Prescription,
    first: &FirstOrder,
    object: ObjectDistance,
    field_deg: f64,
) -> Result<Seidel, OpticsError> {
    if !(field_deg.is_finite() && field_deg.abs() < 90.0) {
        return Err(OpticsError::BadInput {
            name: "field angle",
            value: field_deg,
            expected: "an angle in degrees strictly between -90 and 90",
        });
    }
    let (z_ep, r_ep) = (first.entrance_pupil.z, 0.5 * first.entrance_pupil.diameter);
    // marginal ray: from the axial object point through the pupil's rim
    let (y1, u0) = match object {
        ObjectDistance::Infinity => (r_ep, 0.0),
        ObjectDistance::Finite(d) => {
            let u = r_ep / (d + z_ep);
            (u * d, u)
        }
    };
    // chief ray: through the pupil's centre at the field's slope
    let ubar0 = field_deg.to_radians().tan();
    let ybar1 = -z_ep * ubar0;
    let m = trace(p, y1, u0);
    let c = trace(p, ybar1, ubar0);
    let n0 = p.index_before(0);
    let lagrange = n0 * (ubar0 * y1 - u0 * ybar1);
    let mut surfaces = Vec::with_capacity(p.surfaces().len());
    for (i, s) in p.surfaces().iter().enumerate() {
        let (n, n2) = (p.index_before(i), s.ior);
        let curv = s.vertex_curvature();
        let (u, ub) = if i == 0 { (u0, ubar0) } else { (m.u[i - 1], c.u[i - 1]) };
        let (y, yb) = (m.y[i], c.y[i]);
        let a = n * (u + y * curv);
        let ab = n * (ub + yb * curv);
        let du = m.u[i] / n2 - u / n;
        let s1 = -a * a * y * du;
        let s2 = -a * ab * y * du;
        let s3 = -ab * ab * y * du;
        let s4 = -lagrange * lagrange * curv * (1.0 / n2 - 1.0 / n);
        let s5 = if a != 0.0 { ab / a * (s3 + s4) } else { 0.0 };
        // an ideal lens images plane to plane without aberration
        surfaces.push(if s.paraxial.is_some() { [0.0; 5] } else { [s1, s2, s3, s4, s5] });
    }
    let mut sums = [0.0; 5];
    for s in &surfaces {
        for k in 0..5 {
            sums[k] += s[k];
        }
    }
    Ok(Seidel { surfaces, sums })
}
