//! The brute-force reference for ghost images: rays from the source that
//! at every surface they meet reflect or refract at random, by the
//! surface's Fresnel reflectance at the ray's angle (coatings included),
//! surface by surface in whichever direction they travel, until they
//! reach the film, leave the lens forward of its first surface, are
//! blocked by a clear aperture, or have reflected [`MAX_REFLECTIONS`]
//! times. Unbiased for every path, slow: for tests.
//!
//! A ray reflects at surface k with probability `q = choice(k, R)` (never
//! where R = 0) and carries the weight R / q or (1 - R) / (1 - q): with
//! [`fresnel`] (q = R) this is the Fresnel choice itself, every weight 1;
//! any other choice in (0, 1) has the same expectation for every path and
//! sends more rays down the dim ones a test looks at ([`favouring`]).

use super::image::{Entrance, FilmGrid, GhostImage, Source};
use crate::model::Prescription;
use crate::trace::{Outcome, Ray, Tracer};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Reflections after which a ray is dropped (its weight, a product of
/// that many reflectances, is below 1e-5 of the source's even bare).
pub const MAX_REFLECTIONS: usize = 4;

/// The film images of every path that rays took, keyed by the surfaces
/// (0-based) they reflected at, in order: `[]` the primary image, `[j,
/// i]` the ghost of [`Tracer::ghost`]`(i, j)`.
pub type PathImages = BTreeMap<Vec<usize>, GhostImage>;

/// The Fresnel choice: reflect with probability R.
pub fn fresnel(_surface: usize, r: f64) -> f64 {
    r
}

/// A choice that reflects with probability `q` at the surfaces `at`
/// (0-based) and by R elsewhere: most rays then take the paths that
/// reflect there.
pub fn favouring(at: Vec<usize>, q: f64) -> impl Fn(usize, f64) -> f64 + Sync {
    move |k, r| if at.contains(&k) { q } else { r }
}

/// A walk that reached the film: the surfaces it reflected at, where it
/// landed (mm), its weight.
type Landed = (Vec<usize>, [f64; 2], f64);

/// One surface's four events (met forward or backward, refracted or
/// reflected).
struct Events {
    refract: [Tracer; 2],
    reflect: Option<[Tracer; 2]>,
}

/// Traces `rays` rays of `source` uniformly over `entrance` through `p`
/// with random reflections (see the module), seeded by `seed` (the same
/// images for any thread count), onto the film `film` at the
/// prescription's film distance.
pub fn brute_force(
    p: &Prescription,
    source: &Source,
    entrance: &Entrance,
    film: &FilmGrid,
    rays: usize,
    choice: &(dyn Fn(usize, f64) -> f64 + Sync),
    seed: u64,
) -> PathImages {
    let n = p.surfaces().len();
    let events: Vec<Events> = (0..n)
        .map(|k| Events {
            refract: [false, true].map(|b| Tracer::at_surface(p, k, b, false).expect("k < n")),
            reflect: Tracer::at_surface(p, k, false, true)
                .and_then(|f| Some([f, Tracer::at_surface(p, k, true, true)?])),
        })
        .collect();
    let film_z = p.last_vertex_z() + p.film_distance();
    let area = (2.0 * entrance.half_mm).powi(2);
    const CHUNK: usize = 4096;
    let chunks: Vec<Vec<Landed>> = (0..rays.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ (c as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
            let mut out = Vec::new();
            for _ in c * CHUNK..((c + 1) * CHUNK).min(rays) {
                let x = entrance.centre[0] + entrance.half_mm * (2.0 * rng.random::<f64>() - 1.0);
                let y = entrance.centre[1] + entrance.half_mm * (2.0 * rng.random::<f64>() - 1.0);
                let Some((ray, density)) = entrance.ray_at(source, x, y) else { continue };
                if let Some((path, hit, w)) = walk(&events, ray, film_z, choice, &mut rng) {
                    out.push((path, hit, w * density * area / rays as f64));
                }
            }
            out
        })
        .collect();
    let mut images = PathImages::new();
    for (path, at, w) in chunks.into_iter().flatten() {
        images.entry(path).or_insert_with(|| GhostImage::empty(film)).deposit_point(film, w, at);
    }
    images
}

/// One ray's random walk: the surfaces it reflected at, where it met the
/// film (mm) and its weight; `None` where it did not reach the film.
fn walk(
    events: &[Events],
    mut ray: Ray,
    film_z: f64,
    choice: &(dyn Fn(usize, f64) -> f64 + Sync),
    rng: &mut Xoshiro256PlusPlus,
) -> Option<Landed> {
    let n = events.len();
    let mut k = 0usize;
    let mut weight = 1.0;
    let mut path = Vec::new();
    loop {
        let backward = ray.direction.z < 0.0;
        let e = &events[k];
        let (through, t) = e.refract[backward as usize].trace_fresnel(ray);
        let reflect = match through {
            // met behind itself (trace_fresnel's weight 0): no light goes
            // there
            Outcome::Reached { .. } if t == 0.0 => return None,
            Outcome::Reached { .. } => {
                let r = 1.0 - t;
                let q = if r > 0.0 { choice(k, r).clamp(r.min(1e-6), 1.0 - 1e-6) } else { 0.0 };
                if rng.random::<f64>() < q {
                    weight *= r / q;
                    true
                } else {
                    weight *= t / (1.0 - q);
                    ray = through.ray();
                    false
                }
            }
            Outcome::TotalInternalReflection { .. } => true,
            _ => return None,
        };
        if reflect {
            if path.len() >= MAX_REFLECTIONS {
                return None;
            }
            let back = e.reflect.as_ref()?;
            match back[backward as usize].trace_fresnel(ray) {
                (Outcome::Reached { ray: r, .. }, w) if w > 0.0 => ray = r,
                _ => return None,
            }
            path.push(k);
        }
        if ray.direction.z > 0.0 {
            if k + 1 == n {
                let t = (film_z - ray.origin.z) / ray.direction.z;
                let at = ray.at(t);
                return Some((path, [at.x, at.y], weight));
            }
            k += 1;
        } else {
            k = k.checked_sub(1)?;
        }
    }
}
