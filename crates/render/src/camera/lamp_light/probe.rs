//! Where a source's light can pass: the cells of the front plane probed
//! with rays toward it (its centre and rings across its disc, or a sky
//! patch's texels), coarse then fine, each grid dilated by a cell; and
//! the budget of rays its image needs.

use super::*;

/// The wavelengths a lamp's cells are probed at (the render's range's ends
/// and the primary, for a dispersive lens in a spectral render; else the
/// one a render traces at), and whether the trace is spectral.
pub(super) fn probe_wavelengths(scene: &Scene, cam: &RealLensCamera) -> (Vec<f64>, bool) {
    let p = cam.prescription();
    let primary = p.wavelength_nm();
    match &scene.colour {
        ColourMode::Spectral(range) if p.is_dispersive() => {
            let [lo, hi] = range.nm();
            (vec![primary.clamp(lo, hi), lo, hi], true)
        }
        ColourMode::Monochromatic(nm) => (vec![*nm], p.is_dispersive()),
        _ => (vec![primary], false),
    }
}

/// The directions probed from a front-plane point toward a source (lens
/// frame, the first its centre), given the probe grid's cell size (mm).
type ProbeDirections = dyn Fn(DVec3, f64) -> Vec<DVec3>;

/// What probing a lamp's cells shares.
pub(super) struct Probe<'a> {
    /// The camera whose lens the probes go through.
    pub(super) cam: &'a RealLensCamera,
    /// z of the front plane, mm (lens frame).
    pub(super) z0: f64,
    /// The wavelengths probed (the first the render's own) and whether
    /// the trace is spectral.
    pub(super) nms: &'a [f64],
    pub(super) spectral: bool,
    /// Film size, pixels.
    pub(super) film: (usize, usize),
}

/// The probes of one grid: which cells passed light, the film points (in
/// pixels) of the passing probes at the first wavelength, how many cells'
/// centre probes landed on the film, and the lamp's own image: the largest
/// distance (pixels) from a cell's centre probe to its rim probes.
struct Probed {
    live: Vec<bool>,
    points: Vec<DVec2>,
    centres: Vec<DVec2>,
    spread: f64,
}

