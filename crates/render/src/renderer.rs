//! The render loop: rows in parallel (rayon), camera samples made for a
//! group of pixels and traced through the camera as one batch, stratified
//! pixel and aperture samples decorrelated per pixel, deterministic for a
//! given seed.

use crate::camera::lamp_light::{FilmPlan, LampLight, Unseen};
use crate::camera::{Camera, CameraSample, SpectralLane};
use crate::companions;
use crate::image::Image;
use crate::integrator::{radiance_with, FirstBounce};
use crate::rng::{shuffle, stratified, Sampler};
use crate::scene::format::{CompanionsSpec, FilterSpec};
use crate::scene::{ColourMode, Scene};
use crate::spectrum::sampled::N;
use crate::spectrum::{cie, SampledSpectrum, SampledWavelengths};
use crate::splat::{splat_sample, Splats};
use crate::transport::{Rgb, Spectral};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Render settings that may override the scene's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the random streams.
    pub seed: u64,
}

/// What a render measured besides the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    /// Camera rays generated.
    pub camera_rays: usize,
    /// Camera rays that made it through the lens (all of them for pinhole
    /// and thin-lens cameras).
    pub camera_rays_passed: usize,
    /// Seconds spent on lens flare and diffraction (`film.flare`,
    /// `film.diffraction`; 0 when both are off), of the render's time.
    pub flare_seconds: f64,
}

impl Stats {
    /// Fraction of camera rays that passed the lens.
    pub fn pass_rate(&self) -> f64 {
        self.camera_rays_passed as f64 / self.camera_rays.max(1) as f64
    }
}

/// Camera samples made and traced together: a group of pixels' samples go
/// to the camera as one batch (a real lens traces them with the batch
/// tracer), then each is followed into the scene.
const GROUP_SAMPLES: usize = 8192;

/// Rows rendered together before their splats are added, when a render
/// splats (a fixed number, so the image does not depend on the number of
/// threads; other renders take all rows at once).
const BAND_ROWS: usize = 64;

/// Renders `scene`; `progress` is called with the number of finished rows.
///
/// Each pixel has its own random stream (seeded by the render seed and the
/// pixel), so a render does not depend on the number of threads. The first
/// n^2 samples of a pixel (n = floor(sqrt(spp))) are stratified over the
/// pixel and, independently, over the aperture: the aperture strata are
/// visited in a random order drawn per pixel, so the lens position of a
/// sample is uniform and independent of its position in the pixel and the
/// estimator is unbiased at every sample count (docs/rendering.md).
///
/// A spectral scene ([`ColourMode::Spectral`]) gives each sample four
/// wavelengths (hero-wavelength sampling), the heroes stratified over the
/// pixel's samples in a random order of the pixel's own; the pixel sums
/// CIE XYZ and is converted to linear sRGB at the end. Through a
/// dispersive camera the four wavelengths of a sample leave the lens along
/// one scene ray from four film points, combined by multiple importance
/// sampling ([`Camera::rays_spectral`]); with the box filter each
/// wavelength's light goes to the pixel it lands in (`splat.rs`), rows
/// rendered in bands whose splats are added in row order, so the image does
/// not depend on the number of threads. Through a real lens the
/// companions are traced only for the samples bright enough for their
/// colour to matter (`companions.rs`); the others keep their hero alone.
/// An RGB scene draws exactly the random numbers it drew before spectra
/// existed.
pub fn render(scene: &Scene, opt: Options, progress: &(dyn Fn(usize) + Sync)) -> (Image, Stats) {
    let companions = match scene.film.companions {
        CompanionsSpec::Auto => Companions::Auto,
        CompanionsSpec::All => Companions::From(0.0),
    };
    render_with(scene, opt, progress, companions)
}

