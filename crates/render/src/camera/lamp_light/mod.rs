//! Light traced from the scene's lamps through a real lens onto the film.
//!
//! A lamp (an emissive sphere) seen through a real lens out of focus is a
//! disc of many pixels, each lit through a small patch of the pupil that a
//! camera ray finds only by chance. Traced the other way, from the lamp
//! into the lens, every ray that passes lands somewhere in the disc. The
//! film's measurement (`real_lens.rs`) is, per pixel, `1 / (norm A_pix)`
//! times the integral of radiance over the étendue `dG` of the rays that
//! reach the pixel (on the film side `dA(x) dA(r) = d^2 / cos^4 dG`, so
//! the camera's weight `cos^4 / d^2` leaves `dG` alone); `dG` is conserved
//! through the lens, and on the object side it is `cos θ_g dA(g) dω` for a
//! ray crossing the front plane (square to the axis, in front of the first
//! surface) at `g` in direction `ω`. So a pixel's light from a lamp is
//!
//! ```text
//! 1 / (norm A_pix) ∫ dA(g) ∫_{cone of the lamp from g} L T cos θ_g dω
//! ```
//!
//! over the rays that reach the pixel unoccluded. [`LampLight::build`]
//! probes, per lamp, the cells of the front plane through which its light
//! can pass (`probe.rs`: from the lamp's centre and rings across its disc,
//! at the render's extreme wavelengths, dilated by a cell) and sizes the
//! draw at about [`BUDGET`] x spp passing rays per pixel of the lamp's
//! image. [`LampLight::render`] draws `g` on a jittered grid over those
//! cells in spp passes, every ray of a pass sharing one direction `ω`
//! (stratified over the lamp's cone from pass to pass), so each pass lands
//! as a warped jittered grid over the blur disc: smooth pixel to pixel.
//! Each ray is traced into the lens (its stop shape included) when the
//! scene ray from `g` meets the lamp first, and splatted with the pixel
//! filter. Camera paths that see such a lamp directly through the lens
//! count nothing for it ([`LampLight::unseen`]), so every light path is
//! counted once: the picture is the same in expectation, without the
//! discs' noise (docs/rendering.md measures both). A lamp whose own image
//! is as large as its blur is left to the camera paths, which do better on
//! a resolved image; so are the bright patches of an environment
//! (`sky_patches.rs`), traced the same way otherwise.
//!
//! Spectral renders give each ray four wavelengths (hero-wavelength
//! sampling, the heroes stratified over a task's rays); through a
//! dispersive lens each is traced on its own and lands where its glass
//! indices take it.

use super::real_lens::RealLensCamera;
use super::sky_patches::{self, SkyPatch};
use super::Camera;
use crate::geometry::{Shape, EPS};
use crate::material::Material;
use crate::rng::{shuffle, stratified, Sampler};
use crate::scene::format::FilterSpec;
use crate::scene::{Background, ColourMode, Scene};
use crate::spectrum::sampled::N;
use crate::spectrum::{cie, SampledWavelengths};
use crate::transport::{Rgb, Spectral, Transport};
use glam::{DVec2, DVec3};
use lens::trace::SpectralBatch;
use rayon::prelude::*;
use std::f64::consts::PI;

mod probe;
use probe::{probe_wavelengths, Probe};

/// Cells per side of the grids a lamp's front plane is probed on.
const COARSE: usize = 24;
const GRID: usize = 32;
/// Passing rays per pixel of a lamp's image, per sample per pixel (on the
/// bokeh scene, `report-real-lens.json`, 1, 4, 8 and 16 gave relative RMSE
/// 0.86, 0.41, 0.30, 0.29 at 16 spp, the last at the reference's noise,
/// for 0.10, 0.15, 0.20, 0.30 s: 8 is the least error for the time).
const BUDGET: f64 = 8.0;
/// Emissive spheres traced, at most: the most powerful into the lens
/// (radiance times cross-section over distance squared); any others are
/// left to camera paths, so a scene of thousands of small lights does not
/// spend its time probing them.
const MAX_SPHERES: usize = 256;

