//! Lens flare through a real lens (`film.flare`): the ghosts of the
//! scene's bright sources, the light the primary image loses to them, and
//! (`ghosts+glare`) the veil of the light reflected four times or more.
//!
//! - Sources: the emissive spheres (each taken as a point at its centre of
//!   the intensity its disc sends toward the lens), the emissive quads
//!   that look small from the lens (within [`FLAT_SOURCE_RAD`]; their
//!   area times the cosine toward the lens) and the bright patches of an
//!   environment (each a direction, the patch's power-weighted centre, of
//!   the irradiance its texels give): the [`MAX_SOURCES`] most powerful
//!   that the lens's front vertex sees unoccluded.
//! - Ghosts: every two-reflection path of the lens (`lens::ghost`), each
//!   source's image through it rasterised from a ray grid with Fresnel
//!   weights at each ray's angle and wavelength (`lens::ghost::rasterise`,
//!   checked against the brute-force reference in the lens crate), at
//!   [`WAVELENGTHS`] wavelengths for colour (dispersion and coatings make
//!   ghosts coloured). A first look at the primary wavelength on a coarse
//!   grid drops the faintest ghosts (while their peaks together stay below
//!   [`VISIBLE`] of the image's mean) and sizes each kept ghost's grid: a
//!   large ghost is rasterised on a grid of coarser pixels, then added
//!   bilinearly. Stopped down, the look covers only where light that
//!   reaches the stop entered (the source's footprint for a ghost
//!   reflected at or past the stop, the cells whose rays meet the stop's
//!   opening for one reflected in front of it).
//! - The primary image: multiplied by the lens's transmittance (the
//!   product of 1 - R over its surfaces), per film radius and colour, the
//!   mean over the pupil (docs/rendering.md gives its error).
//! - Glare: the light of the paths with four reflections or more, from
//!   the incoherent multiple reflection of the surfaces at normal
//!   incidence, spread evenly over the frame.
//!
//! A film pixel measures `1 / (norm A_pix)` times the power reaching it
//! (`lamp_light`), so a ghost adds its irradiance over `norm`.

mod bands;
mod entrance;
mod sources;

use super::lamp_light::FilmPlan;
use super::real_lens::RealLensCamera;
use crate::scene::format::FlareSpec;
use crate::scene::Scene;
use bands::{dispersed, interpolate, wavelengths, FineBands};
pub use bands::{FINE, OVERLAP};
use entrance::{footprints, toward_stop};
use glam::DVec3;
use lens::coating::ReflectanceTable;
use lens::ghost::image::Entrance;
use lens::ghost::{ghost_pairs, rasterise_with, FilmGrid, EDGE_STEPS};
use lens::trace::StopShape;
use lens::{Outcome, Prescription, Ray, Tracer};
use rayon::prelude::*;
pub use sources::FLAT_SOURCE_RAD;
use sources::{bright_sources, Bright};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// Sources whose ghosts are drawn, at most (the most powerful).
pub const MAX_SOURCES: usize = 16;
/// Wavelengths a ghost is rasterised at (midpoints of equal bands over
/// 400-700 nm) in a colour render: enough for the colour of coatings and
/// dispersion, which vary slowly with wavelength.
pub const WAVELENGTHS: usize = 4;
/// The faintest ghosts are left out while their peaks sum to less than
/// this fraction of the image's mean luminance (what they would have added
/// to any pixel).
pub const VISIBLE: f64 = 1e-3;
/// Cells across the entrance grid of the first look (over the front
/// element's square, or stopped down the part of it whose light reaches
/// the stop) and of the drawing (over the part the look saw light take).
/// Wide open, 16 cells stepped over the light of 116 of the night street's
/// 1,961 lit ghosts (vignetted to slivers), 10% of the ghost light; 24
/// leave 5% (docs/rendering.md).
const LOOK_CELLS: usize = 24;
const DRAW_CELLS: usize = 16;
/// Times a looked-at cell at a clear aperture's edge is split: none (the
/// light's edge in it is still found by bisection, enough to judge a
/// ghost's peak and extent; splitting twice doubled the flare's cost
/// wide open and changed no picture).
const LOOK_SPLITS: u32 = 0;
/// Bisections that place the light's edge in a looked-at cell (to a
/// sixteenth of its side: fewer made the peaks too coarse to judge which
/// ghosts to leave out).
const LOOK_EDGE_STEPS: u32 = 4;
/// Times a drawn cell whose corners disagree (at a clear aperture's edge)
/// is split.
const DRAW_SPLITS: u32 = 1;
/// The most grid pixels across a ghost's drawing: a larger ghost goes to
/// a grid of pixels 2, 4, 8 or 16 film pixels wide.
const DRAW_PIXELS: f64 = 96.0;

