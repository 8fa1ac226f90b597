//! Aiming a real lens's camera samples at small lamps.
//!
//! From a film point, a small lamp far from the plane in focus is seen
//! through a small patch of the exit pupil; the real-lens camera draws its
//! rear-plane targets uniformly over the pupil bounds, which rarely land in
//! that patch, so a defocused lamp comes out as speckles. Here each lamp
//! gets a model of its patch over the film, made once by tracing rays from
//! the lamp into the lens: the rear-plane target `c(x)` whose ray from film
//! point `x` goes through the lamp's centre, and the matrix `M(x)` by which
//! that target moves per millimetre the lamp's centre moves across the line
//! of sight, both cubic polynomials in `x` (least squares over the traced
//! rays: the pupil's aberrations bend the map from film to pupil). The
//! patch is the ellipse `c(x) + M(x) v`, `|v| <= m R` (R the lamp's radius,
//! m >= 1.1 a margin that grows with the fit's residual).
//!
//! A camera sample from which some lamp's patch can be seen is drawn, with
//! probability [`SHARE`], uniformly in one of those patches (chosen
//! uniformly) instead of over the pupil bounds, and weighted by the
//! mixture's density (the balance heuristic): the estimate stays unbiased
//! whether the model is good or not (a poor model only aims worse), and the
//! density is known for any film point and target, which is what a spectral
//! render's other wavelengths need (docs/rendering.md).

use super::real_lens::LensTrace;
use glam::{DVec2, DVec3};
use lens::trace::SpectralBatch;
use nalgebra::{DMatrix, DVector};

/// The share of samples aimed at lamps where one can be seen.
pub(crate) const SHARE: f64 = 0.5;

/// The most lamps aimed at.
pub const MAX_LAMPS: usize = 64;

/// Rays traced per lamp centre to build a patch model: a square grid this
/// wide over the first surface's clear aperture (those inside it).
const GRID: usize = 24;

/// Terms of a quintic polynomial in two variables.
const TERMS: usize = 21;

/// A cubic polynomial from the film (lens frame, mm) to the rear plane:
/// its coefficients of 1, u, v, u^2, uv, v^2, u^3, u^2 v, u v^2, v^3, with
/// (u, v) the film point relative to the lamp's film box (its middle 0, its
/// half-width 1).
type Cubic = [DVec2; TERMS];

/// One lamp's patch model (lens frame, mm).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LampPatch {
    /// The film box `[x0, x1, y0, y1]` where the lamp can be seen.
    film: [f64; 4],
    /// The middle and half-size of the film box: what the polynomials'
    /// variables are relative to.
    mid: DVec2,
    half: f64,
    /// `c(x)`.
    centre: Cubic,
    /// The columns of `M(x)`.
    moves: [Cubic; 2],
    /// The patch's radius in lamp displacement, mm (the lamp's radius
    /// times the margin).
    reach: f64,
}

/// A patch at one film point: its centre, its matrix's columns and its
/// area (mm^2 of the rear plane).
struct PatchAt {
    centre: DVec2,
    moves: [DVec2; 2],
    area: f64,
}

impl LampPatch {
    /// The patch at film point (fx, fy): `None` outside the lamp's film box
    /// or where the model degenerates.
    fn at(&self, fx: f64, fy: f64) -> Option<PatchAt> {
        let [x0, x1, y0, y1] = self.film;
        if !(fx >= x0 && fx <= x1 && fy >= y0 && fy <= y1) {
            return None;
        }
        let t = monomials((DVec2::new(fx, fy) - self.mid) / self.half);
        let moves = [eval(&self.moves[0], &t), eval(&self.moves[1], &t)];
        let det = moves[0].perp_dot(moves[1]);
        let area = std::f64::consts::PI * self.reach * self.reach * det.abs();
        (area.is_finite() && area > 0.0).then(|| PatchAt { centre: eval(&self.centre, &t), moves, area })
    }
}

impl PatchAt {
    /// Whether rear-plane target `r` lies in the patch.
    fn contains(&self, r: DVec2, reach: f64) -> bool {
        let d = r - self.centre;
        let det = self.moves[0].perp_dot(self.moves[1]);
        // v = M^-1 d (Cramer)
        let v = DVec2::new(d.perp_dot(self.moves[1]), self.moves[0].perp_dot(d)) / det;
        v.length_squared() <= reach * reach
    }
}

/// The lamps a real-lens camera aims at: each lamp's patch model.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RealLampAim {
    patches: Vec<LampPatch>,
}

/// The patches seen from one film point (indices into the list), with the
/// uniform bounds' area there.
pub(crate) struct Seen {
    which: [u8; MAX_LAMPS],
    n: usize,
}

impl RealLampAim {
    /// Whether any lamp is aimed at.
    pub fn is_on(&self) -> bool {
        !self.patches.is_empty()
    }

    /// How many lamps have a patch model.
    pub fn lamps(&self) -> usize {
        self.patches.len()
    }

