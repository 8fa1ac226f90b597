//! Aiming a real lens's camera samples at small lamps.
//!
//! From a film point, a small lamp far from the plane in focus is seen
//! through a small patch of the exit pupil; the real-lens camera draws its
//! rear-plane targets uniformly over the pupil bounds, which rarely land in
//! that patch, so a defocused lamp comes out as speckles. Here each lamp
//! gets a model of the rays it sends through the lens, made once by tracing
//! rays from the lamp into it: for a lamp point `c + v` (`v` across the
//! line of sight, within the lamp's radius R) and a point `g` where the ray
//! crosses the first vertex's plane, the film point `x(g, v)` and the
//! rear-plane point `r(g, v)` the ray passes, as quintic polynomials in `g`
//! (least squares over the traced rays) and linear in `v`. In the pupil
//! point the maps are smooth; in the film point they are not (a defocused
//! image nears a fold at the rim of the pupil, where the film point moves
//! ever more slowly), so a film point's pupil point is found per sample by
//! Newton's method on the polynomials.
//!
//! A camera sample from which some lamp can be seen is drawn, with
//! probability `SHARE` (a half), by picking one of those lamps uniformly and a point
//! `v` uniformly on its disc, solving `x(g, v) = x` for `g` and aiming at
//! `r(g, v)`: its ray meets the lamp at `v` as nearly as the polynomials
//! follow the lens. The density of that target, per rear-plane area, is
//! `1 / (pi R^2 |det J|)` with `J = dr/dv` at fixed `x` (`r_v - r_g x_g^-1
//! x_v`), known for any film point and target (found by solving
//! `x(g, v) = x`, `r(g, v) = r`, and counted only where the draw's own
//! search from the same start reaches the same pupil point), which is what
//! the balance heuristic over the mixture with uniform targets needs, for
//! every sample and for a spectral render's other wavelengths: the estimate
//! stays unbiased however well the polynomials follow the lens. A lamp
//! whose polynomials miss its traced rays by more than 2.5% of its own
//! image gets no model; through a dispersive lens the models are made in
//! `BANDS` (eight) wavelength bands (docs/rendering.md).

use super::real_lens::LensTrace;
use glam::{DVec2, DVec3};
use lens::trace::SpectralBatch;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// The share of samples aimed at lamps where one can be seen.
pub(crate) const SHARE: f64 = 0.5;

/// The most lamps aimed at.
pub const MAX_LAMPS: usize = 64;

/// Rays traced per lamp point to build a model: a square grid this wide
/// over the first surface's clear aperture (those inside it).
const GRID: usize = 24;

/// Terms of a quintic polynomial in two variables.
const TERMS: usize = 21;

/// A quintic from the pupil point `g` (over the first surface's
/// semi-diameter) to a point in the lens frame (mm): its coefficients of
/// the monomials [`monomials`] lists.
type Quintic = [DVec2; TERMS];

/// The maps of one lamp at one pupil point: the film and rear-plane points
/// of the ray from the lamp's centre, and how each moves per millimetre of
/// the lamp point's move along its two directions.
#[derive(Debug, Clone, Copy)]
struct Maps {
    x: DVec2,
    x_v: [DVec2; 2],
    r: DVec2,
    r_v: [DVec2; 2],
}

impl Maps {
    /// The film point of lamp point `v`.
    fn film(&self, v: DVec2) -> DVec2 {
        self.x + self.x_v[0] * v.x + self.x_v[1] * v.y
    }

    /// The rear-plane point of lamp point `v`.
    fn rear(&self, v: DVec2) -> DVec2 {
        self.r + self.r_v[0] * v.x + self.r_v[1] * v.y
    }
}

/// One lamp's model (lens frame, mm).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LampPatch {
    /// The film box `[x0, x1, y0, y1]` where the lamp can be seen.
    film: [f64; 4],
    /// The lamp's radius, mm.
    radius: f64,
    /// Film points from the lamp's centre and from it moved by its radius
    /// along each of the two directions.
    x: [Quintic; 3],
    /// Rear-plane points likewise.
    r: [Quintic; 3],
    /// Where Newton's method starts for a film point: on a [`STARTS`] x
    /// [`STARTS`] grid over the film box, the pupil point of the traced ray
    /// from the lamp's centre that landed nearest each cell's middle.
    starts: Vec<DVec2>,
}