/// A ghost of a source worth drawing, as the first look found it.
#[derive(Clone, Copy)]
struct Looked {
    /// The source (an index into the bright sources).
    source: usize,
    /// The ghost: its index in the lens's list of surface pairs.
    path: usize,
    /// The part of the entrance plane its light took.
    entrance: Entrance,
    /// Its extent on the film: lower and upper corners, mm.
    lo: [f64; 2],
    hi: [f64; 2],
}

/// Adds the lens flare of `scene` through `cam` to `film` (linear sRGB,
/// row-major): the primary image dimmed by the lens's transmittance, then
/// the ghosts (and glare) added. Nothing when `film.flare` is off.
pub(crate) fn render(scene: &Scene, cam: &RealLensCamera, plan: &FilmPlan, film: &mut [DVec3]) {
    if scene.film.flare == FlareSpec::Off {
        return;
    }
    let (w, h) = (plan.width, plan.height);
    let mean = film.iter().map(|v| luminance(*v)).sum::<f64>() / film.len().max(1) as f64;
    let (nms, colours) = wavelengths(plan.colour);
    let p = cam.prescription();
    let lenses: Vec<Prescription> = nms.iter().map(|&nm| p.at_wavelength(nm).unwrap_or_else(|_| p.clone())).collect();
    dim_by_transmittance(cam, &lenses, &colours, w, h, film);
    let layer = ghost_layer(scene, cam, w, h, VISIBLE * mean.max(1e-12));
    for (px, add) in film.iter_mut().zip(layer) {
        *px += add;
    }
}

/// The ghosts (and, for `ghosts+glare`, the glare) of `scene` through
/// `cam` on a `w` x `h` film (linear sRGB, row-major, the scene's colour
/// mode): what [`render`] adds to the image. The faintest ghosts whose
/// peaks at the primary wavelength sum to below `floor` (film units) are
/// left out.
pub fn ghost_layer(scene: &Scene, cam: &RealLensCamera, w: usize, h: usize, floor: f64) -> Vec<DVec3> {
    ghost_layer_banded(scene, cam, w, h, floor, FINE).0
}

