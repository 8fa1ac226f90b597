//! A unidirectional path tracer with direct light sampling (next event
//! estimation) on diffuse surfaces, combined with the emitters that BSDF
//! sampling finds by multiple importance sampling (Veach's power heuristic),
//! and Russian roulette; written once over [`Transport`]: RGB channels or a
//! path's wavelengths.

use crate::camera::lamp_light::Unseen;
use crate::geometry::{Ray, EPS};
use crate::light::sample_shape_at;
use crate::material::{cosine_hemisphere, Material, Scatter};
use crate::rng::Sampler;
use crate::scene::Scene;
use crate::transport::{Channels, Transport};
use glam::DVec3;

/// Longest path, in bounces.
pub const MAX_DEPTH: usize = 32;
/// Bounces before Russian roulette may end a path.
pub const RR_DEPTH: usize = 3;

/// Radiance arriving along `ray`, in the channels of `t` (linear sRGB, or
/// a value per wavelength).
pub fn radiance<T: Transport>(scene: &Scene, ray: Ray, t: &mut T, s: &mut Sampler) -> T::Value {
    radiance_with(scene, ray, t, s, None, &Unseen::NONE)
}

/// The uniforms of a path's first diffuse bounce drawn by the render loop
/// (stratified over a pixel's samples): the light sample's and the
/// direction's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstBounce {
    /// Two uniforms for the light sample.
    pub light: (f64, f64),
    /// Two uniforms for the cosine-sampled direction.
    pub bsdf: (f64, f64),
}

/// [`radiance`] with the first diffuse bounce's uniforms given, and the
/// emitters and environment directions `unseen` counted as black where
/// the ray itself meets them: a real lens's lamps and bright sky, whose
/// directly seen light the render traces from them
/// ([`crate::camera::lamp_light`]).
pub fn radiance_with<T: Transport>(
    scene: &Scene,
    mut ray: Ray,
    t: &mut T,
    s: &mut Sampler,
    mut first: Option<FirstBounce>,
    unseen: &Unseen,
) -> T::Value {
    let mut l = T::Value::ZERO;
    let mut beta = T::Value::ONE;
    // emission seen directly or through specular bounces is counted on hit;
    // after a diffuse bounce, from the point and with the BSDF sample's
    // density (solid angle) kept here, it is weighted against light sampling
    let mut after_diffuse: Option<(DVec3, f64)> = None;
    for depth in 0..MAX_DEPTH {
        let scale = 1.0 + ray.origin.abs().max_element();
        let Some((prim, h)) = scene.intersect(&ray, EPS * scale, f64::INFINITY) else {
            if depth == 0 && unseen.sky(ray.dir) {
                break;
            }
            let le = scene.background.radiance(t, ray.dir);
            match (after_diffuse, &scene.env_sampler) {
                // an environment is light-sampled too: weigh the two
                (Some((_, pdf_bsdf)), Some(env)) => l += beta * le * power_heuristic(pdf_bsdf, env.pdf(ray.dir)),
                _ => l += beta * le,
            }
            break;
        };
        let mat = &scene.materials[scene.material_of[prim]];
        if let Material::Emissive { .. } = mat {
            if depth == 0 && unseen.prim(prim) {
                break;
            }
            // emitters that light sampling cannot pick (infinite planes) are
            // counted whenever a path finds them
            let le = mat.emitted(t, -ray.dir.dot(h.n));
            match after_diffuse {
                Some((from, pdf_bsdf)) if scene.light_sampled(prim) => {
                    let pdf_light = light_pdf(scene, prim, from, h.p, h.n);
                    l += beta * le * power_heuristic(pdf_bsdf, pdf_light);
                }
                _ => l += beta * le,
            }
            break;
        }
        // shading normal on the side the ray came from
        let ns = if ray.dir.dot(h.n) > 0.0 { -h.n } else { h.n };
        let p_scale = 1.0 + h.p.abs().max_element();
        let above = h.p + ns * (EPS * p_scale * 10.0);
        match mat.scatter(t, ray.dir, h.n, h.uv, s) {
            Scatter::None => break,
            Scatter::Diffuse(albedo) => {
                let bounce = first.take();
                l += beta
                    * albedo
                    * direct(scene, t, above, ns, s, bounce.map(|b| b.light))
                    * (1.0 / std::f64::consts::PI);
                let d = cosine_hemisphere(ns, bounce.map_or_else(|| s.next2(), |b| b.bsdf));
                // cosine sampling: cos / pdf = pi cancels the 1/pi of Lambert
                beta *= albedo;
                ray = Ray { origin: above, dir: d };
                after_diffuse = Some((above, d.dot(ns).max(0.0) / std::f64::consts::PI));
            }
            Scatter::Specular(d, w) => {
                beta *= w;
                let side = if d.dot(h.n) > 0.0 { h.n } else { -h.n };
                ray = Ray { origin: h.p + side * (EPS * p_scale * 10.0), dir: d };
                after_diffuse = None;
            }
        }
        if depth >= RR_DEPTH {
            let q = beta.max_channel().min(0.95);
            if q <= 0.0 || s.uniform() >= q {
                break;
            }
            beta *= 1.0 / q;
        }
    }
    l
}