impl Probe<'_> {
    /// The model of the lamp at `c` (lens frame, mm) of radius `r` (mm),
    /// or `None` when it cannot be traced this way (see
    /// [`LampLight::build`]).
    pub(super) fn model(&self, source: Source, sd: f64, sag_max: f64, spp: usize) -> Option<Lamp> {
        let z_rear = self.cam.prescription().last_vertex_z();
        // the directions probed from a front-plane point toward the source
        // (the first its centre), given the cell size; and the steepest
        // ray's tangent to the axis
        let (dirs, tan): (Box<ProbeDirections>, f64) = match &source {
            Source::Sphere { centre: c, radius: r, .. } => {
                let (c, r) = (*c, *r);
                let depth = self.z0 - c.z - r;
                if !(depth > 0.0 && r > 0.0 && c.is_finite()) {
                    return None;
                }
                let alpha = (r / (c - DVec3::new(0.0, 0.0, self.z0)).length()).min(1.0).asin();
                let shift = alpha * (z_rear - self.z0).max(1.0);
                (Box::new(move |g, cell| sphere_probes(g, c, r, shift, cell)), (c.x.hypot(c.y) + r) / depth)
            }
            Source::Sky(patch) => {
                let dirs: Vec<DVec3> = patch.probe_directions().into_iter().map(|d| self.cam.dir_to_lens(d)).collect();
                if dirs[0].z >= -1e-3 {
                    return None;
                }
                let tan = dirs.iter().filter(|d| d.z < 0.0).map(|d| d.x.hypot(d.y) / -d.z).fold(0.0, f64::max);
                // the directions whose shifts at the stop differ by at
                // least half a cell (made once per grid)
                let depth = (z_rear - self.z0).max(1.0);
                let cache = std::cell::RefCell::new((0.0, Vec::new()));
                let thinned = move |_: DVec3, cell: f64| {
                    let mut c = cache.borrow_mut();
                    if c.0 != cell {
                        *c = (cell, thin(&dirs, depth, 0.5 * cell));
                    }
                    c.1.clone()
                };
                (Box::new(thinned), tan.min(10.0))
            }
        };
        // every ray of the source that meets the first surface inside its
        // clear aperture crosses the front plane within rho of the axis
        let rho = sd + (sag_max - self.z0) * tan + 0.5;
        let coarse = 2.0 * rho / COARSE as f64;
        let first = self.grid(&*dirs, DVec2::splat(-rho), coarse, COARSE, &self.nms[..1]);
        // a source whose own image is as large as its blur is left to the
        // camera paths, which do better where an image is resolved
        let (clo, chi) = bounds(&first.centres);
        let blur = (chi - clo).length();
        let own = self.own_image(&source, &first, rho, coarse);
        if first.centres.is_empty() || 2.0 * first.spread.max(own) >= blur {
            return None;
        }
        let live = dilate(&first.live, COARSE);
        // the bounding box of the live cells, probed again finer at every
        // probe wavelength
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for k in (0..COARSE * COARSE).filter(|&k| live[k]) {
            let corner = DVec2::new(-rho + (k % COARSE) as f64 * coarse, -rho + (k / COARSE) as f64 * coarse);
            lo = lo.min(corner);
            hi = hi.max(corner + DVec2::splat(coarse));
        }
        if !lo.is_finite() {
            return None;
        }
        let cell = (hi - lo).max_element() / GRID as f64;
        let fine = self.grid(&*dirs, lo, cell, GRID, self.nms);
        let live = dilate(&fine.live, GRID);
        let live_cells = live.iter().filter(|l| **l).count();
        if live_cells == 0 || fine.centres.is_empty() {
            return None;
        }
        // the image's area in pixels: the pixels its probes land in, or
        // where they are sparse, the ellipse in their bounding box
        let w = self.film.0;
        let mut pixels: Vec<usize> = fine.points.iter().map(|p| p.y as usize * w + p.x as usize).collect();
        pixels.sort_unstable();
        pixels.dedup();
        let (plo, phi) = bounds(&fine.points);
        let sparse = fine.points.len() < 2 * pixels.len();
        let ellipse = 0.25 * PI * (phi - plo + 1.0).element_product();
        let area = if sparse { (pixels.len() as f64).max(ellipse) } else { pixels.len() as f64 };
        let pass = fine.centres.len() as f64 / live_cells as f64;
        let rays = BUDGET * spp as f64 * area / pass.max(0.02);
        let passes = spp.max(1);
        let live_area = live_cells as f64 * cell * cell;
        let spacing = (live_area * passes as f64 / rays).sqrt().max(GRID as f64 * cell / 4096.0);
        Some(Lamp { source, lo, cell, live, passes, spacing, rays })
    }

    /// Probes a `size` x `size` grid of cells of side `cell` from `lo`
    /// (front plane, mm): a ray from each cell's centre along each of
    /// `dirs(centre, cell)` (toward the source, lens frame; the first its
    /// centre), at each of `nms`.
    fn grid(&self, dirs: &dyn Fn(DVec3, f64) -> Vec<DVec3>, lo: DVec2, cell: f64, size: usize, nms: &[f64]) -> Probed {
        let cam = self.cam;
        let mut batch = SpectralBatch::with_capacity(size * size * nms.len());
        let mut owner = Vec::with_capacity(batch.len());
        for k in 0..size * size {
            let g =
                DVec3::new(lo.x + ((k % size) as f64 + 0.5) * cell, lo.y + ((k / size) as f64 + 0.5) * cell, self.z0);
            for (o, omega) in dirs(g, cell).into_iter().enumerate() {
                for (wi, &nm) in nms.iter().enumerate() {
                    batch.push(lens::Ray { origin: g, direction: -omega }, nm);
                    owner.push((k, o, wi == 0));
                }
            }
        }
        let mut t = Vec::new();
        cam.trace_to_film(&mut batch, self.spectral, &mut t);
        let (w, h) = self.film;
        let mut out = Probed { live: vec![false; size * size], points: Vec::new(), centres: Vec::new(), spread: 0.0 };
        let b = &batch.rays;
        let mut centre_of: Vec<Option<DVec2>> = vec![None; size * size];
        for (i, &(k, o, first_nm)) in owner.iter().enumerate() {
            if b.status[i] != 0 || t[i] <= 0.0 {
                continue;
            }
            out.live[k] = true;
            if !first_nm {
                continue;
            }
            let (u, v) = cam.film_uv(b.x[i], b.y[i]);
            let x = DVec2::new(u * w as f64, v * h as f64);
            if o == 0 {
                centre_of[k] = Some(x);
            } else if let Some(x0) = centre_of[k] {
                out.spread = out.spread.max((x - x0).length());
            }
            if x.x >= 0.0 && x.y >= 0.0 && x.x < w as f64 && x.y < h as f64 {
                out.points.push(x);
                if o == 0 {
                    out.centres.push(x);
                }
            }
        }
        out
    }
}