    /// Builds the patch models of `lamps` (centre and radius, lens frame,
    /// mm) by tracing, for each, a grid of rays from its centre and from
    /// its centre moved by its radius across the line of sight (twice)
    /// through the first surface's clear aperture (`first_sd`, mm, at the
    /// first vertex) to the film (`scene_to_film`, at `nm`). A lamp whose
    /// rays do not reach the film in enough places (fewer than 8, or all
    /// on a line) gets no model; at most [`MAX_LAMPS`] lamps (none beyond).
    pub(crate) fn build(
        lamps: &[(DVec3, f64)],
        scene_to_film: &LensTrace,
        first_sd: f64,
        z_film: f64,
        z_rear: f64,
        nm: f64,
    ) -> Self {
        if lamps.len() > MAX_LAMPS || !(first_sd.is_finite() && first_sd > 0.0) {
            return RealLampAim::default();
        }
        let grid: Vec<DVec2> = (0..GRID * GRID)
            .map(|k| {
                let (i, j) = ((k % GRID) as f64 + 0.5, (k / GRID) as f64 + 0.5);
                DVec2::new(2.0 * i / GRID as f64 - 1.0, 2.0 * j / GRID as f64 - 1.0) * first_sd
            })
            .filter(|p| p.length() <= first_sd)
            .collect();
        let patches =
            lamps.iter().filter_map(|&(c, r)| patch(c, r, &grid, scene_to_film, z_film, z_rear, nm)).collect();
        RealLampAim { patches }
    }

    /// The patches that can be seen from film point (fx, fy) and are
    /// smaller than the uniform bounds there (`uniform_area`, mm^2): a
    /// lamp in focus is seen through the whole pupil, and aiming at it
    /// would gain nothing.
    pub(crate) fn seen(&self, fx: f64, fy: f64, uniform_area: f64) -> Seen {
        let mut s = Seen { which: [0; MAX_LAMPS], n: 0 };
        for (k, p) in self.patches.iter().enumerate() {
            if p.at(fx, fy).is_some_and(|a| a.area < uniform_area) {
                s.which[s.n] = k as u8;
                s.n += 1;
            }
        }
        s
    }

    /// A rear-plane target drawn uniformly in one of the patches `seen`
    /// from (fx, fy) (the first uniform picks the patch, its remainder and
    /// the second place the point).
    pub(crate) fn draw(&self, seen: &Seen, fx: f64, fy: f64, a: (f64, f64)) -> Option<DVec2> {
        let scaled = a.0 * seen.n as f64;
        let j = (scaled as usize).min(seen.n.checked_sub(1)?);
        let p = &self.patches[seen.which[j] as usize];
        let at = p.at(fx, fy)?;
        let (radius, phi) = ((scaled - j as f64).clamp(0.0, 1.0).sqrt() * p.reach, std::f64::consts::TAU * a.1);
        let v = DVec2::new(phi.cos(), phi.sin()) * radius;
        Some(at.centre + at.moves[0] * v.x + at.moves[1] * v.y)
    }

    /// The density (per mm^2 of the rear plane) with which [`Self::draw`]
    /// gives target `r` from (fx, fy): the mean over the patches seen of
    /// their uniform densities.
    pub(crate) fn density(&self, seen: &Seen, fx: f64, fy: f64, r: DVec2) -> f64 {
        if seen.n == 0 {
            return 0.0;
        }
        let mut sum = 0.0;
        for &k in &seen.which[..seen.n] {
            let p = &self.patches[k as usize];
            if let Some(at) = p.at(fx, fy) {
                if at.contains(r, p.reach) {
                    sum += 1.0 / at.area;
                }
            }
        }
        sum / seen.n as f64
    }
}

impl Seen {
    /// Whether no patch is seen.
    pub(crate) fn is_empty(&self) -> bool {
        self.n == 0
    }
}

/// Where rays from `from` through the first-vertex points `grid` reach the
/// film: per grid point, the film point and the rear-plane crossing, or
/// `None` where the ray is blocked.
fn landings(
    from: DVec3,
    grid: &[DVec2],
    scene_to_film: &LensTrace,
    z_film: f64,
    z_rear: f64,
    nm: f64,
) -> Vec<Option<(DVec2, DVec2)>> {
    let mut batch = SpectralBatch::with_capacity(grid.len());
    for g in grid {
        let to = DVec3::new(g.x, g.y, 0.0) - from;
        match to.try_normalize() {
            Some(direction) => batch.push(lens::Ray { origin: from, direction }, nm),
            None => {
                batch.push(lens::Ray::default(), nm);
                let last = batch.len() - 1;
                batch.rays.status[last] = u64::MAX;
            }
        }
    }
    let mut t = Vec::new();
    scene_to_film.trace(&mut batch, false, &mut t, |_, _| 1.0);
    let r = &batch.rays;
    (0..grid.len())
        .map(|i| {
            let ok = r.status[i] == 0
                && t[i] > 0.0
                && r.dz[i] > 0.0
                && (r.z[i] - z_film).abs() < 1e-6 * z_film.abs().max(1.0);
            ok.then(|| {
                let film = DVec2::new(r.x[i], r.y[i]);
                let back = (z_film - z_rear) / r.dz[i];
                (film, film - DVec2::new(r.dx[i], r.dy[i]) * back)
            })
        })
        .collect()
}