/// Cells across the film box of a lamp's table of starting points.
const STARTS: usize = 32;

/// A 2 x 2 matrix of columns `a`, `b` solved against `d` (Cramer), `None`
/// when singular.
fn solve2(a: DVec2, b: DVec2, d: DVec2) -> Option<DVec2> {
    let det = a.perp_dot(b);
    let v = DVec2::new(d.perp_dot(b), a.perp_dot(d)) / det;
    (det != 0.0 && v.is_finite()).then_some(v)
}

/// Step of the finite differences in the pupil point (its unit).
const H: f64 = 1e-6;

impl LampPatch {
    /// Whether film point `x` lies in the lamp's film box.
    fn covers(&self, x: DVec2) -> bool {
        let [x0, x1, y0, y1] = self.film;
        x.x >= x0 && x.x <= x1 && x.y >= y0 && x.y <= y1
    }

    /// The maps at pupil point `g` (in its unit).
    fn maps(&self, g: DVec2) -> Maps {
        let t = monomials(g);
        let (x0, x1, x2) = (eval(&self.x[0], &t), eval(&self.x[1], &t), eval(&self.x[2], &t));
        let (r0, r1, r2) = (eval(&self.r[0], &t), eval(&self.r[1], &t), eval(&self.r[2], &t));
        let k = 1.0 / self.radius;
        Maps { x: x0, x_v: [(x1 - x0) * k, (x2 - x0) * k], r: r0, r_v: [(r1 - r0) * k, (r2 - r0) * k] }
    }

    /// The pupil point whose ray from lamp point `v` reaches film point
    /// `x`, by Newton's method from the traced ray's that landed nearest
    /// (damped; `None` when it does not converge to a hundred-thousandth
    /// of a micrometre).
    fn pupil_point(&self, x: DVec2, v: DVec2) -> Option<DVec2> {
        let miss = |g: DVec2| {
            let t = monomials(g);
            let (x0, x1, x2) = (eval(&self.x[0], &t), eval(&self.x[1], &t), eval(&self.x[2], &t));
            x0 + ((x1 - x0) * v.x + (x2 - x0) * v.y) / self.radius - x
        };
        let mut g = self.start(x);
        let mut f = miss(g);
        for _ in 0..30 {
            if f.length() < 1e-8 {
                return Some(g);
            }
            let fx = (miss(g + DVec2::new(H, 0.0)) - f) / H;
            let fy = (miss(g + DVec2::new(0.0, H)) - f) / H;
            let d = solve2(fx, fy, -f)?;
            // halve the step until the miss shrinks
            let mut step = 1.0;
            loop {
                let next = g + d * step;
                let fn_ = miss(next);
                if fn_.length() < f.length() {
                    (g, f) = (next, fn_);
                    break;
                }
                step *= 0.5;
                if step < 1e-4 {
                    return None;
                }
            }
        }
        (f.length() < 1e-8).then_some(g)
    }

    /// The pupil point of the traced ray from the lamp's centre that
    /// landed nearest film point `x`: where the searches start.
    fn start(&self, x: DVec2) -> DVec2 {
        let [x0, x1, y0, y1] = self.film;
        let cell = |t: f64, lo: f64, hi: f64| (((t - lo) / (hi - lo) * STARTS as f64) as usize).min(STARTS - 1);
        self.starts.get(cell(x.y, y0, y1) * STARTS + cell(x.x, x0, x1)).copied().unwrap_or(DVec2::ZERO)
    }

    /// `J = dr/dv` at fixed film point, at pupil point `g` and lamp point
    /// `v`: `r_v - r_g x_g^-1 x_v`, as its determinant.
    fn jacobian_det(&self, g: DVec2, v: DVec2) -> Option<f64> {
        let m = self.maps(g);
        let (mx, my) = (self.maps(g + DVec2::new(H, 0.0)), self.maps(g + DVec2::new(0.0, H)));
        let x_g = [(mx.film(v) - m.film(v)) / H, (my.film(v) - m.film(v)) / H];
        let r_g = [(mx.rear(v) - m.rear(v)) / H, (my.rear(v) - m.rear(v)) / H];
        let col = |k: usize| -> Option<DVec2> {
            // x_g^-1 x_v[k], then r_g times it
            let s = solve2(x_g[0], x_g[1], m.x_v[k])?;
            Some(m.r_v[k] - (r_g[0] * s.x + r_g[1] * s.y))
        };
        let (a, b) = (col(0)?, col(1)?);
        let det = a.perp_dot(b);
        (det.is_finite() && det != 0.0).then_some(det)
    }

