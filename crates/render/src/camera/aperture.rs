//! Aperture shapes: where on a unit aperture a sample lands.

use crate::scene::format::ApertureSpec;

/// A shape inscribed in the unit circle.
#[derive(Debug, Clone, PartialEq)]
pub enum Aperture {
    /// The unit disc.
    Circle,
    /// A regular polygon with `blades` corners on the unit circle, rotated.
    Polygon {
        /// Corners.
        blades: u32,
        /// Rotation, radians.
        rotation: f64,
    },
}

impl Aperture {
    /// From the scene spec; errors name the field.
    pub fn from_spec(s: &ApertureSpec) -> Result<Self, String> {
        Ok(match *s {
            ApertureSpec::Circle => Aperture::Circle,
            ApertureSpec::Polygon { blades, rotation_deg } => {
                if blades < 3 {
                    return Err(format!("aperture_shape.blades = {blades}: a polygon needs at least 3 blades"));
                }
                if !rotation_deg.is_finite() {
                    return Err("aperture_shape.rotation_deg must be a finite angle".into());
                }
                Aperture::Polygon { blades, rotation: rotation_deg.to_radians() }
            }
        })
    }

    /// A point uniform over the shape (unit scale) from two uniforms.
    pub fn sample(&self, u: (f64, f64)) -> (f64, f64) {
        match *self {
            Aperture::Circle => concentric(u),
            Aperture::Polygon { blades, rotation } => {
                // pick a triangle of the fan, then a uniform point in it
                let n = blades as f64;
                let k = (u.0 * n).floor().min(n - 1.0);
                let v = u.0 * n - k; // reuse the remainder as a fresh uniform
                let a0 = rotation + std::f64::consts::TAU * k / n;
                let a1 = rotation + std::f64::consts::TAU * (k + 1.0) / n;
                let (mut s, mut t) = (v, u.1);
                if s + t > 1.0 {
                    s = 1.0 - s;
                    t = 1.0 - t;
                }
                (s * a0.cos() + t * a1.cos(), s * a0.sin() + t * a1.sin())
            }
        }
    }

    /// Whether a point (unit scale) lies inside the shape.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        match *self {
            Aperture::Circle => x * x + y * y <= 1.0,
            Aperture::Polygon { blades, rotation } => {
                let n = blades as f64;
                // inside every edge's half-plane: the apothem is cos(pi/n)
                let apothem = (std::f64::consts::PI / n).cos();
                (0..blades).all(|k| {
                    let mid = rotation + std::f64::consts::TAU * (k as f64 + 0.5) / n;
                    x * mid.cos() + y * mid.sin() <= apothem
                })
            }
        }
    }

    /// Area of the shape at unit scale.
    pub fn area(&self) -> f64 {
        match *self {
            Aperture::Circle => std::f64::consts::PI,
            Aperture::Polygon { blades, .. } => {
                let n = blades as f64;
                0.5 * n * (std::f64::consts::TAU / n).sin()
            }
        }
    }
}

/// Shirley–Chiu concentric map of the unit square onto the unit disc.
pub fn concentric(u: (f64, f64)) -> (f64, f64) {
    let (a, b) = (2.0 * u.0 - 1.0, 2.0 * u.1 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, std::f64::consts::FRAC_PI_4 * (b / a))
    } else {
        (b, std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}
