//! Materials: diffuse (colour or checker texture), emissive, mirror, and a
//! smooth dielectric of constant index or of a catalogue glass. Written
//! once over [`Transport`]: RGB or a path's wavelengths.

use crate::rng::Sampler;
use crate::spectrum::{Colour, Radiance};
use crate::transport::{Channels, Medium, Transport};
use glam::DVec3;

/// A surface's appearance. Colours are linear sRGB.
#[derive(Debug, Clone, PartialEq)]
pub enum Material {
    /// Lambertian reflector.
    Diffuse {
        /// Albedo.
        albedo: Colour,
    },
    /// Lambertian with a checker texture of the given square size (in the
    /// shape's texture units: metres on planes, 0..1 on quads and spheres).
    Checker {
        /// First colour.
        a: Colour,
        /// Second colour.
        b: Colour,
        /// Square size.
        scale: f64,
    },
    /// Emits `radiance` from its front side; does not reflect.
    Emissive {
        /// Radiance, W / (m^2 sr) per channel, or a spectrum.
        radiance: Radiance,
    },
    /// Perfect mirror.
    Mirror {
        /// Reflectance.
        tint: Colour,
    },
    /// Smooth dielectric: a constant index, or a catalogue glass whose
    /// index follows the path's wavelength.
    Dielectric {
        /// The medium inside.
        medium: Medium,
    },
}

/// What a surface does to a path, with the path's channels `V`.
pub enum Scatter<V> {
    /// Diffuse: the albedo; the integrator samples the hemisphere and lights.
    Diffuse(V),
    /// A specular direction with its throughput weight.
    Specular(DVec3, V),
    /// Absorbed (emitters).
    None,
}

impl Material {
    /// Emitted radiance toward a viewer on the side of `n` (front only).
    pub fn emitted<T: Transport>(&self, t: &T, cos_out: f64) -> T::Value {
        match self {
            Material::Emissive { radiance } if cos_out > 0.0 => t.radiance(radiance),
            _ => T::Value::ZERO,
        }
    }

    /// Scattering at a hit with unit normal `n` (facing out of the shape),
    /// incoming direction `d` (toward the surface), texture coordinates `uv`.
    /// A dispersive dielectric keeps only the path's hero wavelength.
    pub fn scatter<T: Transport>(
        &self,
        t: &mut T,
        d: DVec3,
        n: DVec3,
        uv: (f64, f64),
        s: &mut Sampler,
    ) -> Scatter<T::Value> {
        match self {
            Material::Diffuse { albedo } => Scatter::Diffuse(t.reflectance(albedo)),
            Material::Checker { a, b, scale } => {
                let k = ((uv.0 / scale).floor() + (uv.1 / scale).floor()) as i64;
                Scatter::Diffuse(t.reflectance(if k.rem_euclid(2) == 0 { a } else { b }))
            }
            Material::Emissive { .. } => Scatter::None,
            Material::Mirror { tint } => Scatter::Specular(reflect(d, n), t.reflectance(tint)),
            Material::Dielectric { medium } => {
                let ior = t.ior(medium);
                let entering = d.dot(n) < 0.0;
                let (nn, eta) = if entering { (n, 1.0 / ior) } else { (-n, ior) };
                let cos_i = -d.dot(nn);
                let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
                if k < 0.0 {
                    return Scatter::Specular(reflect(d, nn), T::Value::ONE);
                }
                let cos_t = k.sqrt();
                // Fresnel (dielectric, unpolarised)
                let n1 = if entering { 1.0 } else { ior };
                let n2 = if entering { ior } else { 1.0 };
                let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
                let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
                let fr = 0.5 * (rs * rs + rp * rp);
                if s.uniform() < fr {
                    Scatter::Specular(reflect(d, nn), T::Value::ONE)
                } else {
                    Scatter::Specular((eta * d + (eta * cos_i - cos_t) * nn).normalize(), T::Value::ONE)
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