/// Which spectral samples trace their companion wavelengths through a real
/// lens with glasses (elsewhere they cost nothing and every sample has
/// them). [`render`] takes the scene's choice (`film.companions`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Companions {
    /// Those whose radiance, at the brightest of their four wavelengths,
    /// is at least a threshold set by a pilot (`companions.rs`).
    Auto,
    /// Those whose radiance at the brightest of their wavelengths is at
    /// least this (0: all of them; infinity: none, every sample keeps its
    /// hero alone). Any threshold gives the same image in expectation;
    /// it trades colour noise against time.
    From(f64),
}

/// [`render`] with the choice of which samples trace their companions.
///
/// The loop in one screen: the film is made in bands of rows (all rows at
/// once unless the render splats), each band's rows in parallel
/// (`render_row`), then the band's rows and splats added to the film in
/// row order (`add_band`).
pub fn render_with(
    scene: &Scene,
    opt: Options,
    progress: &(dyn Fn(usize) + Sync),
    companions: Companions,
) -> (Image, Stats) {
    let plan = Plan::new(scene, opt, companions);
    let (w, h) = (plan.width, plan.height);
    let (done, passed) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let mut film: Vec<DVec3> = vec![DVec3::ZERO; w * h];
    let band_rows = if plan.splatting { BAND_ROWS } else { h.max(1) };
    for band in (0..h).step_by(band_rows) {
        let rows: Vec<Row> = (band..(band + band_rows).min(h))
            .into_par_iter()
            .map(|y| {
                let row = render_row(scene, &plan, y);
                passed.fetch_add(row.passed, Ordering::Relaxed);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1);
                row
            })
            .collect();
        add_band(&mut film, band, rows, &plan);
    }
    let mut flare_seconds = 0.0;
    if let Camera::Real(cam) = &scene.camera {
        let fp = FilmPlan { width: w, height: h, filter: scene.film.filter, colour: &scene.colour, seed: opt.seed };
        if let Some(lamps) = &plan.lamps {
            lamps.render(scene, cam, &fp, &mut film);
        }
        let t = std::time::Instant::now();
        crate::camera::flare::render(scene, cam, &fp, &mut film);
        if scene.film.diffraction == crate::scene::format::DiffractionSpec::On {
            let k = crate::camera::diffraction::kernel(cam, &scene.colour, w, h);
            crate::camera::diffraction::convolve(&mut film, w, h, &k);
        }
        flare_seconds = t.elapsed().as_secs_f64();
    }
    let stats =
        Stats { camera_rays: w * h * plan.spp, camera_rays_passed: passed.load(Ordering::Relaxed), flare_seconds };
    (Image { width: w, height: h, pixels: film }, stats)
}

/// What every row of a render shares: the film's size, the sample counts,
/// and the spectral choices made once.
struct Plan {
    width: usize,
    height: usize,
    /// Samples per pixel.
    spp: usize,
    /// Strata per side: the first strata^2 samples of a pixel are
    /// stratified.
    strata: usize,
    /// Pixels whose samples go to the camera as one batch.
    group: usize,
    seed: u64,
    /// Companion wavelengths go to the pixel they land in (a dispersive
    /// camera, spectral, the box filter).
    splatting: bool,
    /// Through a real lens with glasses, the radiance (at the brightest of
    /// its wavelengths) from which a sample traces its companions
    /// (`companions.rs`).
    companions_from: f64,
    /// Through a real lens, the lamps and bright sky whose light is traced
    /// from them (`camera::lamp_light`), and what camera paths therefore
    /// count as black where they meet it first.
    lamps: Option<LampLight>,
    unseen: Unseen,
}