/// [`ghost_layer`] with each flare band cut into `fine` bands for a ghost
/// whose copies lie apart ([`dispersed`]; 1: none is), and how many
/// ghosts were drawn so.
fn ghost_layer_banded(
    scene: &Scene,
    cam: &RealLensCamera,
    w: usize,
    h: usize,
    floor: f64,
    fine: usize,
) -> (Vec<DVec3>, usize) {
    let mut film = vec![DVec3::ZERO; w * h];
    let (nms, colours) = wavelengths(&scene.colour);
    let p = cam.prescription();
    let lenses: Vec<Prescription> = nms.iter().map(|&nm| p.at_wavelength(nm).unwrap_or_else(|_| p.clone())).collect();
    let sources = bright_sources(scene, cam, &nms);
    if sources.is_empty() {
        return (film, 0);
    }
    let [sw, sh] = cam.sensor_mm();
    let pix = sw / w as f64;
    let norm = cam.centre_weight();
    let primary = nms.len() / 2;
    let pairs = ghost_pairs(&lenses[primary]);
    // the first look: each (source, ghost) at the primary wavelength on a
    // coarse grid, its peak and extent
    let footprints = footprints(&lenses[primary], &sources);
    let stop = lenses[primary].stop_index();
    let look_grid = FilmGrid {
        centre_mm: [0.0; 2],
        pixel_mm: 8.0 * pix,
        nx: w.div_ceil(8),
        ny: (sh / (8.0 * pix)).ceil() as usize,
    };
    // each ghost's path at each wavelength, built once (an asphere's start
    // tables cost as much as tracing a few hundred rays), reading the
    // coatings' reflectances from a table (the thin-film formula at every
    // step was a third of a ghost ray's cost)
    // a stop of blades (or a mask) shapes the ghosts it limits
    let shape = stop_shape(cam);
    let path_of = |p: &Prescription, table: &Arc<ReflectanceTable>, [i, j]: [usize; 2]| -> Option<Tracer> {
        let t = Tracer::ghost(p, i, j, p.film_distance())?.with_reflectances(table.clone());
        Some(match &shape {
            Some(s) => t.with_stop_shape(s.clone()),
            None => t,
        })
    };
    let paths = |k: usize, wanted: &[bool]| -> Vec<Option<Tracer>> {
        let p = &lenses[k];
        let table = Arc::new(Tracer::forward(p).reflectance_table());
        pairs.par_iter().zip(wanted).map(|(&pair, &want)| if want { path_of(p, &table, pair) } else { None }).collect()
    };
    let look_paths = paths(primary, &vec![true; pairs.len()]);
    let jobs: Vec<(usize, usize)> = (0..sources.len()).flat_map(|s| (0..pairs.len()).map(move |g| (s, g))).collect();
    let looked: Vec<Option<(f64, Looked)>> = jobs
        .par_iter()
        .map(|&(si, g)| {
            let b = &sources[si];
            let t = look_paths[g].as_ref()?;
            // stopped down, where the light can have entered: light
            // reflected at or past the stop passed it first (the source's
            // footprint); light reflected twice in front of it, where the
            // path takes it to the stop's opening
            let square = Entrance::of(&lenses[primary], &b.source);
            let e = match footprints[si] {
                Some(f) if pairs[g][1] >= stop => f,
                Some(f) if f.half_mm < 0.25 * square.half_mm => {
                    toward_stop(t, &lenses[primary], &b.source, &square).unwrap_or(square)
                }
                _ => square,
            };
            let img = rasterise_with(t, &b.source, &e, &look_grid, LOOK_CELLS, LOOK_SPLITS, LOOK_EDGE_STEPS);
            // the drawing's cells over the part of the front element's
            // square the light took (stopped down, a few of its cells)
            let e = img.entered?;
            let area = look_grid.pixel_mm * look_grid.pixel_mm;
            let peak = img.power.iter().fold(0.0f64, |a, &v| a.max(v)) / area * b.scale * b.radiance[primary] / norm;
            (peak > 0.0).then(|| {
                // the ghost's extent on the film, mm, from its occupied cells
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for (k, v) in img.power.iter().enumerate() {
                    if *v > 0.0 {
                        let c = look_grid.centre_of(k);
                        let half = look_grid.pixel_mm / 2.0;
                        lo = [lo[0].min(c[0] - half), lo[1].min(c[1] - half)];
                        hi = [hi[0].max(c[0] + half), hi[1].max(c[1] + half)];
                    }
                }
                (peak, Looked { source: si, path: g, entrance: e, lo, hi })
            })
        })
        .collect();
    // the faintest ghosts left out while their peaks together stay below
    // `floor`: hundreds of ghosts each too faint to see can add up to a
    // glow that is not
    let mut looked: Vec<(f64, Looked)> = looked.into_iter().flatten().collect();
    looked.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut dropped = 0.0;
    let faint = looked.iter().take_while(|g| {
        dropped += g.0;
        dropped < floor
    });
    let skip = faint.count();
    let looked: Vec<Looked> = looked.into_iter().skip(skip).map(|g| g.1).collect();
    // each kept ghost's grid: pixels 1, 2, 4, 8 or 16 film pixels wide, so
    // that it is at most DRAW_PIXELS across
    let kept: Vec<(usize, Looked)> = looked
        .into_iter()
        .map(|g| {
            let across = (g.hi[0] - g.lo[0]).max(g.hi[1] - g.lo[1]) / pix;
            let mut level = 1usize;
            while across / level as f64 > DRAW_PIXELS && level < 16 {
                level *= 2;
            }
            (level, g)
        })
        .collect();
    // the kept ghosts' paths at each wavelength
    let mut wanted = vec![false; pairs.len()];
    for (_, g) in &kept {
        wanted[g.path] = true;
    }
    let mut look_paths = Some(look_paths);
    let drawn_paths: Vec<Vec<Option<Tracer>>> = (0..lenses.len())
        .map(|k| if k == primary { look_paths.take().unwrap_or_default() } else { paths(k, &wanted) })
        .collect();
    // the fine bands, made where a ghost needs them
    let fine_bands: OnceLock<FineBands> = OnceLock::new();
    let spread = AtomicUsize::new(0);
    // each level's grid of irradiance (per unit of norm), linear sRGB;
    // a ghost drawn on the part of its level's grid that holds it
    let mut levels: Vec<(usize, FilmGrid, Vec<DVec3>)> = Vec::new();
    for level in [1usize, 2, 4, 8, 16] {
        if !kept.iter().any(|k| k.0 == level) {
            continue;
        }
        let lp = level as f64 * pix;
        let grid = FilmGrid { centre_mm: [0.0; 2], pixel_mm: lp, nx: w.div_ceil(level), ny: (sh / lp).ceil() as usize };
        let mine: Vec<&Looked> = kept.iter().filter(|k| k.0 == level).map(|k| &k.1).collect();
        let mut sum = vec![DVec3::ZERO; grid.nx * grid.ny];
        // a few dozen ghosts at a time, each at every wavelength, added in
        // a fixed order (the same bits for any thread count)
        for part in mine.chunks(64) {
            let images: Vec<(usize, usize, usize, Vec<DVec3>)> = part
                .par_iter()
                .filter_map(|&&Looked { source: si, path, entrance: e, lo, hi }| {
                    let b = &sources[si];
                    // the part of the level's grid over the ghost, with a
                    // margin of half its extent and 16 of its pixels (the
                    // other wavelengths' ghosts differ, the look was coarse)
                    let m = 0.5 * (hi[0] - lo[0]).max(hi[1] - lo[1]) + 16.0 * lp;
                    let (a0, b0) = grid.to_pixels(lo[0] - m, lo[1] - m);
                    let (a1, b1) = grid.to_pixels(hi[0] + m, hi[1] + m);
                    let i0 = (a0.floor().max(0.0) as usize).min(grid.nx);
                    let j0 = (b0.floor().max(0.0) as usize).min(grid.ny);
                    let i1 = (a1.ceil().max(0.0) as usize).min(grid.nx);
                    let j1 = (b1.ceil().max(0.0) as usize).min(grid.ny);
                    if i1 <= i0 || j1 <= j0 {
                        return None;
                    }
                    let (nx, ny) = (i1 - i0, j1 - j0);
                    let x0 = (i0 as f64 - grid.nx as f64 / 2.0) * lp;
                    let y0 = (j0 as f64 - grid.ny as f64 / 2.0) * lp;
                    let local = FilmGrid {
                        centre_mm: [x0 + nx as f64 * lp / 2.0, y0 + ny as f64 * lp / 2.0],
                        pixel_mm: lp,
                        nx,
                        ny,
                    };
                    let draw =
                        |t: &Tracer| rasterise_with(t, &b.source, &e, &local, DRAW_CELLS, DRAW_SPLITS, EDGE_STEPS);
                    let s = b.scale / (norm * lp * lp);
                    let coarse: Vec<Option<Vec<f64>>> =
                        drawn_paths.iter().map(|paths_k| Some(draw(paths_k.get(path)?.as_ref()?).power)).collect();
                    let mut out = vec![DVec3::ZERO; nx * ny];
                    if nms.len() > 1 && fine > 1 && dispersed(&coarse) {
                        // copies of the ghost apart at the flare's
                        // wavelengths: drawn at the fine bands' instead
                        spread.fetch_add(1, Ordering::Relaxed);
                        let f = fine_bands.get_or_init(|| FineBands::new(p, fine));
                        for (k, (nm, colour)) in f.nms.iter().zip(&f.colours).enumerate() {
                            // the middle fine band of each is the band's own
                            // wavelength, drawn already
                            let img = if k % fine == fine / 2 {
                                coarse[k / fine].clone()
                            } else {
                                path_of(&f.lenses[k], &f.tables[k], pairs[path]).map(|t| draw(&t).power)
                            };
                            let weight = *colour * (s * interpolate(&nms, &b.radiance, *nm));
                            for (o, v) in out.iter_mut().zip(img.into_iter().flatten()) {
                                *o += weight * v;
                            }
                        }
                    } else {
                        for (k, img) in coarse.into_iter().enumerate() {
                            let weight = colours[k] * (s * b.radiance[k]);
                            for (o, v) in out.iter_mut().zip(img.into_iter().flatten()) {
                                *o += weight * v;
                            }
                        }
                    }
                    Some((i0, j0, nx, out))
                })
                .collect();
            for (i0, j0, nx, img) in images {
                for (q, v) in img.into_iter().enumerate() {
                    sum[(j0 + q / nx) * grid.nx + i0 + q % nx] += v;
                }
            }
        }
        levels.push((level, grid, sum));
    }
    let glare = if scene.film.flare == FlareSpec::GhostsAndGlare {
        glare_veil(&lenses, &colours, &sources, &footprints, shape, norm, sw * sh)
    } else {
        DVec3::ZERO
    };
    for (row, line) in film.chunks_mut(w).enumerate().take(h) {
        for (col, px) in line.iter_mut().enumerate() {
            // the pixel's film point: u = 0.5 - x / sw, v = 0.5 + y / sh
            let fx = (0.5 - (col as f64 + 0.5) / w as f64) * sw;
            let fy = ((row as f64 + 0.5) / h as f64 - 0.5) * sh;
            let mut add = glare;
            for (_, grid, sum) in &levels {
                add += bilinear(grid, sum, fx, fy);
            }
            *px += add;
        }
    }
    (film, spread.into_inner())
}

