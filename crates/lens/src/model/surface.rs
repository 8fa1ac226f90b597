//! One refracting (or stop) surface of a prescription, stored by curvature,
//! with its aspheric departure when it has one ([`Asphere`]).

/// A surface of a validated prescription: a sphere or plane, or an asphere
/// (a conic with polynomial terms) when [`Surface::asphere`] is set.
///
/// Conventions (docs/architecture.md): the surface is stored by its curvature
/// `c = 1/R` in 1/mm, positive when the centre of curvature lies on the image
/// side (+z); a plane has `c = 0`. `thickness` is the axial distance in mm to
/// the next surface's vertex (for the last surface: to the film). `ior` is the
/// refractive index of the medium after the surface (toward +z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Curvature 1/R in 1/mm; 0 for a plane.
    pub curvature: f64,
    /// Axial distance to the next vertex (or the film), mm, >= 0.
    pub thickness: f64,
    /// Refractive index of the medium after this surface (1.0 = air), at
    /// the prescription's wavelength ([`super::Prescription::wavelength_nm`]).
    pub ior: f64,
    /// The glass after this surface, an index into
    /// [`super::Prescription::glasses`]; `None` for a constant index.
    pub glass: Option<usize>,
    /// Clear-aperture radius in mm; `None` means the surface does not clip.
    pub semi_diameter: Option<f64>,
    /// Whether this surface is the aperture stop.
    pub stop: bool,
    /// The conic constant and polynomial terms of an aspheric surface
    /// (`None` for a sphere or plane).
    pub asphere: Option<Asphere>,
    /// An ideal thin lens of this focal length (mm) in the vertex plane
    /// (Zemax's paraxial surface; `None` for a real surface): a ray of
    /// slopes t = (dx/dz, dy/dz) meeting it at height h leaves with t -
    /// h / f (travelling +z), toward the point f t of the focal plane, and
    /// gains the optical path that makes a plane wave converge there
    /// exactly (docs/architecture.md, "Wave optics").
    pub paraxial: Option<f64>,
    /// This surface's own decentre, mm in x and y (0, 0: none); see
    /// [`super::Placement::of_motion`].
    pub decenter_mm: [f64; 2],
    /// This surface's own tilt, degrees about x then the new y (0, 0:
    /// none).
    pub tilt_deg: [f64; 2],
}

/// The most polynomial terms of an asphere: powers r^1 to r^16 (Zemax's
/// even asphere goes to r^16).
pub const MAX_ASPHERE_POWER: usize = 16;

/// The departure of an aspheric surface from its base sphere. Its sag, mm,
/// at radial height r mm, for the surface's curvature c (1/mm), is
///
/// z(r) = c r^2 / (1 + sqrt(1 - (1 + k) c^2 r^2)) + sum_j a_j r^j,
///
/// as in Zemax's even and odd aspheres: `k` the conic constant (0 sphere,
/// -1 paraboloid, < -1 hyperboloid, between -1 and 0 prolate ellipsoid,
/// > 0 oblate), `a_j` (mm^(1-j)) the coefficient of r^j.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asphere {
    /// Conic constant k.
    pub conic: f64,
    /// `coefficients[j - 1]` is a_j, the coefficient of r^j, mm^(1-j).
    pub coefficients: [f64; MAX_ASPHERE_POWER],
}

impl Asphere {
    /// An asphere of conic constant `conic` with the even terms `even`
    /// (coefficients of r^2, r^4, r^6, ...) and the terms `odd` of every
    /// power (r^1, r^2, r^3, ...); `None` when there are more terms than
    /// [`MAX_ASPHERE_POWER`] allows.
    pub fn new(conic: f64, even: &[f64], odd: &[f64]) -> Option<Asphere> {
        if 2 * even.len() > MAX_ASPHERE_POWER || odd.len() > MAX_ASPHERE_POWER {
            return None;
        }
        let mut coefficients = [0.0; MAX_ASPHERE_POWER];
        for (i, a) in even.iter().enumerate() {
            coefficients[2 * i + 1] += a;
        }
        for (i, a) in odd.iter().enumerate() {
            coefficients[i] += a;
        }
        Some(Asphere { conic, coefficients })
    }

    /// The highest power with a non-zero coefficient (0 for a pure conic).
    pub fn degree(&self) -> usize {
        self.coefficients.iter().rposition(|a| *a != 0.0).map_or(0, |i| i + 1)
    }

    /// Whether every non-zero term has an even power (the sag is then a
    /// smooth function of r^2, with no cone at the vertex).
    pub fn is_even(&self) -> bool {
        self.coefficients.iter().step_by(2).all(|a| *a == 0.0)
    }

    /// The even terms (coefficients of r^2, r^4, ...) up to the last
    /// non-zero one.
    pub fn even_terms(&self) -> Vec<f64> {
        let n = self.degree().div_ceil(2);
        (0..n).map(|i| self.coefficients[2 * i + 1]).collect()
    }

    /// The terms of every power (r^1, r^2, ...) up to the last non-zero one.
    pub fn all_terms(&self) -> Vec<f64> {
        self.coefficients[..self.degree()].to_vec()
    }