impl Plan {
    fn new(scene: &Scene, opt: Options, companions: Companions) -> Plan {
        let spp = opt.spp.max(1) as usize;
        let lamps = LampLight::build(scene, spp);
        let unseen = lamps.as_ref().map(|l| l.unseen().clone()).unwrap_or_default();
        Plan {
            width: scene.film.width as usize,
            height: scene.film.height as usize,
            spp,
            strata: (spp as f64).sqrt().floor().max(1.0) as usize,
            group: (GROUP_SAMPLES / spp).max(1),
            seed: opt.seed,
            // through a dispersive lens with the box filter, companion
            // wavelengths go to the pixel they land in (`splat`): rows are
            // rendered in bands, each band's splats added in row order once
            // it is done, so the image does not depend on the number of
            // threads
            splatting: matches!(scene.colour, ColourMode::Spectral(_))
                && scene.camera.is_dispersive()
                && scene.film.filter == FilterSpec::Box,
            companions_from: match companions {
                Companions::Auto => companions::threshold(scene, opt.seed, spp, &unseen),
                Companions::From(v) => v,
            },
            lamps,
            unseen,
        }
    }
}

/// One rendered row: its pixels' values, the splats it sends to other
/// pixels (when the render splats), and how many of its camera rays passed
/// the lens.
struct Row {
    pixels: Vec<DVec3>,
    splats: Option<Splats>,
    passed: usize,
}

/// The buffers a row reuses from one group of pixels to the next: the
/// camera samples and what the camera made of them, the strata orders, the
/// first bounces, each sample's wavelengths and radiance.
#[derive(Default)]
struct Scratch {
    samples: Vec<CameraSample>,
    rays: Vec<Option<(crate::geometry::Ray, f64)>>,
    lanes: Vec<Option<(crate::geometry::Ray, [SpectralLane; N])>>,
    order: Vec<usize>,
    colours: Vec<SampledWavelengths>,
    lambda_order: Vec<usize>,
    light_order: Vec<usize>,
    bsdf_order: Vec<usize>,
    firsts: Vec<FirstBounce>,
    radiances: Vec<SampledSpectrum>,
    traced: Vec<bool>,
    selected: Vec<usize>,
}

/// Renders row `y`: its pixels a group at a time, each group's samples
/// drawn ([`draw_samples`]), then followed through the camera and the scene
/// ([`spectral_group`] or [`rgb_group`]).
fn render_row(scene: &Scene, plan: &Plan, y: usize) -> Row {
    let w = plan.width;
    let mut row = Row {
        pixels: Vec::with_capacity(w),
        splats: plan.splatting.then(|| Splats::new(y, w, plan.height)),
        passed: 0,
    };
    let mut scratch = Scratch::default();
    for x0 in (0..w).step_by(plan.group) {
        let xs = x0..(x0 + plan.group).min(w);
        let mut samplers: Vec<Sampler> = xs.clone().map(|x| Sampler::new(plan.seed, (y * w + x) as u64)).collect();
        draw_samples(scene, plan, (xs, y), &mut samplers, &mut scratch);
        match scene.colour {
            ColourMode::Spectral(_) => spectral_group(scene, plan, (x0, y), &mut samplers, &mut scratch, &mut row),
            _ => rgb_group(scene, plan, &mut samplers, &mut scratch, &mut row),
        }
    }
    row
}

/// Each pixel's samples (`spp` of them, pixel by pixel): its film and
/// aperture positions (the first strata^2 stratified, the aperture strata in
/// a random order of the pixel's own), its first bounce's light and
/// direction (strata of their own), and its wavelengths.
fn draw_samples(
    scene: &Scene,
    plan: &Plan,
    (xs, y): (std::ops::Range<usize>, usize),
    samplers: &mut [Sampler],
    b: &mut Scratch,
) {
    let (spp, strata, w, h) = (plan.spp, plan.strata, plan.width, plan.height);
    b.samples.clear();
    b.colours.clear();
    b.firsts.clear();
    for (x, s) in xs.zip(samplers) {
        // the aperture strata in a random order of this pixel's own
        shuffle_strata(&mut b.order, strata, s);
        for k in 0..spp {
            let stratified_k = k < b.order.len();
            let (jx, jy) = if stratified_k { stratified(k, strata, s.next2()) } else { s.next2() };
            let (ox, oy) = match scene.film.filter {
                FilterSpec::Box => (jx, jy),
                FilterSpec::Tent => (0.5 + tent(jx), 0.5 + tent(jy)),
            };
            let a = from_stratum(&b.order, k, strata, s);
            let film = ((x as f64 + ox) / w as f64, (y as f64 + oy) / h as f64);
            b.samples.push(CameraSample::new(film, a));
        }
        // the first bounce's light and direction: strata of their own, each
        // in a random order of the pixel's
        shuffle_strata(&mut b.light_order, strata, s);
        shuffle_strata(&mut b.bsdf_order, strata, s);
        for k in 0..spp {
            let light = from_stratum(&b.light_order, k, strata, s);
            b.firsts.push(FirstBounce { light, bsdf: from_stratum(&b.bsdf_order, k, strata, s) });
        }
        let start = b.colours.len();
        push_wavelengths(scene, spp, s, &mut b.lambda_order, &mut b.colours);
        let first = b.samples.len() - spp;
        for (sample, wl) in b.samples[first..].iter_mut().zip(&b.colours[start..]) {
            sample.wavelength_nm = Some(wl.hero());
        }
    }
}