/// The camera's stop shape (its blades or mask at the stop's radius) for
/// the flare's tracers; `None` for a round stop, which the clear aperture
/// is.
fn stop_shape(cam: &RealLensCamera) -> Option<StopShape> {
    let p = cam.prescription();
    let transmission = cam.aperture().scaled(p.stop_semi_diameter())?;
    Some(StopShape { surface: p.stop_index(), transmission })
}

/// Relative luminance of linear sRGB.
fn luminance(v: DVec3) -> f64 {
    0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z
}

/// The film's value at film point (x, y) mm from a level's grid: bilinear
/// between the grid's pixel centres (0 outside).
fn bilinear(grid: &FilmGrid, v: &[DVec3], x: f64, y: f64) -> DVec3 {
    let (u, w) = grid.to_pixels(x, y);
    let (u, w) = (u - 0.5, w - 0.5);
    let (i0, j0) = (u.floor(), w.floor());
    let (fu, fw) = (u - i0, w - j0);
    let mut out = DVec3::ZERO;
    for (dj, wj) in [(0.0, 1.0 - fw), (1.0, fw)] {
        for (di, wi) in [(0.0, 1.0 - fu), (1.0, fu)] {
            let (i, j) = (i0 + di, j0 + dj);
            if i >= 0.0 && j >= 0.0 && (i as usize) < grid.nx && (j as usize) < grid.ny && wi * wj > 0.0 {
                out += v[j as usize * grid.nx + i as usize] * (wi * wj);
            }
        }
    }
    out
}