/// Rays traced from all sources together, at most, per camera sample of
/// the render: a source that fills the frame draws no more than about
/// what the camera paths cost.
const MAX_RAYS_PER_SAMPLE: f64 = 2.0;

/// Grid points handled together (one task).
const TASK_RAYS: usize = 2048;
/// Tasks run in parallel before their splats are added.
const WAVE: usize = 64;

/// The lamps of a scene traced through a real lens, ready to render.
#[derive(Debug, Clone)]
pub struct LampLight {
    lamps: Vec<Lamp>,
    /// What camera paths leave to the lamps.
    unseen: Unseen,
    /// z of the front plane, mm (lens frame): in front of the first
    /// surface everywhere inside its clear aperture.
    z0: f64,
}

/// One lamp: where it is, the cells of the front plane its light can pass
/// through, and how its rays are drawn.
#[derive(Debug, Clone)]
struct Lamp {
    /// Where its light comes from.
    source: Source,
    /// The probe grid: its lower corner (mm, front plane), cell side (mm),
    /// and which of its `GRID` x `GRID` cells may pass light.
    lo: DVec2,
    cell: f64,
    live: Vec<bool>,
    /// Passes over the front plane: each a jittered grid of spacing
    /// `spacing` (mm) over the probe grid, the points in live cells traced,
    /// every ray of a pass along one direction toward the source (its
    /// uniforms shared): the source's image being smaller than its blur,
    /// a pass lands as a warped jittered grid over the blur disc, smooth
    /// pixel to pixel.
    passes: usize,
    spacing: f64,
    /// Rays drawn in all (about).
    rays: f64,
}

/// A light source traced into the lens.
#[derive(Debug, Clone)]
enum Source {
    /// An emissive sphere: its primitive, centre (lens frame, mm) and
    /// radius (mm).
    Sphere { prim: usize, centre: DVec3, radius: f64 },
    /// A patch of bright texels of the environment.
    Sky(SkyPatch),
}

/// What camera paths count as black where they meet it first, because
/// [`LampLight`] traces its light from the source: emissive spheres, and
/// environment texels.
#[derive(Debug, Clone, Default)]
pub struct Unseen {
    prims: Vec<usize>,
    /// The environment image's size and its traced texels.
    sky: Option<(usize, usize, Vec<bool>)>,
}

impl Unseen {
    /// Nothing unseen.
    pub const NONE: Unseen = Unseen { prims: Vec::new(), sky: None };

    /// Whether primitive `prim` is traced from its light.
    pub fn prim(&self, prim: usize) -> bool {
        self.prims.binary_search(&prim).is_ok()
    }

    /// Whether the environment along `d` (scene frame) is traced from its
    /// light.
    pub fn sky(&self, d: DVec3) -> bool {
        match &self.sky {
            Some((w, h, mask)) => {
                let (x, y) = sky_patches::texel_of(d, *w, *h);
                mask[y * w + x]
            }
            None => false,
        }
    }
}

/// The light a ray carries from its source, evaluated per transport.
enum Emit<'a> {
    /// An emissive material seen at `cos` to its normal.
    Material(&'a Material, f64),
    /// The environment along a direction (scene frame).
    Sky(DVec3),
}

impl Emit<'_> {
    fn value<T: Transport>(&self, scene: &Scene, t: &T) -> T::Value {
        match self {
            Emit::Material(m, cos) => m.emitted(t, *cos),
            Emit::Sky(d) => scene.background.radiance(t, *d),
        }
    }
}