    /// About the area (mm^2 of the rear plane) the lamp's patch covers
    /// from film point `x`: `pi R^2 |det J|` at the lamp's centre and the
    /// pupil point of the traced ray that landed nearest (no search: near
    /// the rim of the lamp's disc no ray from its centre reaches `x`, but
    /// rays from its edge do).
    fn area(&self, x: DVec2) -> Option<f64> {
        Some(std::f64::consts::PI * self.radius * self.radius * self.jacobian_det(self.start(x), DVec2::ZERO)?.abs())
    }

    /// A rear-plane target from film point `x` toward lamp point `v`.
    fn target(&self, x: DVec2, v: DVec2) -> Option<DVec2> {
        let g = self.pupil_point(x, v)?;
        Some(self.maps(g).rear(v))
    }

    /// The density (per mm^2 of the rear plane) with which
    /// [`Self::target`], given `v` uniform on the lamp's disc, gives target
    /// `r` from film point `x`: 0 where no lamp point sends it.
    fn density(&self, x: DVec2, r: DVec2) -> f64 {
        // the pupil point g, with the lamp point v(g) that reaches x from
        // it (exact: x is linear in v), such that r(g, v(g)) = r
        let lamp_point = |g: DVec2| {
            let m = self.maps(g);
            solve2(m.x_v[0], m.x_v[1], x - m.x).map(|v| (v, m.rear(v) - r))
        };
        let mut g = self.start(x);
        let Some((mut v, mut f)) = lamp_point(g) else { return 0.0 };
        let mut converged = false;
        for _ in 0..30 {
            if f.length() < 1e-8 {
                converged = true;
                break;
            }
            let (Some((_, fx)), Some((_, fy))) =
                (lamp_point(g + DVec2::new(H, 0.0)), lamp_point(g + DVec2::new(0.0, H)))
            else {
                return 0.0;
            };
            let Some(d) = solve2((fx - f) / H, (fy - f) / H, -f) else { return 0.0 };
            let mut step = 1.0;
            loop {
                let Some((vn, fnext)) = lamp_point(g + d * step) else { return 0.0 };
                if fnext.length() < f.length() {
                    (g, v, f) = (g + d * step, vn, fnext);
                    break;
                }
                step *= 0.5;
                if step < 1e-4 {
                    return 0.0;
                }
            }
        }
        if !(converged || f.length() < 1e-8) || v.length() > self.radius {
            return 0.0;
        }
        // only what the draw itself reaches: its search from the same start
        // must end at this pupil point (where it fails, no sample has r)
        if !self.pupil_point(x, v).is_some_and(|h| (h - g).length() < 1e-6) {
            return 0.0;
        }
        match self.jacobian_det(g, v) {
            Some(det) => 1.0 / (std::f64::consts::PI * self.radius * self.radius * det.abs()),
            None => 0.0,
        }
    }
}

/// The lamps a real-lens camera aims at: each lamp's model, for each of a
/// few wavelengths across the spectrum a render samples (one, the primary,
/// for a lens without glasses). A sample uses the models of the band
/// nearest its wavelength, and so does the density of each of a spectral
/// sample's wavelengths: a lamp's patch moves with the wavelength through a
/// dispersive lens, and the models follow it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RealLampAim {
    bands: Vec<Band>,
    /// The wavelength of samples that carry none (RGB), nm.
    primary: f64,
}

/// The lamps' models at one wavelength.
#[derive(Debug, Clone, PartialEq)]
struct Band {
    nm: f64,
    patches: Vec<LampPatch>,
}

/// The lamps seen from one film point at one wavelength (the band, and
/// indices into its list).
pub(crate) struct Seen {
    band: usize,
    which: [u8; MAX_LAMPS],
    n: usize,
}

impl Seen {
    /// Whether no lamp is seen.
    pub(crate) fn is_empty(&self) -> bool {
        self.n == 0
    }
}

/// Wavelength bands of a dispersive lens's lamp models.
const BANDS: usize = 8;