/// Film radii the transmittance is sampled at (from the centre to the
/// corner), and rays per radius (a square grid over the last surface).
const T_RADII: usize = 24;
const T_RAYS: usize = 12;

/// Multiplies the film by the lens's transmittance for light reaching each
/// film radius: per wavelength, the mean over rays from the film point to
/// a grid over the last surface's clear aperture of the product of 1 - R
/// along their reverse trace, then as a colour (each channel's share of a
/// flat spectrum).
fn dim_by_transmittance(
    cam: &RealLensCamera,
    lenses: &[Prescription],
    colours: &[DVec3],
    w: usize,
    h: usize,
    film: &mut [DVec3],
) {
    let [sw, sh] = cam.sensor_mm();
    let corner = 0.5 * (sw * sw + sh * sh).sqrt();
    let table: Vec<DVec3> = (0..=T_RADII)
        .into_par_iter()
        .map(|k| {
            let r = corner * k as f64 / T_RADII as f64;
            let white: DVec3 = colours.iter().sum();
            let mut sum = DVec3::ZERO;
            for (p, c) in lenses.iter().zip(colours) {
                sum += *c * transmittance(p, r);
            }
            sum / white.max(DVec3::splat(1e-12))
        })
        .collect();
    for (row, line) in film.chunks_mut(w).enumerate().take(h) {
        for (col, px) in line.iter_mut().enumerate() {
            let fx = (0.5 - (col as f64 + 0.5) / w as f64) * sw;
            let fy = ((row as f64 + 0.5) / h as f64 - 0.5) * sh;
            let t = (fx * fx + fy * fy).sqrt() / corner * T_RADII as f64;
            let k = (t.floor() as usize).min(T_RADII - 1);
            let f = (t - k as f64).clamp(0.0, 1.0);
            *px *= table[k] * (1.0 - f) + table[k + 1] * f;
        }
    }
}