/// Direct light at a diffuse point `p` with normal `n` (irradiance times pi:
/// the caller multiplies by albedo / pi): point lights, and one emissive
/// shape chosen in proportion to its power, sampled by area.
fn direct<T: Transport>(
    scene: &Scene,
    t: &T,
    p: DVec3,
    n: DVec3,
    s: &mut Sampler,
    light_u: Option<(f64, f64)>,
) -> T::Value {
    let mut e = T::Value::ZERO;
    for (lp, intensity) in &scene.point_lights {
        let lp = *lp;
        let d = lp - p;
        let dist2 = d.length_squared();
        let cos = n.dot(d) / dist2.sqrt();
        if cos > 0.0 && scene.visible(p, lp) {
            e += t.radiance(intensity) * (cos / dist2);
        }
    }
    if let Some(env) = &scene.env_sampler {
        // one direction drawn from the environment's own light
        if let Some((d, pdf)) = env.sample(light_u.unwrap_or_else(|| s.next2())) {
            let cos = n.dot(d);
            let ray = Ray { origin: p, dir: d };
            let scale = 1.0 + p.abs().max_element();
            if cos > 0.0 && scene.intersect(&ray, EPS * scale, f64::INFINITY).is_none() {
                let w = power_heuristic(pdf, cos / std::f64::consts::PI);
                e += scene.background.radiance(t, d) * (cos / pdf * w);
            }
        }
    }
    if let Some((prim, chosen)) = scene.choose_emitter(s.uniform()) {
        let u = light_u.unwrap_or_else(|| s.next2());
        if let Some((q, nq, pdf_area)) = sample_shape_at(&scene.shapes[prim], u) {
            let d = q - p;
            let dist2 = d.length_squared();
            let dir = d / dist2.sqrt();
            let cos = n.dot(dir);
            let cos_l = -nq.dot(dir);
            if cos > 0.0 && cos_l > 0.0 && scene.visible(p, q) {
                let le = scene.materials[scene.material_of[prim]].emitted(t, cos_l);
                let pdf = pdf_area * chosen;
                // against the chance that cosine sampling of the BSDF finds
                // the same point, both densities in solid angle
                let w = power_heuristic(pdf * dist2 / cos_l, cos / std::f64::consts::PI);
                e += le * (cos * cos_l / (dist2 * pdf) * w);
            }
        }
    }
    e
}

/// The power heuristic (exponent 2) weight of a sample drawn with density
/// `a` against another technique of density `b`.
fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if a.is_infinite() {
        1.0
    } else {
        0.0
    }
}

/// The density (per solid angle at `from`) with which [`direct`] draws the
/// point `q` (normal `nq`) of emitter `prim`: the probability of choosing
/// it times its uniform area density, turned into solid angle.
fn light_pdf(scene: &Scene, prim: usize, from: DVec3, q: DVec3, nq: DVec3) -> f64 {
    let d = q - from;
    let dist2 = d.length_squared();
    let cos_l = (nq.dot(d) / dist2.sqrt()).abs();
    let area = scene.shapes[prim].area();
    if !(cos_l > 0.0 && area > 0.0) {
        return f64::INFINITY;
    }
    dist2 * scene.emitter_probability(prim) / (cos_l * area)
}
