//! Materials: diffuse (colour or checker texture), emissive, mirror, glass.

use crate::rng::Sampler;
use glam::DVec3;

/// A surface's appearance. Colours are linear RGB.
#[derive(Debug, Clone, PartialEq)]
pub enum Material {
    /// Lambertian reflector.
    Diffuse {
        /// Albedo.
        albedo: DVec3,
    },
    /// Lambertian with a checker texture of the given square size (in the
    /// shape's texture units: metres on planes, 0..1 on quads and spheres).
    Checker {
        /// First colour.
        a: DVec3,
        /// Second colour.
        b: DVec3,
        /// Square size.
        scale: f64,
    },
    /// Emits `radiance` from its front side; does not reflect.
    Emissive {
        /// Radiance, W / (m^2 sr) per channel.
        radiance: DVec3,
    },
    /// Perfect mirror.
    Mirror {
        /// Reflectance.
        tint: DVec3,
    },
    /// Smooth dielectric.
    Glass {
        /// Refractive index.
        ior: f64,
    },
}

/// What a surface does to a path.
pub enum Scatter {
    /// Diffuse: the albedo; the integrator samples the hemisphere and lights.
    Diffuse(DVec3),
    /// A specular direction with its throughput weight.
    Specular(DVec3, DVec3),
    /// Absorbed (emitters).
    None,
}

impl Material {
    /// Emitted radiance toward a viewer on the side of `n` (front only).
    pub fn emitted(&self, cos_out: f64) -> DVec3 {
        match self {
            Material::Emissive { radiance } if cos_out > 0.0 => *radiance,
            _ => DVec3::ZERO,
        }
    }

    /// Scattering at a hit with unit normal `n` (facing out of the shape),
    /// incoming direction `d` (toward the surface), texture coordinates `uv`.
    pub fn scatter(&self, d: DVec3, n: DVec3, uv: (f64, f64), s: &mut Sampler) -> Scatter {
        match *self {
            Material::Diffuse { albedo } => Scatter::Diffuse(albedo),
            Material::Checker { a, b, scale } => {
                let k = ((uv.0 / scale).floor() + (uv.1 / scale).floor()) as i64;
                Scatter::Diffuse(if k.rem_euclid(2) == 0 { a } else { b })
            }
            Material::Emissive { .. } => Scatter::None,
            Material::Mirror { tint } => Scatter::Specular(reflect(d, n), tint),
            Material::Glass { ior } => {
                let entering = d.dot(n) < 0.0;
                let (nn, eta) = if entering { (n, 1.0 / ior) } else { (-n, ior) };
                let cos_i = -d.dot(nn);
                let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
                if k < 0.0 {
                    return Scatter::Specular(reflect(d, nn), DVec3::ONE);
                }
                let cos_t = k.sqrt();
                // Fresnel (dielectric, unpolarised)
                let n1 = if entering { 1.0 } else { ior };
                let n2 = if entering { ior } else { 1.0 };
                let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
                let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
                let fr = 0.5 * (rs * rs + rp * rp);
                if s.uniform() < fr {
                    Scatter::Specular(reflect(d, nn), DVec3::ONE)
                } else {
                    Scatter::Specular((eta * d + (eta * cos_i - cos_t) * nn).normalize(), DVec3::ONE)
                }
            }
        }
    }
}

/// Mirror reflection of `d` about `n`.
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// Cosine-weighted direction about `n` from two uniforms.
pub fn cosine_hemisphere(n: DVec3, u: (f64, f64)) -> DVec3 {
    let r = u.0.sqrt();
    let phi = std::f64::consts::TAU * u.1;
    let (t, b) = basis(n);
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u.0).max(0.0).sqrt()).normalize()
}

/// An orthonormal basis (t, b) perpendicular to unit `n`.
pub fn basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}