    /// Sag (mm) at radial height `h` mm of the asphere on a base of
    /// curvature `c` (1/mm); `None` where the conic does not reach `h`
    /// ((1 + k) c^2 h^2 > 1).
    pub fn sag(&self, c: f64, h: f64) -> Option<f64> {
        let h = h.abs();
        let s = h * h;
        let q = 1.0 - (1.0 + self.conic) * c * c * s;
        if q.is_nan() || q < -4.0 * f64::EPSILON {
            return None;
        }
        let conic = c * s / (1.0 + q.max(0.0).sqrt());
        let poly = self.coefficients[..self.degree()].iter().rev().fold(0.0, |acc, a| acc * h + a) * h;
        Some(conic + poly)
    }

    /// dz/dr (the slope of the profile) at radial height `h` >= 0 mm;
    /// `None` where the conic does not reach `h`.
    pub fn slope(&self, c: f64, h: f64) -> Option<f64> {
        let q = 1.0 - (1.0 + self.conic) * c * c * h * h;
        if q.is_nan() || q <= 0.0 && c != 0.0 {
            return None;
        }
        let conic = if c == 0.0 { 0.0 } else { c * h / q.sqrt() };
        let n = self.degree();
        let poly = (1..=n).rev().fold(0.0, |acc, j| acc * h + j as f64 * self.coefficients[j - 1]);
        Some(conic + poly)
    }
}

impl Surface {
    /// Radius of curvature in mm, `None` for a plane.
    pub fn radius(&self) -> Option<f64> {
        (self.curvature != 0.0).then(|| 1.0 / self.curvature)
    }

    /// Sag (z of the surface relative to its vertex, +z toward the image) at
    /// radial height `h` mm, or `None` where the surface does not reach `h`
    /// (a sphere: |c h| > 1). Continuous as c -> 0: `sag = c h^2 / (1 +
    /// sqrt(1 - c^2 h^2))`; an asphere adds its conic and terms
    /// ([`Asphere::sag`]).
    pub fn sag(&self, h: f64) -> Option<f64> {
        profile_sag(self.curvature, self.asphere.as_ref(), h)
    }

    /// The paraxial curvature at the vertex, 1/mm: `c + 2 a_2` (an r^2 term
    /// bends the surface near the axis like a change of radius). An r^1
    /// term (a cone at the vertex) has no paraxial meaning and is left out.
    pub fn vertex_curvature(&self) -> f64 {
        match &self.asphere {
            Some(a) => self.curvature + 2.0 * a.coefficients[1],
            None => self.curvature,
        }
    }
}

/// Sag (mm) at height `h` mm of the surface of base curvature `c` (1/mm)
/// and, when given, aspheric departure `asphere`: [`Asphere::sag`], or the
/// sphere's [`sag`].
pub fn profile_sag(c: f64, asphere: Option<&Asphere>, h: f64) -> Option<f64> {
    match asphere {
        Some(a) => a.sag(c, h),
        None => sag(c, h),
    }
}

/// Sag of a sphere of curvature `c` (1/mm) at radial height `h` (mm), in mm;
/// `None` where `|c h| > 1`. Exact for planes (`c = 0` gives 0).
pub fn sag(c: f64, h: f64) -> Option<f64> {
    let ch2 = c * c * h * h;
    // A rim exactly at |R| (a hemisphere) may round to just above 1.
    if ch2.is_nan() || ch2 > 1.0 + 4.0 * f64::EPSILON {
        return None;
    }
    Some(c * h * h / (1.0 + (1.0 - ch2).max(0.0).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sag_of_plane_is_zero_and_hemisphere_reaches_radius() {
        assert_eq!(sag(0.0, 10.0), Some(0.0));
        let r = 12.0;
        assert!((sag(1.0 / r, r).unwrap() - r).abs() < 1e-12);
        assert!((sag(-1.0 / r, r).unwrap() + r).abs() < 1e-12);
        assert_eq!(sag(1.0 / r, r * 1.01), None);
    }

    #[test]
    fn asphere_sag_and_slope() {
        // a paraboloid: z = c r^2 / 2 exactly
        let p = Asphere::new(-1.0, &[], &[]).unwrap();
        assert!((p.sag(0.02, 30.0).unwrap() - 0.01 * 900.0).abs() < 1e-12);
        assert!((p.slope(0.02, 30.0).unwrap() - 0.02 * 30.0).abs() < 1e-12);
        // a sphere written as a conic of k = 0 is the sphere
        let s = Asphere::new(0.0, &[], &[]).unwrap();
        assert!((s.sag(0.05, 12.0).unwrap() - sag(0.05, 12.0).unwrap()).abs() < 1e-15);
        // terms: r^2 and r^4 on a plane, slope by finite differences
        let a = Asphere::new(0.0, &[1e-3, -2e-6], &[1e-4, 0.0, 3e-7]).unwrap();
        assert_eq!(a.degree(), 4);
        assert!(!a.is_even());
        let h = 7.0f64;
        let want = 1e-3 * h * h - 2e-6 * h.powi(4) + 1e-4 * h + 3e-7 * h.powi(3);
        assert!((a.sag(0.0, h).unwrap() - want).abs() < 1e-15);
        let fd = (a.sag(0.01, h + 1e-6).unwrap() - a.sag(0.01, h - 1e-6).unwrap()) / 2e-6;
        assert!((a.slope(0.01, h).unwrap() - fd).abs() < 1e-8);
        assert_eq!(Asphere::new(0.0, &[0.0; 9], &[]), None);
    }

    #[test]
    fn near_flat_sag_matches_parabola() {
        let c = 1e-9;
        let h = 10.0;
        let s = sag(c, h).unwrap();
        assert!((s - c * h * h / 2.0).abs() < 1e-20);
    }
}