impl Source {
    /// A ray from front-plane point `g` (lens frame, mm) toward the source
    /// drawn with the uniforms `u`: its direction (lens frame, toward the
    /// source), the inverse of its density per steradian, and what it
    /// carries; `None` where the scene hides the source from `g` along it.
    fn sample<'a>(
        &self,
        scene: &'a Scene,
        cam: &RealLensCamera,
        g: DVec3,
        u: (f64, f64),
    ) -> Option<(DVec3, f64, Emit<'a>)> {
        match self {
            Source::Sphere { prim, centre, radius } => {
                let (omega, solid) = cone_sample(g, *centre, *radius, u)?;
                // unoccluded: the scene ray from g toward the lamp meets it first
                let ray = cam.ray_to_scene(g, omega);
                let eps = EPS * (1.0 + ray.origin.abs().max_element());
                let (hit_prim, hit) = scene.intersect(&ray, eps, f64::INFINITY)?;
                let cos_out = -ray.dir.dot(hit.n);
                (hit_prim == *prim && cos_out > 0.0)
                    .then(|| (omega, solid, Emit::Material(&scene.materials[scene.material_of[*prim]], cos_out)))
            }
            Source::Sky(patch) => {
                let (d, pdf) = patch.sample(u)?;
                let omega = cam.dir_to_lens(d);
                // unoccluded: the scene ray from g leaves the scene
                let ray = cam.ray_to_scene(g, omega);
                let eps = EPS * (1.0 + ray.origin.abs().max_element());
                scene.intersect(&ray, eps, f64::INFINITY).is_none().then(|| (omega, 1.0 / pdf, Emit::Sky(ray.dir)))
            }
        }
    }
}

impl Lamp {
    /// Grid points per side of a pass.
    fn points(&self) -> usize {
        ((GRID as f64 * self.cell / self.spacing).ceil() as usize).max(1)
    }

    /// Whether front-plane point `g` (mm) lies in a live cell.
    fn is_live(&self, g: DVec2) -> bool {
        let k = (g - self.lo) / self.cell;
        k.x >= 0.0
            && k.y >= 0.0
            && k.x < GRID as f64
            && k.y < GRID as f64
            && self.live[k.y as usize * GRID + k.x as usize]
    }
}

/// What a render's splats need from the scene: film size, filter, colour.
pub(crate) struct FilmPlan<'a> {
    /// Film size, pixels.
    pub width: usize,
    pub height: usize,
    pub filter: FilterSpec,
    pub colour: &'a ColourMode,
    pub seed: u64,
}

/// One task: grid rows `rows` of pass `pass` of lamp `lamp`, with the
/// pass's direction uniforms when its rays share them.
#[derive(Debug, Clone)]
struct Task {
    lamp: usize,
    pass: usize,
    rows: std::ops::Range<usize>,
    shared: (f64, f64),
}