/// The mean transmittance (product of 1 - R) of the rays from film point
/// (0, r) through `p` back to object space, over a grid on its last
/// surface; 1 where none passes.
fn transmittance(p: &Prescription, r: f64) -> f64 {
    let tracer = Tracer::reverse(p);
    let n = p.surfaces().len();
    let last = &p.surfaces()[n - 1];
    let sd = last.semi_diameter.unwrap_or(p.stop_semi_diameter() * 2.0);
    let z_last = p.last_vertex_z();
    let film = DVec3::new(0.0, r, z_last + p.film_distance());
    let (mut sum, mut count) = (0.0, 0usize);
    for j in 0..T_RAYS {
        for i in 0..T_RAYS {
            let (x, y) = (
                sd * (2.0 * (i as f64 + 0.5) / T_RAYS as f64 - 1.0),
                sd * (2.0 * (j as f64 + 0.5) / T_RAYS as f64 - 1.0),
            );
            if x * x + y * y > sd * sd {
                continue;
            }
            let Some(ray) = Ray::new(film, DVec3::new(x, y, z_last) - film) else { continue };
            if let (Outcome::Reached { .. }, t) = tracer.trace_fresnel(ray) {
                sum += t;
                count += 1;
            }
        }
    }
    if count == 0 {
        1.0
    } else {
        sum / count as f64
    }
}

/// The veil of glare (linear sRGB, the same at every pixel): each source's
/// light entering the lens (its primary image's power at the primary
/// wavelength, scaled per wavelength by its radiance) times the share that
/// leaves by four reflections or more (incoherent multiple reflection at
/// normal incidence, less the primary and the two-reflection ghosts),
/// over the frame's area.
fn glare_veil(
    lenses: &[Prescription],
    colours: &[DVec3],
    sources: &[Bright],
    footprints: &[Option<Entrance>],
    shape: Option<StopShape>,
    norm: f64,
    frame_mm2: f64,
) -> DVec3 {
    let primary = lenses.len() / 2;
    let p = &lenses[primary];
    let film = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 1.0, nx: 1, ny: 1 };
    let forward = Tracer::forward(p);
    let forward = match shape {
        Some(s) => forward.with_stop_shape(s),
        None => forward,
    };
    // each source's light entering, at the primary wavelength (the same for
    // every wavelength's share)
    let entering: Vec<f64> = sources
        .iter()
        .zip(footprints)
        .map(|(b, f)| {
            let e = f.unwrap_or_else(|| Entrance::of(p, &b.source));
            rasterise_with(&forward, &b.source, &e, &film, LOOK_CELLS, LOOK_SPLITS, LOOK_EDGE_STEPS).total
        })
        .collect();
    let mut out = DVec3::ZERO;
    for (k, lens_k) in lenses.iter().enumerate() {
        let share = higher_order_share(lens_k);
        for (b, entering) in sources.iter().zip(&entering) {
            out += colours[k] * (entering * b.scale * b.radiance[k] * share / (norm * frame_mm2));
        }
    }
    out
}