impl RealLampAim {
    /// Whether any lamp is aimed at.
    pub fn is_on(&self) -> bool {
        self.bands.iter().any(|b| !b.patches.is_empty())
    }

    /// How many lamps have a model at the primary wavelength.
    pub fn lamps(&self) -> usize {
        self.bands.get(self.band(None)).map_or(0, |b| b.patches.len())
    }

    /// The band nearest `nm` (`None`: the primary wavelength).
    fn band(&self, nm: Option<f64>) -> usize {
        let nm = nm.unwrap_or(self.primary);
        (0..self.bands.len())
            .min_by(|&a, &b| (self.bands[a].nm - nm).abs().total_cmp(&(self.bands[b].nm - nm).abs()))
            .unwrap_or(0)
    }

    /// Builds the models of `lamps` (centre and radius, lens frame, mm) by
    /// tracing, for each, a grid of rays from its centre and from its
    /// centre moved by its radius across the line of sight (twice) through
    /// the first surface's clear aperture (`first_sd`, mm, at the first
    /// vertex) to the film (`scene_to_film`), at the primary wavelength
    /// `primary` (nm) or, where `spectrum` gives a range (nm), at
    /// [`BANDS`] wavelengths spread over it. A lamp whose rays do not reach
    /// the film in enough places (fewer than 42, twice the polynomials'
    /// terms, or too few to fix them) or whose polynomials do not follow
    /// them gets no model at that wavelength; at most [`MAX_LAMPS`] lamps
    /// (none beyond).
    pub(crate) fn build(
        lamps: &[(DVec3, f64)],
        scene_to_film: &LensTrace,
        first_sd: f64,
        z_film: f64,
        z_rear: f64,
        primary: f64,
        spectrum: Option<(f64, f64)>,
    ) -> Self {
        if lamps.is_empty() || lamps.len() > MAX_LAMPS || !(first_sd.is_finite() && first_sd > 0.0) {
            return RealLampAim::default();
        }
        let grid: Vec<DVec2> = (0..GRID * GRID)
            .map(|k| {
                let (i, j) = ((k % GRID) as f64 + 0.5, (k / GRID) as f64 + 0.5);
                DVec2::new(2.0 * i / GRID as f64 - 1.0, 2.0 * j / GRID as f64 - 1.0)
            })
            .filter(|p| p.length() <= 1.0)
            .collect();
        // a band's middle wavelength each, over the range
        let nms: Vec<f64> = match spectrum {
            Some((lo, hi)) if lo < hi => (0..BANDS).map(|k| lo + (hi - lo) * (k as f64 + 0.5) / BANDS as f64).collect(),
            _ => vec![primary],
        };
        let spectral = nms.len() > 1;
        let bands = nms
            .par_iter()
            .map(|&nm| Band {
                nm,
                patches: lamps
                    .iter()
                    .filter_map(|&(c, r)| patch(c, r, &grid, first_sd, scene_to_film, (z_film, z_rear), nm, spectral))
                    .collect(),
            })
            .collect();
        RealLampAim { bands, primary }
    }

    /// The lamps that can be seen at wavelength `nm` (`None`: the primary)
    /// from film point (fx, fy) through a patch smaller than the uniform
    /// bounds there (`uniform_area`, mm^2): a lamp in focus is seen through
    /// the whole pupil, and aiming at it would gain nothing.
    pub(crate) fn seen(&self, fx: f64, fy: f64, uniform_area: f64, nm: Option<f64>) -> Seen {
        let x = DVec2::new(fx, fy);
        let band = self.band(nm);
        let mut s = Seen { band, which: [0; MAX_LAMPS], n: 0 };
        let Some(b) = self.bands.get(band) else { return s };
        for (k, p) in b.patches.iter().enumerate() {
            if p.covers(x) && p.area(x).is_some_and(|a| a < uniform_area) {
                s.which[s.n] = k as u8;
                s.n += 1;
            }
        }
        s
    }