impl LampLight {
    /// Models the scene's emissive spheres seen through `cam` for a render
    /// of `spp` samples per pixel: for each, the cells of the front plane
    /// through which its light can pass (probed from the lamp's centre and
    /// rings across its disc at the wavelengths the render samples, then
    /// dilated by a cell) and how many rays to draw (about [`BUDGET`] x
    /// spp passing rays per pixel of its image). A lamp reaching the front
    /// plane, or with no probe passing onto the film, is left to the
    /// camera paths. `None` when no lamp is modelled, the camera is not a
    /// real lens, or the scene's `lamp_tracing` is off.
    pub fn build(scene: &Scene, spp: usize) -> Option<LampLight> {
        let Camera::Real(cam) = &scene.camera else { return None };
        if !scene.lamp_tracing {
            return None;
        }
        let p = cam.prescription();
        let s0 = &p.surfaces()[0];
        let sd = s0.semi_diameter.unwrap_or(3.0 * p.stop_semi_diameter());
        let sags: Vec<f64> = (0..=32).filter_map(|k| s0.sag(sd * k as f64 / 32.0)).collect();
        let z0 = sags.iter().fold(0.0f64, |a, &b| a.min(b)) - 0.5;
        let sag_max = sags.iter().fold(0.0f64, |a, &b| a.max(b));
        let (nms, spectral) = probe_wavelengths(scene, cam);
        let (w, h) = (scene.film.width as usize, scene.film.height as usize);
        let mut sources: Vec<Source> = (0..scene.shapes.len())
            .filter(|&i| matches!(scene.materials[scene.material_of[i]], Material::Emissive { .. }))
            .filter_map(|i| match scene.shapes[i] {
                Shape::Sphere { center, radius } => {
                    Some(Source::Sphere { prim: i, centre: cam.point_to_lens(center), radius: radius * 1e3 })
                }
                _ => None,
            })
            .collect();
        // the most powerful spheres, by the flux they send toward the lens
        if sources.len() > MAX_SPHERES {
            let flux = |s: &Source| match s {
                Source::Sphere { prim, centre, radius } => {
                    let l = match &scene.materials[scene.material_of[*prim]] {
                        Material::Emissive { radiance } => Rgb.radiance(radiance).max_element(),
                        _ => 0.0,
                    };
                    l * radius * radius / centre.length_squared().max(f64::MIN_POSITIVE)
                }
                Source::Sky(_) => f64::INFINITY,
            };
            sources.sort_by(|a, b| flux(b).total_cmp(&flux(a)));
            sources.truncate(MAX_SPHERES);
        }
        let env = match &scene.background {
            Background::Environment(img) => Some((img.width, img.height)),
            _ => None,
        };
        if let Background::Environment(img) = &scene.background {
            sources.extend(sky_patches::find(img).into_iter().map(Source::Sky));
        }
        let mut lamps: Vec<Lamp> = sources
            .into_par_iter()
            .filter_map(|source| {
                let probe = Probe { cam, z0, nms: &nms, spectral, film: (w, h) };
                probe.model(source, sd, sag_max, spp)
            })
            .collect();
        // at most MAX_RAYS_PER_SAMPLE rays a camera sample: every source's
        // grid made coarser alike where the sum would pass it
        let total: f64 = lamps.iter().map(|l| l.rays).sum();
        let cap = MAX_RAYS_PER_SAMPLE * (spp * w * h) as f64;
        if total > cap {
            for l in &mut lamps {
                l.spacing *= (total / cap).sqrt();
                l.rays *= cap / total;
            }
        }
        let mut unseen = Unseen::default();
        for l in &lamps {
            match &l.source {
                Source::Sphere { prim, .. } => unseen.prims.push(*prim),
                Source::Sky(patch) => {
                    let (w, h) = env.expect("a sky patch comes from an environment");
                    let mask = unseen.sky.get_or_insert_with(|| (w, h, vec![false; w * h]));
                    for &k in patch.texels() {
                        mask.2[k] = true;
                    }
                }
            }
        }
        unseen.prims.sort_unstable();
        (!lamps.is_empty()).then_some(LampLight { lamps, unseen, z0 })
    }

    /// The primitives whose light seen directly through the lens comes
    /// from here (sorted): camera paths count nothing for them at their
    /// first hit.
    pub fn lamps(&self) -> &[usize] {
        &self.unseen.prims
    }

    /// Rays drawn from all sources in a render (about).
    pub fn rays(&self) -> f64 {
        self.lamps.iter().map(|l| l.rays).sum()
    }

    /// The patches of the environment traced from their light.
    pub fn sky_patches(&self) -> usize {
        self.lamps.iter().filter(|l| matches!(l.source, Source::Sky(_))).count()
    }

    /// What camera paths count as black where they meet it first.
    pub fn unseen(&self) -> &Unseen {
        &self.unseen
    }

