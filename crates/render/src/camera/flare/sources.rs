//! The scene's bright sources whose ghosts the flare draws, as points or
//! directions in the lens frame with their light per wavelength.

use super::MAX_SOURCES;
use crate::camera::real_lens::RealLensCamera;
use crate::camera::sky_patches;
use crate::envmap::direction;
use crate::geometry::{Shape, EPS};
use crate::material::Material;
use crate::scene::{Background, Scene};
use crate::spectrum::SampledWavelengths;
use crate::transport::Spectral;
use glam::DVec3;
use lens::ghost::Source;
use std::f64::consts::{PI, TAU};

/// One bright source, in the lens frame, with its light per wavelength.
pub(super) struct Bright {
    pub(super) source: Source,
    /// Radiant intensity (a point, per unit radiance: sr mm^2) or
    /// irradiance (a direction, per unit radiance: sr) scale.
    pub(super) scale: f64,
    /// Its radiance at each of the flare's wavelengths.
    pub(super) radiance: Vec<f64>,
}

/// The scene's bright sources seen by the lens (see the module), at most
/// [`MAX_SOURCES`], the most powerful first.
pub(super) fn bright_sources(scene: &Scene, cam: &RealLensCamera, nms: &[f64]) -> Vec<Bright> {
    let front = DVec3::new(0.0, 0.0, -1.0);
    let seen = |d: DVec3, prim: Option<usize>| {
        let ray = cam.ray_to_scene(front, d);
        let eps = EPS * (1.0 + ray.origin.abs().max_element());
        match scene.intersect(&ray, eps, f64::INFINITY) {
            Some((hit, _)) => prim == Some(hit),
            None => prim.is_none(),
        }
    };
    let at = |nm: f64| Spectral::new(SampledWavelengths::single(nm));
    let mut out: Vec<(f64, Bright)> = Vec::new();
    for (i, shape) in scene.shapes.iter().enumerate() {
        let m = &scene.materials[scene.material_of[i]];
        if !matches!(m, Material::Emissive { .. }) {
            continue;
        }
        if let Some(b) = small_flat_source(cam, shape, m, nms, &at) {
            if seen((b.1 - front).normalize(), Some(i)) {
                out.push((b.0, Bright { source: Source::Point(b.1), scale: b.2, radiance: b.3 }));
            }
            continue;
        }
        let Shape::Sphere { center, radius } = shape else { continue };
        let c = cam.point_to_lens(*center);
        let rho = radius * 1e3;
        let r = (c - front).length();
        if c.z + rho >= front.z || r <= rho || !seen((c - front).normalize(), Some(i)) {
            continue;
        }
        // the disc's solid angle from the front, times r^2: intensity per
        // unit radiance, sr mm^2
        let solid = TAU * (1.0 - (1.0 - (rho / r).powi(2)).max(0.0).sqrt());
        let radiance: Vec<f64> = nms.iter().map(|&nm| m.emitted(&at(nm), 1.0).0[0]).collect();
        let scale = solid * r * r;
        let power = scale * radiance.iter().sum::<f64>() / (r * r);
        out.push((power, Bright { source: Source::Point(c), scale, radiance }));
    }
    if let Background::Environment(img) = &scene.background {
        for patch in sky_patches::find(img) {
            let (w, h) = (img.width, img.height);
            let mut radiance = vec![0.0; nms.len()];
            let mut centre = DVec3::ZERO;
            for &k in patch.texels() {
                let (u, v) = (((k % w) as f64 + 0.5) / w as f64, ((k / w) as f64 + 0.5) / h as f64);
                let d = direction(u, v);
                let solid = (TAU / w as f64) * (PI / h as f64) * (v * PI).sin();
                for (r, &nm) in radiance.iter_mut().zip(nms) {
                    *r += scene.background.radiance(&at(nm), d).0[0] * solid;
                }
                centre += d * solid * scene.background.radiance(&at(550.0), d).0[0];
            }
            let toward = cam.dir_to_lens(centre.normalize_or(DVec3::Z));
            if toward.z >= 0.0 || !seen(toward, None) {
                continue;
            }
            let power = radiance.iter().sum::<f64>();
            // irradiance per unit radiance: the patch's solid angle, carried
            // in `radiance` already (scale 1)
            out.push((power, Bright { source: Source::Direction(-toward), scale: 1.0, radiance }));
        }
    }
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    out.truncate(MAX_SOURCES);
    out.into_iter().map(|x| x.1).collect()
}

/// The widest an emissive quad may look from the lens (its longest side's
/// angle, radians: 2 degrees) to be taken as a point source: a larger
/// one's ghosts would be its own shape blurred, which a point's are not,
/// and it makes none.
pub const FLAT_SOURCE_RAD: f64 = 0.035;

/// An emissive quad small as the lens sees it ([`FLAT_SOURCE_RAD`]), its
/// front facing the lens, as a point source at its centre (the lens
/// frame, mm): its power for ranking, the point, its intensity per unit
/// radiance (its area times the cosine toward the lens, mm^2) and its
/// radiance at `nms`. `None` for any other shape (a mesh's triangles are
/// not taken one by one: a lamp of many would keep only the
/// [`MAX_SOURCES`] brightest).
fn small_flat_source(
    cam: &RealLensCamera,
    shape: &Shape,
    m: &Material,
    nms: &[f64],
    at: &impl Fn(f64) -> Spectral,
) -> Option<(f64, DVec3, f64, Vec<f64>)> {
    let corners: Vec<DVec3> = match *shape {
        Shape::Quad { corner, u, v } => vec![corner, corner + u, corner + u + v, corner + v],
        _ => return None,
    };
    let n = corners.len();
    // the area vector of the polygon (m^2, along its front side's normal,
    // as the shape's hit normal) and its centre, in the scene
    let area = (1..n - 1).map(|k| (corners[k] - corners[0]).cross(corners[k + 1] - corners[0])).sum::<DVec3>() / 2.0;
    let middle = corners.iter().sum::<DVec3>() / n as f64;
    let front = DVec3::new(0.0, 0.0, -1.0);
    let eye = cam.ray_to_scene(front, DVec3::Z).origin;
    let cos = area.dot(eye - middle) / (area.length() * (eye - middle).length());
    // where the lens sees it (mm)
    let lens: Vec<DVec3> = corners.iter().map(|&p| cam.point_to_lens(p)).collect();
    let centre = cam.point_to_lens(middle);
    let r = (front - centre).length();
    let longest = (0..n).map(|k| (lens[(k + 1) % n] - lens[k]).length()).fold(0.0, f64::max);
    if centre.z >= front.z || cos.is_nan() || cos <= 0.0 || longest > FLAT_SOURCE_RAD * r {
        return None;
    }
    let projected = area.length() * 1e6 * cos;
    let radiance: Vec<f64> = nms.iter().map(|&nm| m.emitted(&at(nm), cos).0[0]).collect();
    let power = projected * radiance.iter().sum::<f64>() / (r * r);
    Some((power, centre, projected, radiance))
}