/// A spectral group of pixels starting at `x0`: the samples through the
/// camera (a dispersive one gives each wavelength its film point; another
/// sends all four along one ray with its plain weight), the paths'
/// radiance, then through a real lens the companions of the paths bright
/// enough to need them, and each pixel's estimate in XYZ made linear sRGB
/// (splatted where the render splats).
fn spectral_group(
    scene: &Scene,
    plan: &Plan,
    (x0, y): (usize, usize),
    samplers: &mut [Sampler],
    b: &mut Scratch,
    row: &mut Row,
) {
    let (spp, w, h) = (plan.spp, plan.width, plan.height);
    let dispersive = scene.camera.is_dispersive();
    if dispersive {
        scene.camera.heroes(&b.samples, &b.colours, &mut b.lanes);
    } else {
        scene.camera.rays(&b.samples, &mut b.rays);
    }
    trace_paths(scene, plan, dispersive, samplers, b, &mut row.passed);
    if dispersive && scene.camera.companions_cost_a_trace() {
        trace_companions(scene, plan, b);
    }
    for i in 0..samplers.len() {
        let x = x0 + i;
        let mut sum = DVec3::ZERO;
        for k in (i * spp..(i + 1) * spp).filter(|&k| b.traced[k]) {
            let (wl, l) = (&b.colours[k], b.radiances[k]);
            sum += if dispersive {
                let Some((_, lane)) = &b.lanes[k] else { continue };
                match row.splats.as_mut() {
                    Some(sp) => splat_sample(wl, l, lane, (x, y), film_cell(plan, k - i * spp, (x, y)), sp),
                    None => {
                        let pixel = |film: (f64, f64)| pixel_density(scene.film.filter, film, (x, y), (w, h));
                        combine(wl, l, lane, pixel)
                    }
                }
            } else {
                let Some((_, weight)) = b.rays[k] else { continue };
                wl.xyz(l) * weight
            };
        }
        row.pixels.push(cie::xyz_to_rgb(sum / (spp as f64 * cie::y_integral())));
    }
}

/// The cell of pixel (`x`, `y`) its `k`th sample's film point was drawn
/// in (box filter): its centre and half-size, film u, v; the pixel itself
/// for the samples beyond the strata.
fn film_cell(plan: &Plan, k: usize, (x, y): (usize, usize)) -> ((f64, f64), (f64, f64)) {
    let (w, h, n) = (plan.width as f64, plan.height as f64, plan.strata);
    // the middle of the cell `draw_samples` jittered in (`stratified`)
    let ((cx, cy), side) = if k < n * n { (stratified(k, n, (0.5, 0.5)), n as f64) } else { ((0.5, 0.5), 1.0) };
    (((x as f64 + cx) / w, (y as f64 + cy) / h), (0.5 / (side * w), 0.5 / (side * h)))
}