    /// Adds the lamps' light to `film` (linear sRGB, `width * height`
    /// pixels, row-major): every lamp's rays traced and splatted, the same
    /// image on any number of threads.
    pub(crate) fn render(&self, scene: &Scene, cam: &RealLensCamera, plan: &FilmPlan, film: &mut [DVec3]) {
        let mut tasks = Vec::new();
        for (li, l) in self.lamps.iter().enumerate() {
            // the passes' shared directions, stratified over the cone in a
            // random order
            let mut s = Sampler::new(plan.seed ^ 0x6c61_6d70_7061_7373, li as u64);
            let q = (l.passes as f64).sqrt().floor() as usize;
            let mut dirs: Vec<usize> = (0..q * q).collect();
            shuffle(&mut dirs, &mut s);
            let n = l.points();
            let rows = (TASK_RAYS / n).max(1);
            for pass in 0..l.passes {
                let shared = match dirs.get(pass) {
                    Some(&k) => stratified(k, q, s.next2()),
                    None => s.next2(),
                };
                for r in (0..n).step_by(rows) {
                    tasks.push(Task { lamp: li, pass, rows: r..(r + rows).min(n), shared });
                }
            }
        }
        for wave in tasks.chunks(WAVE) {
            let splats: Vec<Vec<(usize, DVec3)>> = wave.par_iter().map(|t| self.task(scene, cam, plan, t)).collect();
            for (i, v) in splats.into_iter().flatten() {
                film[i] += v;
            }
        }
    }

    /// The splats (pixel index, linear sRGB) of one task's rays.
    fn task(&self, scene: &Scene, cam: &RealLensCamera, plan: &FilmPlan, task: &Task) -> Vec<(usize, DVec3)> {
        let l = &self.lamps[task.lamp];
        let n = l.points();
        let stream = ((task.lamp as u64) << 40) | ((task.pass as u64) << 20) | task.rows.start as u64;
        let mut s = Sampler::new(plan.seed ^ 0x6c61_6d70_6c69_6768, stream);
        let p = cam.prescription();
        let dispersive = p.is_dispersive();
        let (spectral, lanes) = match plan.colour {
            ColourMode::Spectral(_) if dispersive => (true, N),
            ColourMode::Monochromatic(_) => (dispersive, 1),
            _ => (false, 1),
        };
        let primary = p.wavelength_nm();
        let a_pix = cam.sensor_mm()[0] * cam.sensor_mm()[1] / (plan.width * plan.height) as f64;
        let scale = l.spacing * l.spacing / (l.passes as f64 * cam.centre_weight() * a_pix);
        let count = task.rows.len() * n;
        let mut batch = SpectralBatch::with_capacity(count * lanes);
        // per ray: its weight (without T) and what it carries
        let mut rays: Vec<(f64, Carry)> = Vec::with_capacity(count);
        let mut wl_order: Vec<usize> = (0..count).collect();
        shuffle(&mut wl_order, &mut s);
        for (k, (j, i)) in task.rows.clone().flat_map(|j| (0..n).map(move |i| (j, i))).enumerate() {
            let (jx, jy) = s.next2();
            let g2 = l.lo + DVec2::new(i as f64 + jx, j as f64 + jy) * l.spacing;
            // wavelengths stratified over the task's rays (a ray's own,
            // so a dispersive lens's fringes are sampled by every ray)
            let u_wl = (wl_order[k] as f64 + s.uniform()) / count as f64;
            let u_dir = task.shared;
            if !l.is_live(g2) {
                continue;
            }
            let g = DVec3::new(g2.x, g2.y, self.z0);
            let Some((omega, solid, emit)) = l.source.sample(scene, cam, g, u_dir) else { continue };
            let d_in = -omega;
            if d_in.z <= 0.0 {
                continue;
            }
            let weight = d_in.z * solid * scale;
            let into = lens::Ray { origin: g, direction: d_in };
            let carry = match plan.colour {
                ColourMode::Rgb => {
                    batch.push(into, primary);
                    Carry::Rgb(emit.value(scene, &Rgb))
                }
                ColourMode::Monochromatic(nm) => {
                    batch.push(into, *nm);
                    let wl = SampledWavelengths::single(*nm);
                    Carry::Grey(emit.value(scene, &Spectral::new(wl)).0[0])
                }
                ColourMode::Spectral(range) => {
                    let wl = range.sample_four(u_wl);
                    let le = emit.value(scene, &Spectral::new(wl));
                    if spectral {
                        for nm in wl.nm {
                            batch.push(into, nm);
                        }
                        Carry::Lanes(wl, le.0)
                    } else {
                        batch.push(into, primary);
                        Carry::Rgb(cie::xyz_to_rgb(wl.xyz(le) / cie::y_integral()))
                    }
                }
            };
            rays.push((weight, carry));
        }
        let mut t = Vec::new();
        cam.trace_to_film(&mut batch, spectral, &mut t);
        let b = &batch.rays;
        let mut out = Vec::with_capacity(batch.len());
        let mut k = 0;
        for (weight, carry) in &rays {
            let lanes_here = if let Carry::Lanes(..) = carry { N } else { 1 };
            for j in 0..lanes_here {
                let i = k + j;
                if b.status[i] != 0 || t[i] <= 0.0 {
                    continue;
                }
                let value = match carry {
                    Carry::Rgb(v) => *v,
                    Carry::Grey(v) => DVec3::splat(*v),
                    Carry::Lanes(wl, le) => {
                        cie::xyz_to_rgb(cie::cmf(wl.nm[j]) * (le[j] / (wl.pdf[j] * N as f64 * cie::y_integral())))
                    }
                };
                let uv = cam.film_uv(b.x[i], b.y[i]);
                splat(plan, uv, value * (weight * t[i]), &mut out);
            }
            k += lanes_here;
        }
        out
    }
}