    /// A rear-plane target toward one of the lamps `seen` from (fx, fy)
    /// (the first uniform picks the lamp, its remainder and the second a
    /// point uniformly on its disc).
    pub(crate) fn draw(&self, seen: &Seen, fx: f64, fy: f64, a: (f64, f64)) -> Option<DVec2> {
        let scaled = a.0 * seen.n as f64;
        let j = (scaled as usize).min(seen.n.checked_sub(1)?);
        let p = &self.bands[seen.band].patches[seen.which[j] as usize];
        let (radius, phi) = ((scaled - j as f64).clamp(0.0, 1.0).sqrt() * p.radius, std::f64::consts::TAU * a.1);
        p.target(DVec2::new(fx, fy), DVec2::new(phi.cos(), phi.sin()) * radius)
    }

    /// The density (per mm^2 of the rear plane) with which [`Self::draw`]
    /// gives target `r` from (fx, fy): the mean over the lamps seen.
    pub(crate) fn density(&self, seen: &Seen, fx: f64, fy: f64, r: DVec2) -> f64 {
        if seen.n == 0 {
            return 0.0;
        }
        let x = DVec2::new(fx, fy);
        let patches = &self.bands[seen.band].patches;
        seen.which[..seen.n].iter().map(|&k| patches[k as usize].density(x, r)).sum::<f64>() / seen.n as f64
    }
}

/// Where rays from `from` through the first-vertex points `grid` (mm)
/// reach the film: per grid point, the film point and the rear-plane
/// crossing, or `None` where the ray is blocked.
fn landings(
    from: DVec3,
    grid: &[DVec2],
    scene_to_film: &LensTrace,
    (z_film, z_rear): (f64, f64),
    nm: f64,
    spectral: bool,
) -> Vec<Option<(DVec2, DVec2)>> {
    let mut batch = SpectralBatch::with_capacity(grid.len());
    for g in grid {
        match (DVec3::new(g.x, g.y, 0.0) - from).try_normalize() {
            Some(direction) => batch.push(lens::Ray { origin: from, direction }, nm),
            None => batch.push_skipped(nm),
        }
    }
    let mut t = Vec::new();
    scene_to_film.trace(&mut batch, spectral, &mut t, |_, _| 1.0);
    let r = &batch.rays;
    (0..grid.len())
        .map(|i| {
            (r.status[i] == 0 && t[i] > 0.0 && r.dz[i] > 0.0).then(|| {
                let film = DVec2::new(r.x[i], r.y[i]);
                (film, film - DVec2::new(r.dx[i], r.dy[i]) * ((z_film - z_rear) / r.dz[i]))
            })
        })
        .collect()
}

/// The monomials of a quintic at `p`: 1, u, v, u^2, uv, v^2, ... v^5.
fn monomials(p: DVec2) -> [f64; TERMS] {
    let (mut pu, mut pv) = ([1.0; 6], [1.0; 6]);
    for k in 1..6 {
        pu[k] = pu[k - 1] * p.x;
        pv[k] = pv[k - 1] * p.y;
    }
    let mut t = [0.0; TERMS];
    let mut k = 0;
    for degree in 0..=5 {
        for j in 0..=degree {
            t[k] = pu[degree - j] * pv[j];
            k += 1;
        }
    }
    t
}

/// A quintic at the monomials `t`.
fn eval(c: &Quintic, t: &[f64; TERMS]) -> DVec2 {
    c.iter().zip(t).fold(DVec2::ZERO, |s, (c, t)| s + *c * *t)
}

/// The least-squares quintic through the pairs (pupil point, lens-frame
/// point), and its largest miss (mm); `None` when the pupil points do not
/// fix one.
fn fit(pairs: &[(DVec2, DVec2)]) -> Option<(Quintic, f64)> {
    if pairs.len() < 2 * TERMS {
        return None;
    }
    let a = DMatrix::from_fn(pairs.len(), TERMS, |i, j| monomials(pairs[i].0)[j]);
    let svd = a.svd(true, true);
    let s = &svd.singular_values;
    if s.min() <= 1e-9 * s.max() {
        return None;
    }
    let cx = svd.solve(&DVector::from_iterator(pairs.len(), pairs.iter().map(|p| p.1.x)), 0.0).ok()?;
    let cy = svd.solve(&DVector::from_iterator(pairs.len(), pairs.iter().map(|p| p.1.y)), 0.0).ok()?;
    let mut c = [DVec2::ZERO; TERMS];
    for (j, v) in c.iter_mut().enumerate() {
        *v = DVec2::new(cx[j], cy[j]);
    }
    let worst = pairs.iter().map(|(g, y)| (eval(&c, &monomials(*g)) - *y).length()).fold(0.0, f64::max);
    (c.iter().all(|v| v.is_finite()) && worst.is_finite()).then_some((c, worst))
}