/// Each spectral sample that passed the camera followed into the scene:
/// its radiance at its wavelengths (kept with it: the scene may have ended
/// the companions), and whether it was traced.
fn trace_paths(
    scene: &Scene,
    plan: &Plan,
    dispersive: bool,
    samplers: &mut [Sampler],
    b: &mut Scratch,
    passed: &mut usize,
) {
    let spp = plan.spp;
    b.radiances.clear();
    b.radiances.resize(b.samples.len(), SampledSpectrum([0.0; N]));
    b.traced.clear();
    b.traced.resize(b.samples.len(), false);
    for (i, s) in samplers.iter_mut().enumerate() {
        for k in i * spp..(i + 1) * spp {
            let ray = if dispersive {
                match &b.lanes[k] {
                    Some((ray, lane)) if lane[0].transmission > 0.0 => *ray,
                    _ => continue,
                }
            } else {
                match b.rays[k] {
                    Some((ray, w)) if w > 0.0 => ray,
                    _ => continue,
                }
            };
            *passed += 1;
            let mut t = Spectral::new(b.colours[k]);
            b.radiances[k] = radiance_with(scene, ray, &mut t, s, Some(b.firsts[k]), &plan.unseen);
            b.colours[k] = t.wavelengths;
            b.traced[k] = true;
        }
    }
}

/// Through a real lens with glasses, the companion wavelengths traced for
/// the paths at least `plan.companions_from` bright (`companions.rs`); the
/// others keep their hero alone.
fn trace_companions(scene: &Scene, plan: &Plan, b: &mut Scratch) {
    b.selected.clear();
    for k in 0..b.samples.len() {
        let wl = &mut b.colours[k];
        if !b.traced[k] || wl.secondary_terminated() {
            continue;
        }
        if b.radiances[k].max_element() >= plan.companions_from {
            b.selected.push(k);
        } else {
            wl.terminate_secondary();
        }
    }
    scene.camera.companions(&b.colours, &mut b.lanes, &b.selected);
}

/// An RGB (or one-wavelength) group of pixels: the samples through the
/// camera, each that passed followed into the scene, each pixel the mean
/// of its samples' weighted radiance.
fn rgb_group(scene: &Scene, plan: &Plan, samplers: &mut [Sampler], b: &mut Scratch, row: &mut Row) {
    let spp = plan.spp;
    scene.camera.rays(&b.samples, &mut b.rays);
    for (i, s) in samplers.iter_mut().enumerate() {
        let mut sum = DVec3::ZERO;
        for k in i * spp..(i + 1) * spp {
            let Some((ray, weight)) = b.rays[k] else { continue };
            if weight <= 0.0 {
                continue;
            }
            row.passed += 1;
            let first = Some(b.firsts[k]);
            sum += weight
                * match scene.colour {
                    ColourMode::Monochromatic(nm) => {
                        let mut t = Spectral::new(SampledWavelengths::single(nm));
                        DVec3::splat(radiance_with(scene, ray, &mut t, s, first, &plan.unseen).0[0])
                    }
                    _ => radiance_with(scene, ray, &mut Rgb, s, first, &plan.unseen),
                };
        }
        row.pixels.push(sum / spp as f64);
    }
}

/// Adds a band of rows to the film: each row's own values, then the band's
/// splats (which may reach rows of other bands), in row order.
fn add_band(film: &mut [DVec3], band: usize, rows: Vec<Row>, plan: &Plan) {
    let w = plan.width;
    let mut band_splats = Vec::new();
    for (y, row) in (band..).zip(rows) {
        for (p, v) in film[y * w..(y + 1) * w].iter_mut().zip(row.pixels) {
            *p += v;
        }
        band_splats.extend(row.splats);
    }
    let scale = 1.0 / (plan.spp as f64 * cie::y_integral());
    for sp in band_splats {
        sp.merge_into(film, scale);
    }
}