impl Probe<'_> {
    /// The radius (pixels) of the source's own image: the largest distance
    /// on the film from where its centre's ray lands to where its rim's do,
    /// all from the passing cell nearest the grid's centre (`rho` its half
    /// width, `cell` its cells' side). The grid's own spread misses it
    /// where the probes are thinned to the cell (a small source in focus
    /// sends every probe but its centre's through the same cell). 0 where
    /// no cell passed.
    fn own_image(&self, source: &Source, first: &Probed, rho: f64, cell: f64) -> f64 {
        let g = (0..COARSE * COARSE)
            .filter(|&k| first.live[k])
            .map(|k| {
                DVec3::new(
                    -rho + ((k % COARSE) as f64 + 0.5) * cell,
                    -rho + ((k / COARSE) as f64 + 0.5) * cell,
                    self.z0,
                )
            })
            .min_by(|a, b| a.truncate().length().total_cmp(&b.truncate().length()));
        let Some(g) = g else { return 0.0 };
        // toward the source: its centre first, then its rim
        let omegas: Vec<DVec3> = match source {
            Source::Sphere { centre, radius, .. } => {
                let to = *centre - g;
                let dist = to.length();
                if dist <= *radius {
                    return 0.0;
                }
                let axis = to / dist;
                let (sin, cos) = (radius / dist, (1.0 - (radius / dist).powi(2)).sqrt());
                let (e1, e2) = axis.any_orthonormal_pair();
                std::iter::once(axis)
                    .chain((0..16).map(|k| {
                        let phi = std::f64::consts::TAU * k as f64 / 16.0;
                        axis * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin
                    }))
                    .collect()
            }
            Source::Sky(patch) => patch.probe_directions().into_iter().map(|d| self.cam.dir_to_lens(d)).collect(),
        };
        let mut batch = SpectralBatch::with_capacity(omegas.len());
        for omega in &omegas {
            batch.push(lens::Ray { origin: g, direction: -*omega }, self.nms[0]);
        }
        let mut t = Vec::new();
        self.cam.trace_to_film(&mut batch, self.spectral, &mut t);
        let (w, h) = self.film;
        let b = &batch.rays;
        let at = |i: usize| {
            let (u, v) = self.cam.film_uv(b.x[i], b.y[i]);
            DVec2::new(u * w as f64, v * h as f64)
        };
        if b.status[0] != 0 {
            return 0.0;
        }
        let centre = at(0);
        (1..omegas.len()).filter(|&i| b.status[i] == 0).map(|i| (at(i) - centre).length()).fold(0.0, f64::max)
    }
}

/// Directions from front-plane point `g` toward the sphere (`c`, `r`) (lens
/// frame, mm): its centre, then rings across its disc, as many as keep
/// their shifts at the stop (`shift` for the whole disc) within a `cell`.
/// None from inside the sphere.
fn sphere_probes(g: DVec3, c: DVec3, r: f64, shift: f64, cell: f64) -> Vec<DVec3> {
    let to = c - g;
    let dist = to.length();
    if dist <= r {
        return Vec::new();
    }
    let a = to / dist;
    let (e1, e2) = a.any_orthonormal_pair();
    let half = (r / dist).asin();
    let rings = ((shift / cell).ceil() as usize).clamp(1, 8);
    let mut out = vec![a];
    for k in 1..=rings {
        let frac = 0.999 * k as f64 / rings as f64;
        let m = ((2.0 * PI * frac * shift / cell).ceil() as usize).clamp(6, 64);
        let th = frac * half;
        out.extend((0..m).map(|j| {
            let phi = 2.0 * PI * j as f64 / m as f64;
            a * th.cos() + (e1 * phi.cos() + e2 * phi.sin()) * th.sin()
        }));
    }
    out
}

/// The directions of `dirs` (lens frame, toward the source, the first
/// kept) whose shifts at a plane `depth` mm behind the front plane are at
/// least `tolerance` mm from every direction kept before them.
fn thin(dirs: &[DVec3], depth: f64, tolerance: f64) -> Vec<DVec3> {
    let shift = |d: &DVec3| DVec2::new(d.x, d.y) * (depth / -d.z.min(-1e-6));
    let mut kept: Vec<(DVec3, DVec2)> = Vec::new();
    for d in dirs {
        let s = shift(d);
        if kept.iter().all(|(_, k)| (*k - s).length() >= tolerance) {
            kept.push((*d, s));
        }
    }
    kept.into_iter().map(|(d, _)| d).collect()
}

/// The bounding box of `points`.
fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points
        .iter()
        .fold((DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

/// The live cells of a `size` x `size` grid grown by one cell (eight
/// neighbours): a region of passing rays narrower than a cell between two
/// probes is still inside.
fn dilate(live: &[bool], size: usize) -> Vec<bool> {
    let mut out = live.to_vec();
    let n = size as isize;
    for k in (0..size * size).filter(|&k| live[k]) {
        let (i, j) = ((k % size) as isize, (k / size) as isize);
        for dj in -1..=1 {
            for di in -1..=1 {
                let (a, b) = (i + di, j + dj);
                if a >= 0 && b >= 0 && a < n && b < n {
                    out[(b * n + a) as usize] = true;
                }
            }
        }
    }
    out
}