/// The share of the light entering `p` that reaches the image side after
/// four or more reflections, at normal incidence (incoherent: powers add),
/// at the prescription's wavelength.
fn higher_order_share(p: &Prescription) -> f64 {
    let s = p.surfaces();
    let nm = p.wavelength_nm();
    let r: Vec<f64> = (0..s.len())
        .filter(|&k| s[k].paraxial.is_none() && p.index_before(k) != s[k].ior)
        .map(|k| p.coating(k).reflectance(p.index_before(k), s[k].ior, 1.0, nm, false))
        .collect();
    // the stack's transmittance with every multiple reflection: adding a
    // surface of reflectance R to a stack of (T, R_back) gives T T_s / (1 -
    // R_back R)
    let (mut t, mut r_back) = (1.0, 0.0);
    for &rk in &r {
        let tk = 1.0 - rk;
        let denom = 1.0 - r_back * rk;
        let t_new = t * tk / denom;
        r_back = rk + tk * tk * r_back / denom;
        t = t_new;
    }
    let direct: f64 = r.iter().map(|rk| 1.0 - rk).product();
    let mut ghosts = 0.0;
    for j in 0..r.len() {
        for i in 0..j {
            ghosts += r[i] * r[j];
        }
    }
    (t - direct * (1.0 + ghosts)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::scene::format::SceneFile;

    /// The night street at f/8 behind six blades: the ghosts whose copies
    /// lie apart (dispersion moves them by more than their width) are drawn
    /// at the fine bands, and the ghost layer keeps its luminance within
    /// 0.5% of the one drawn at the four bands alone, each channel within
    /// 1% (the finer bands integrate the colour matching functions
    /// better).
    #[test]
    fn dispersed_ghosts_keep_their_light_at_fine_bands() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes");
        let text = std::fs::read_to_string(dir.join("flare-night-street.json")).unwrap();
        let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
        json["camera"]["f_number"] = 8.0.into();
        json["camera"]["aperture_shape"] = serde_json::json!({"shape": "polygon", "blades": 6, "rotation_deg": 10});
        let file: SceneFile = serde_json::from_value(json).unwrap();
        let scene = Scene::build(file, &dir, "<test>").unwrap();
        let Camera::Real(cam) = &scene.camera else { panic!("a real lens") };
        let (w, h) = (480, 270);
        let floor = 1e-4;
        let (fine, spread) = ghost_layer_banded(&scene, cam, w, h, floor, FINE);
        let (coarse, none) = ghost_layer_banded(&scene, cam, w, h, floor, 1);
        assert_eq!(none, 0);
        assert!(spread >= 1, "{spread} ghosts drawn at fine bands");
        let (a, b): (DVec3, DVec3) = (fine.iter().sum(), coarse.iter().sum());
        eprintln!(
            "{spread} ghosts at fine bands; layer {a:.1} against {b:.1} at four bands: luminance {:+.2e}, channels {:.2e}",
            luminance(a) / luminance(b) - 1.0,
            ((a - b) / b).abs().max_element()
        );
        assert!((luminance(a) - luminance(b)).abs() < 5e-3 * luminance(b), "{a} vs {b}");
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-2 * b[c], "channel {c}: {} vs {}", a[c], b[c]);
        }
    }
}
