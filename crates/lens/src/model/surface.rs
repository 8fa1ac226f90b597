//! One refracting (or stop) surface of a prescription, stored by curvature.

/// A spherical (or plane) surface of a validated prescription.
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
}

impl Surface {
    /// Radius of curvature in mm, `None` for a plane.
    pub fn radius(&self) -> Option<f64> {
        (self.curvature != 0.0).then(|| 1.0 / self.curvature)
    }

    /// Sag (z of the surface relative to its vertex, +z toward the image) at
    /// radial height `h` mm, or `None` where the sphere does not reach `h`
    /// (|c h| > 1). Continuous as c -> 0: `sag = c h^2 / (1 + sqrt(1 - c^2 h^2))`.
    pub fn sag(&self, h: f64) -> Option<f64> {
        sag(self.curvature, h)
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
    fn near_flat_sag_matches_parabola() {
        let c = 1e-9;
        let h = 10.0;
        let s = sag(c, h).unwrap();
        assert!((s - c * h * h / 2.0).abs() < 1e-20);
    }
}