/// One lamp's model (see the module) at `nm` (traced at that wavelength
/// when `spectral`, else at the lens's primary), or `None`.
#[allow(clippy::too_many_arguments)]
fn patch(
    c: DVec3,
    radius: f64,
    grid: &[DVec2],
    first_sd: f64,
    scene_to_film: &LensTrace,
    planes: (f64, f64),
    nm: f64,
    spectral: bool,
) -> Option<LampPatch> {
    // in front of the first vertex, clear of it
    if !(c.is_finite() && radius > 0.0 && c.z + radius < 0.0) {
        return None;
    }
    // two directions across the line of sight to the lens
    let sight = (DVec3::ZERO - c).try_normalize()?;
    let (u1, u2) = crate::material::basis(sight);
    let points = [c, c + u1 * radius, c + u2 * radius];
    let in_mm: Vec<DVec2> = grid.iter().map(|g| *g * first_sd).collect();
    let traced: Vec<Vec<Option<(DVec2, DVec2)>>> =
        points.iter().map(|&o| landings(o, &in_mm, scene_to_film, planes, nm, spectral)).collect();
    // the pupil points every lamp point's ray passes through
    let both: Vec<usize> = (0..grid.len()).filter(|&i| traced.iter().all(|t| t[i].is_some())).collect();
    let pairs = |m: usize, film: bool| -> Vec<(DVec2, DVec2)> {
        both.iter().filter_map(|&i| traced[m][i].map(|(x, r)| (grid[i], if film { x } else { r }))).collect()
    };
    let fits: Vec<(Quintic, f64)> = [(0, true), (1, true), (2, true), (0, false), (1, false), (2, false)]
        .iter()
        .map(|&(m, f)| fit(&pairs(m, f)))
        .collect::<Option<_>>()?;
    let x = [fits[0].0, fits[1].0, fits[2].0];
    let r = [fits[3].0, fits[4].0, fits[5].0];
    // the polynomials must follow the lens to within a hundredth of the
    // lamp's own image: how far its light moves on the film and on the
    // rear plane as the lamp point crosses its radius (else no model: a
    // poor one would aim worse than the uniform bounds)
    let t = monomials(DVec2::ZERO);
    let moves = |q: &[Quintic; 3]| {
        (eval(&q[1], &t) - eval(&q[0], &t)).length().min((eval(&q[2], &t) - eval(&q[0], &t)).length())
    };
    let (x_worst, r_worst) =
        (fits[..3].iter().map(|f| f.1).fold(0.0, f64::max), fits[3..].iter().map(|f| f.1).fold(0.0, f64::max));
    if !(x_worst < 0.025 * moves(&x) && r_worst < 0.025 * moves(&r)) {
        return None;
    }
    // the film box of every traced landing, grown by 15% of its size
    // for the rays between the grid's and the pupil's rim
    let mut b = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
    for (x, _) in traced.iter().flatten().flatten() {
        b = [b[0].min(x.x), b[1].max(x.x), b[2].min(x.y), b[3].max(x.y)];
    }
    let grow = 0.15 * (b[1] - b[0]).max(b[3] - b[2]);
    let film = [b[0] - grow, b[1] + grow, b[2] - grow, b[3] + grow];
    let landed: Vec<(DVec2, DVec2)> = both.iter().filter_map(|&i| traced[0][i].map(|(x, _)| (x, grid[i]))).collect();
    let starts = (0..STARTS * STARTS)
        .map(|k| {
            let middle = DVec2::new(
                film[0] + (film[1] - film[0]) * ((k % STARTS) as f64 + 0.5) / STARTS as f64,
                film[2] + (film[3] - film[2]) * ((k / STARTS) as f64 + 0.5) / STARTS as f64,
            );
            let nearest = landed
                .iter()
                .min_by(|a, b| (a.0 - middle).length_squared().total_cmp(&(b.0 - middle).length_squared()));
            nearest.map_or(DVec2::ZERO, |l| l.1)
        })
        .collect();
    film.iter().all(|v| v.is_finite()).then_some(LampPatch { film, radius, x, r, starts })
}