/// What a lamp ray carries to the film.
enum Carry {
    /// Linear sRGB (an RGB render, or a spectral one through a lens
    /// without glasses: the four wavelengths land together).
    Rgb(DVec3),
    /// One wavelength's radiance (a monochromatic render).
    Grey(f64),
    /// The four wavelengths and their radiance, each traced on its own.
    Lanes(SampledWavelengths, [f64; N]),
}

/// Adds `value` at film position `uv` to the pixels the filter reaches.
fn splat(plan: &FilmPlan, (u, v): (f64, f64), value: DVec3, out: &mut Vec<(usize, DVec3)>) {
    let (w, h) = (plan.width, plan.height);
    let (x, y) = (u * w as f64, v * h as f64);
    if !(x.is_finite() && y.is_finite()) {
        return;
    }
    match plan.filter {
        FilterSpec::Box => {
            if x >= 0.0 && y >= 0.0 && x < w as f64 && y < h as f64 {
                out.push((y as usize * w + x as usize, value));
            }
        }
        FilterSpec::Tent => {
            let (x0, y0) = ((x - 0.5).floor(), (y - 0.5).floor());
            for py in [y0, y0 + 1.0] {
                for px in [x0, x0 + 1.0] {
                    if px < 0.0 || py < 0.0 || px >= w as f64 || py >= h as f64 {
                        continue;
                    }
                    let f = (1.0 - (x - px - 0.5).abs()).max(0.0) * (1.0 - (y - py - 0.5).abs()).max(0.0);
                    if f > 0.0 {
                        out.push((py as usize * w + px as usize, value * f));
                    }
                }
            }
        }
    }
}

/// A direction from `g` uniformly in the cone that the sphere (`c`, `r`)
/// subtends there, from the uniforms `u`, and the cone's solid angle;
/// `None` when `g` is inside the sphere.
fn cone_sample(g: DVec3, c: DVec3, r: f64, u: (f64, f64)) -> Option<(DVec3, f64)> {
    let to = c - g;
    let dist = to.length();
    if dist <= r {
        return None;
    }
    let a = to / dist;
    let cos_max = (1.0 - (r / dist).powi(2)).max(0.0).sqrt();
    let cos = 1.0 - u.0 * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u.1;
    let (e1, e2) = a.any_orthonormal_pair();
    Some(((a * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin).normalize(), 2.0 * PI * (1.0 - cos_max)))
}