/// The XYZ estimate (times ∫ȳ) of one spectral camera sample: its
/// radiance `l` at each of its wavelengths, combined by the balance
/// heuristic over the densities with which the camera would have drawn the
/// same scene ray with each wavelength as the hero (each lane's camera
/// density times the pixel filter's density at that lane's film point;
/// Wilkie et al. 2014). Where the scene has ended the companions (a
/// dispersive material), the hero alone.
fn combine(
    wl: &SampledWavelengths,
    l: SampledSpectrum,
    lanes: &[SpectralLane; N],
    pixel: impl Fn((f64, f64)) -> f64,
) -> DVec3 {
    let mut pix = [0.0; N];
    for j in 0..N {
        if lanes[j].density > 0.0 {
            pix[j] = pixel(lanes[j].film);
        }
    }
    if wl.secondary_terminated() {
        let (lane, p) = (&lanes[0], pix[0] * lanes[0].density);
        return if p > 0.0 {
            cie::cmf(wl.nm[0]) * (l.0[0] * lane.transmission * pix[0] / (wl.pdf[0] * p))
        } else {
            DVec3::ZERO
        };
    }
    let mut total = 0.0;
    for m in 0..N {
        total += pix[m] * lanes[m].density;
    }
    if total.is_nan() || total <= 0.0 {
        return DVec3::ZERO;
    }
    let mut xyz = DVec3::ZERO;
    for j in 0..N {
        let f = l.0[j] * lanes[j].transmission * pix[j];
        if f != 0.0 {
            xyz += cie::cmf(wl.nm[j]) * (f / wl.pdf[j]);
        }
    }
    xyz / total
}

/// The density of the pixel filter for film point `film` (u, v in [0, 1])
/// in pixel `(x, y)` of a `(w, h)` image, per pixel area: the box filter's
/// 1 inside the pixel, the tent's product of triangles over two pixels.
fn pixel_density(filter: FilterSpec, film: (f64, f64), (x, y): (usize, usize), (w, h): (usize, usize)) -> f64 {
    let ox = film.0 * w as f64 - x as f64;
    let oy = film.1 * h as f64 - y as f64;
    match filter {
        FilterSpec::Box => {
            if (0.0..1.0).contains(&ox) && (0.0..1.0).contains(&oy) {
                1.0
            } else {
                0.0
            }
        }
        FilterSpec::Tent => (1.0 - (ox - 0.5).abs()).max(0.0) * (1.0 - (oy - 0.5).abs()).max(0.0),
    }
}

/// Appends the wavelengths of a pixel's `spp` samples to `out` (nothing
/// for an RGB render): heroes stratified over the sampling distribution's
/// CDF, the strata in a random order drawn from the pixel's stream.
fn push_wavelengths(
    scene: &Scene,
    spp: usize,
    s: &mut Sampler,
    order: &mut Vec<usize>,
    out: &mut Vec<SampledWavelengths>,
) {
    match &scene.colour {
        ColourMode::Rgb => {}
        ColourMode::Monochromatic(nm) => out.extend(std::iter::repeat_n(SampledWavelengths::single(*nm), spp)),
        ColourMode::Spectral(range) => {
            order.clear();
            order.extend(0..spp);
            shuffle(order, s);
            out.extend(order.iter().map(|&k| range.sample_four((k as f64 + s.uniform()) / spp as f64)));
        }
    }
}

/// The `strata` x `strata` cells in a random order of the pixel's stream.
fn shuffle_strata(order: &mut Vec<usize>, strata: usize, s: &mut Sampler) {
    order.clear();
    order.extend(0..strata * strata);
    shuffle(order, s);
}

/// Sample `k`'s two uniforms: jittered in cell `order[k]`, or plain beyond
/// the strata.
fn from_stratum(order: &[usize], k: usize, strata: usize, s: &mut Sampler) -> (f64, f64) {
    match order.get(k) {
        Some(&o) => stratified(o, strata, s.next2()),
        None => s.next2(),
    }
}

/// Tent-distributed offset in [-1, 1] from a uniform.
fn tent(u: f64) -> f64 {
    let t = 2.0 * u;
    if t < 1.0 {
        t.sqrt() - 1.0
    } else {
        1.0 - (2.0 - t).sqrt()
    }
}