/// The cubic's terms at (u, v).
fn monomials(p: DVec2) -> [f64; TERMS] {
    let mut t = [0.0; TERMS];
    let mut k = 0;
    for degree in 0..=5 {
        for j in 0..=degree {
            t[k] = p.x.powi(degree - j) * p.y.powi(j);
            k += 1;
        }
    }
    t
}

/// A cubic at the terms `t`.
fn eval(c: &Cubic, t: &[f64; TERMS]) -> DVec2 {
    c.iter().zip(t).fold(DVec2::ZERO, |s, (c, t)| s + *c * *t)
}

/// Least-squares cubic from film points to rear-plane points over the
/// pairs (film points relative to `mid`, over `half`), and its largest
/// residual, mm; `None` when the film points do not fix a cubic.
fn fit(pairs: &[(DVec2, DVec2)], mid: DVec2, half: f64) -> Option<(Cubic, f64)> {
    if pairs.len() < 2 * TERMS {
        return None;
    }
    let a = DMatrix::from_fn(pairs.len(), TERMS, |i, j| monomials((pairs[i].0 - mid) / half)[j]);
    let svd = a.clone().svd(true, true);
    // a rank-deficient design (film points on a line): no fit
    let s = &svd.singular_values;
    if s.min() <= 1e-9 * s.max() {
        return None;
    }
    let solve = |b: DVector<f64>| svd.solve(&b, 0.0).ok();
    let cx = solve(DVector::from_iterator(pairs.len(), pairs.iter().map(|p| p.1.x)))?;
    let cy = solve(DVector::from_iterator(pairs.len(), pairs.iter().map(|p| p.1.y)))?;
    let mut c = [DVec2::ZERO; TERMS];
    for (j, v) in c.iter_mut().enumerate() {
        *v = DVec2::new(cx[j], cy[j]);
    }
    let mut misses: Vec<f64> =
        pairs.iter().map(|(x, y)| (eval(&c, &monomials((*x - mid) / half)) - *y).length()).collect();
    misses.sort_by(f64::total_cmp);
    let worst = misses[(misses.len() * 9 / 10).min(misses.len() - 1)];
    (c.iter().all(|v| v.is_finite()) && worst.is_finite()).then_some((c, worst))
}

/// One lamp's patch model (see the module), or `None`.
fn patch(
    c: DVec3,
    radius: f64,
    grid: &[DVec2],
    scene_to_film: &LensTrace,
    z_film: f64,
    z_rear: f64,
    nm: f64,
) -> Option<LampPatch> {
    // in front of the first vertex, clear of it
    if !(c.is_finite() && radius > 0.0 && c.z + radius < 0.0) {
        return None;
    }
    // two directions across the line of sight to the lens
    let sight = (DVec3::ZERO - c).try_normalize()?;
    let (u1, u2) = crate::material::basis(sight);
    let centres = [c, c + u1 * radius, c + u2 * radius];
    let traced: Vec<Vec<Option<(DVec2, DVec2)>>> =
        centres.iter().map(|&o| landings(o, grid, scene_to_film, z_film, z_rear, nm)).collect();
    let pairs = |m: usize| -> Vec<(DVec2, DVec2)> {
        (0..grid.len()).filter(|&i| traced.iter().all(|t| t[i].is_some())).filter_map(|i| traced[m][i]).collect()
    };
    let (p0, p1, p2) = (pairs(0), pairs(1), pairs(2));
    // the film box of every traced landing, grown by a fiftieth
    let mut b = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
    for (x, _) in p0.iter().chain(&p1).chain(&p2) {
        b = [b[0].min(x.x), b[1].max(x.x), b[2].min(x.y), b[3].max(x.y)];
    }
    let mid = DVec2::new(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]));
    let half = 0.5 * (b[1] - b[0]).max(b[3] - b[2]);
    if !(half.is_finite() && half > 0.0) {
        return None;
    }
    let (c0, worst) = fit(&p0, mid, half)?;
    let (c1, _) = fit(&p1, mid, half)?;
    let (c2, _) = fit(&p2, mid, half)?;
    let moves = [c1, c2].map(|c| {
        let mut m = [DVec2::ZERO; TERMS];
        for j in 0..TERMS {
            m[j] = (c[j] - c0[j]) / radius;
        }
        m
    });
    let grow = 0.15 * half;
    let film = [b[0] - grow, b[1] + grow, b[2] - grow, b[3] + grow];
    // the margin: the fit's largest residual against the patch's size at
    // the box's middle
    let t = monomials(DVec2::ZERO);
    let size = radius * eval(&moves[0], &t).perp_dot(eval(&moves[1], &t)).abs().sqrt();
    if !(size.is_finite() && size > 0.0) {
        return None;
    }
    let margin = (1.1 + 1.5 * worst / size).min(4.0);
    Some(LampPatch { film, mid, half, centre: c0, moves, reach: radius * margin })
}
