//! A ghost's image of a point source on a film grid, rasterised from a
//! grid of rays.
//!
//! The source's light is cut into cells on an entrance plane in front of
//! the lens (a square over the first surface's clear aperture); each cell's
//! corner rays are traced through the path (ghost or primary) with their
//! Fresnel weights ([`crate::Tracer::trace_fresnel`]), and the cell's power
//! (times its corners' mean weight) is spread evenly over the two film
//! triangles its corners make. A cell whose corners do not all reach the
//! film (one is blocked by a clear aperture) is split in four, down to
//! [`MAX_SPLITS`] times; in a cell still mixed then, the light's edge is
//! found on its sides by bisection and the part that reaches is deposited
//! as a polygon (so a ghost's rim is smooth, not the cells' staircase).
//! Smooth (no noise) and energy-conserving: every watt of a cell that
//! reaches the film lands in some triangle (on the grid or, counted in
//! `total`, off it).
//!
//! The rays go through the batch tracer ([`crate::Tracer::trace_fresnel_soa`],
//! the same bits as one at a time): the grid's corners together, then the
//! points the cells will ask for traced ahead a level at a time (the
//! midpoints of the cells to split, then each bisection step of the
//! finest mixed cells' sides), so that the cells, walked in a fixed order,
//! find every ray traced.

use super::coverage::{pixel_areas, polygon_area};
use crate::model::Prescription;
use crate::trace::{Outcome, Ray, RayBatch, Tracer};
use glam::DVec3;
use rayon::prelude::*;
use std::cell::RefCell;
use std::collections::HashMap;

/// How many times a cell whose corners do not all reach the film is split
/// in four (each level halves the width of the edge band it is unsure of).
pub const MAX_SPLITS: u32 = 4;

/// A grid of square pixels on the film plane: `nx` by `ny` pixels of
/// `pixel_mm`, centred on `centre_mm` (film x, y, mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmGrid {
    /// The grid's centre on the film, mm.
    pub centre_mm: [f64; 2],
    /// The pixels' width and height, mm.
    pub pixel_mm: f64,
    /// Pixels across (x).
    pub nx: usize,
    /// Pixels down (y).
    pub ny: usize,
}

impl FilmGrid {
    /// Pixel coordinates (continuous: pixel (i, j) spans [i, i + 1) x [j,
    /// j + 1)) of the film point (x, y) mm.
    pub fn to_pixels(&self, x: f64, y: f64) -> (f64, f64) {
        (
            (x - self.centre_mm[0]) / self.pixel_mm + self.nx as f64 / 2.0,
            (y - self.centre_mm[1]) / self.pixel_mm + self.ny as f64 / 2.0,
        )
    }

    /// The film point (mm) at the centre of pixel `index` (row-major).
    pub fn centre_of(&self, index: usize) -> [f64; 2] {
        let (i, j) = (index % self.nx, index / self.nx);
        [
            self.centre_mm[0] + (i as f64 + 0.5 - self.nx as f64 / 2.0) * self.pixel_mm,
            self.centre_mm[1] + (j as f64 + 0.5 - self.ny as f64 / 2.0) * self.pixel_mm,
        ]
    }

    /// The index (row-major, y down the rows) of the pixel holding film
    /// point (x, y) mm, `None` off the grid.
    pub fn index_of(&self, x: f64, y: f64) -> Option<usize> {
        let (u, v) = self.to_pixels(x, y);
        (u >= 0.0 && v >= 0.0 && u < self.nx as f64 && v < self.ny as f64).then(|| v as usize * self.nx + u as usize)
    }
}

/// A point source, in the lens's global frame (mm, z from the first
/// vertex).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    /// At infinity, its light travelling along `direction` (unit, +z), of
    /// irradiance 1 across the beam: the power through an area A of a plane
    /// z = const is A |direction.z|.
    Direction(DVec3),
    /// At `position` (in front of the lens), of radiant intensity 1: the
    /// power into a solid angle is that solid angle.
    Point(DVec3),
}

/// A square of the entrance plane z = `z_mm` (in front of the lens),
/// centred on (`centre[0]`, `centre[1]`), `half_mm` wide each side of it:
/// where the source's rays start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entrance {
    /// The plane's z, mm from the first vertex (negative: in front).
    pub z_mm: f64,
    /// The square's centre, mm.
    pub centre: [f64; 2],
    /// Half the square's side, mm.
    pub half_mm: f64,
}

impl Entrance {
    /// The square that holds every ray of `source` that can meet the first
    /// surface inside its clear aperture (or within the largest clear
    /// aperture of the lens where the first has none), on a plane 1 mm in
    /// front of the first surface's rim or vertex, whichever is nearer the
    /// source.
    pub fn of(p: &Prescription, source: &Source) -> Entrance {
        let s = p.surfaces();
        let widest = s.iter().filter_map(|s| s.semi_diameter).fold(0.0, f64::max).max(1.0);
        let sd = s[0].semi_diameter.unwrap_or(widest);
        let rim = s[0].sag(sd).unwrap_or(0.0);
        let z_mm = rim.min(0.0) - 1.0;
        let depth = rim.abs() + 1.0;
        let (centre, slope) = match *source {
            Source::Direction(d) => {
                let t = DVec3::new(d.x / d.z, d.y / d.z, 0.0);
                ([t.x * z_mm, t.y * z_mm], t.length())
            }
            Source::Point(q) => {
                let k = (z_mm - q.z) / -q.z;
                let lateral = (q.x * q.x + q.y * q.y).sqrt();
                ([q.x * (1.0 - k), q.y * (1.0 - k)], (lateral + sd) / -q.z)
            }
        };
        Entrance { z_mm, centre, half_mm: sd * 1.02 + depth * slope }
    }

    /// The ray from the source through the entrance plane at (x, y) and
    /// the power it stands for per unit area of the plane (mm^-2 of the
    /// source's unit: irradiance or intensity).
    pub fn ray_at(&self, source: &Source, x: f64, y: f64) -> Option<(Ray, f64)> {
        let at = DVec3::new(x, y, self.z_mm);
        match *source {
            Source::Direction(d) => Ray::new(at, d).map(|r| (r, d.z.abs())),
            Source::Point(q) => {
                let v = at - q;
                let r2 = v.length_squared();
                Ray::new(at, v).map(|r| (r, v.z.abs() / (r2 * r2.sqrt())))
            }
        }
    }
}

impl Entrance {
    /// The smallest square of this entrance's plane, on its `cells` x
    /// `cells` grid, that holds every grid point whose ray reaches the film
    /// through `tracer`, widened by `margin` cells each side; `None` where
    /// no grid point's ray does. Where a test's brute-force rays need not
    /// go (they are unbiased on any region that holds the light's).
    pub fn around_passing(&self, tracer: &Tracer, source: &Source, cells: usize, margin: usize) -> Option<Entrance> {
        let n = cells.max(1);
        let side = 2.0 * self.half_mm / n as f64;
        let at = |i: usize| -self.half_mm + i as f64 * side;
        let grid = grid_corners(tracer, self, source, n, |i, j| [self.centre[0] + at(i), self.centre[1] + at(j)]);
        let hits = (0..=n).flat_map(|j| (0..=n).map(move |i| (i, j))).filter(|&(i, j)| grid[j][i].0.is_some());
        self.around_cells(side, hits, margin as f64)
    }

    /// The square of this entrance's plane that holds the grid points
    /// `hits` (column, row on a grid of cells `side` mm wide from its lower
    /// corner), widened by `margin` cells each side and no larger than this
    /// one; `None` without points.
    fn around_cells(&self, side: f64, hits: impl Iterator<Item = (usize, usize)>, margin: f64) -> Option<Entrance> {
        let at = |i: usize| -self.half_mm + i as f64 * side;
        let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
        for (i, j) in hits {
            (i0, i1, j0, j1) = (i0.min(i), i1.max(i), j0.min(j), j1.max(j));
        }
        if i0 == usize::MAX {
            return None;
        }
        let (x0, x1) = (at(i0) - margin * side, at(i1) + margin * side);
        let (y0, y1) = (at(j0) - margin * side, at(j1) + margin * side);
        let half = ((x1 - x0).max(y1 - y0) / 2.0).min(self.half_mm);
        Some(Entrance {
            z_mm: self.z_mm,
            centre: [self.centre[0] + (x0 + x1) / 2.0, self.centre[1] + (y0 + y1) / 2.0],
            half_mm: half,
        })
    }
}

/// A ghost's (or the primary's) image of a source.
#[derive(Debug, Clone, PartialEq)]
pub struct GhostImage {
    /// Power per pixel (the grid's, row-major), in the source's unit
    /// times mm^2 (irradiance) or sr (intensity).
    pub power: Vec<f64>,
    /// All the power that reached the film, on the grid or off it.
    pub total: f64,
    /// The power-weighted mean of where it landed on the film, mm.
    pub centroid_mm: [f64; 2],
    /// The part of the entrance plane whose grid corners' rays reached
    /// the film, widened by one cell each side (where the light that
    /// reached can have entered); `None` where no corner's ray reached or
    /// the image was not rasterised from a grid.
    pub entered: Option<Entrance>,
}

impl GhostImage {
    /// An empty image of `film`.
    pub fn empty(film: &FilmGrid) -> Self {
        GhostImage { power: vec![0.0; film.nx * film.ny], total: 0.0, centroid_mm: [0.0; 2], entered: None }
    }

    /// Adds `power` landing at the film point `at` (mm), for the
    /// centroid and total (not the pixels).
    pub(crate) fn count(&mut self, power: f64, at: [f64; 2]) {
        let t = self.total + power;
        if t > 0.0 {
            for (c, a) in self.centroid_mm.iter_mut().zip(at) {
                *c += (a - *c) * power / t;
            }
        }
        self.total = t;
    }

    /// Adds `power` at the film point `at`, in its pixel and the sums.
    pub fn deposit_point(&mut self, film: &FilmGrid, power: f64, at: [f64; 2]) {
        if let Some(i) = film.index_of(at[0], at[1]) {
            self.power[i] += power;
        }
        self.count(power, at);
    }

    /// Spreads `power` evenly over the film triangle `t` (mm): each pixel
    /// gets the share of the triangle's area that lies in it (the triangle
    /// clipped to the pixel's square); a triangle of no area lands in the
    /// pixel of its centroid.
    pub fn deposit_triangle(&mut self, film: &FilmGrid, power: f64, t: [[f64; 2]; 3]) {
        let centroid = [(t[0][0] + t[1][0] + t[2][0]) / 3.0, (t[0][1] + t[1][1] + t[2][1]) / 3.0];
        self.count(power, centroid);
        if film.nx == 0 || film.ny == 0 {
            return;
        }
        let q: [(f64, f64); 3] = t.map(|p| film.to_pixels(p[0], p[1]));
        let area = polygon_area(&q);
        let (nx, ny) = (film.nx as f64, film.ny as f64);
        let lo = |f: fn(&(f64, f64)) -> f64| q.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = |f: fn(&(f64, f64)) -> f64| q.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        let (u0, u1, v0, v1) = (lo(|p| p.0), hi(|p| p.0), lo(|p| p.1), hi(|p| p.1));
        if !(u1 >= 0.0 && v1 >= 0.0 && u0 < nx && v0 < ny) {
            return;
        }
        if area.is_nan() || area <= 1e-12 {
            if let Some(i) = film.index_of(centroid[0], centroid[1]) {
                self.power[i] += power;
            }
            return;
        }
        let (i0, i1) = (u0.max(0.0) as usize, (u1.min(nx - 1.0)) as usize);
        let (j0, j1) = (v0.max(0.0) as usize, (v1.min(ny - 1.0)) as usize);
        if i0 == i1 && j0 == j1 && u0 >= i0 as f64 && u1 <= (i0 + 1) as f64 && v0 >= j0 as f64 && v1 <= (j0 + 1) as f64
        {
            self.power[j0 * film.nx + i0] += power;
            return;
        }
        pixel_areas(&q, (i0, i1), (j0, j1), |i, j, a| self.power[j * film.nx + i] += power * a / area);
    }
}

/// Where one corner ray landed: film (x, y) mm and its Fresnel weight;
/// `None` where it did not reach the film.
type Corner = Option<([f64; 2], f64)>;

/// The corner ray through the entrance point (x, y).
fn corner(tracer: &Tracer, entrance: &Entrance, source: &Source, x: f64, y: f64) -> (Corner, f64) {
    let Some((ray, density)) = entrance.ray_at(source, x, y) else { return (None, 0.0) };
    match tracer.trace_fresnel(ray) {
        (Outcome::Reached { ray, .. }, w) if w > 0.0 => (Some(([ray.origin.x, ray.origin.y], w)), density),
        _ => (None, density),
    }
}

/// The corner rays through the entrance points `at`, traced together
/// ([`Tracer::trace_fresnel_soa`]: the same bits as [`corner`] one at a
/// time).
fn corners(tracer: &Tracer, entrance: &Entrance, source: &Source, at: &[[f64; 2]]) -> Vec<(Corner, f64)> {
    let mut batch = RayBatch::with_capacity(at.len());
    let mut density = Vec::with_capacity(at.len());
    for &[x, y] in at {
        match entrance.ray_at(source, x, y) {
            Some((ray, d)) => {
                batch.push(ray);
                density.push(d);
            }
            None => {
                batch.push_skipped();
                density.push(0.0);
            }
        }
    }
    let mut weights = Vec::new();
    tracer.trace_fresnel_soa(&mut batch, &mut weights);
    (0..at.len())
        .map(|i| {
            let reached = batch.status[i] == 0 && weights[i] > 0.0;
            (reached.then_some(([batch.x[i], batch.y[i]], weights[i])), density[i])
        })
        .collect()
}

/// Points of a grid traced together, at most (a larger grid is cut into
/// parts this size traced in parallel).
const BATCH: usize = 2048;

/// The corner rays of a grid of `(n + 1)^2` points, `point(i, j)`, by rows
/// (row j, column i): traced in batches, in parallel for a large grid.
fn grid_corners(
    tracer: &Tracer,
    entrance: &Entrance,
    source: &Source,
    n: usize,
    point: impl Fn(usize, usize) -> [f64; 2] + Sync,
) -> Vec<Vec<(Corner, f64)>> {
    let rows_per = (BATCH / (n + 1)).max(1);
    let parts: Vec<Vec<(Corner, f64)>> = (0..=n)
        .step_by(rows_per)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|j0| {
            let at: Vec<[f64; 2]> = (j0..(j0 + rows_per).min(n + 1))
                .flat_map(|j| (0..=n).map(move |i| (i, j)))
                .map(|(i, j)| point(i, j))
                .collect();
            corners(tracer, entrance, source, &at)
        })
        .collect();
    let all: Vec<(Corner, f64)> = parts.into_iter().flatten().collect();
    all.chunks(n + 1).map(|r| r.to_vec()).collect()
}

/// The image through `tracer` (a ghost's path, [`Tracer::ghost`], or the
/// primary's, [`Tracer::forward_to_film`], ending on the film plane) of
/// `source`, on `film`, from a `cells` x `cells` grid over `entrance`
/// (refined at the edges, see the module). A large grid's corners are
/// traced in parallel; the rest runs in a fixed order, so the image is
/// the same bits for any thread count.
pub fn rasterise(tracer: &Tracer, source: &Source, entrance: &Entrance, film: &FilmGrid, cells: usize) -> GhostImage {
    rasterise_with(tracer, source, entrance, film, cells, MAX_SPLITS, EDGE_STEPS)
}

/// [`rasterise`] with cells whose corners disagree split at most `splits`
/// times and the light's edge placed on a still-mixed cell's sides by
/// `edge_steps` bisections (0: the cell lands on its corners that reached;
/// at most 30 are taken): fewer rays for a coarser edge, as a renderer may
/// want. A point shared by neighbouring cells (a side's midpoint, the
/// points bisecting a side) is traced once.
pub fn rasterise_with(
    tracer: &Tracer,
    source: &Source,
    entrance: &Entrance,
    film: &FilmGrid,
    cells: usize,
    splits: u32,
    edge_steps: u32,
) -> GhostImage {
    let n = cells.max(1);
    let side = 2.0 * entrance.half_mm / n as f64;
    let at = |i: usize| -entrance.half_mm + i as f64 * side;
    let corners =
        grid_corners(tracer, entrance, source, n, |i, j| [entrance.centre[0] + at(i), entrance.centre[1] + at(j)]);
    let mut image = GhostImage::empty(film);
    let traced = RefCell::new(HashMap::new());
    // bisection past 2^-30 of a cell is below the rounding of its points
    let edge_steps = edge_steps.min(30);
    let unit = side / (1u64 << (MAX_SPLITS + edge_steps)) as f64;
    let origin = [entrance.centre[0] - entrance.half_mm, entrance.centre[1] - entrance.half_mm];
    let grid = Grid { tracer, entrance, source, film, edge_steps, origin, unit, traced: &traced };
    let hits = (0..=n).flat_map(|j| (0..=n).map(move |i| (i, j))).filter(|&(i, j)| corners[j][i].0.is_some());
    image.entered = entrance.around_cells(side, hits, 1.0);
    let depth = MAX_SPLITS - splits.min(MAX_SPLITS);
    let cells: Vec<Cell> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| Cell {
            xy: [entrance.centre[0] + at(i), entrance.centre[1] + at(j)],
            side,
            c: [corners[j][i], corners[j][i + 1], corners[j + 1][i + 1], corners[j + 1][i]],
            depth,
        })
        .collect();
    // every ray the cells will ask for, traced ahead in batches
    grid.trace_ahead(cells.clone());
    for c in cells {
        cell(&grid, &mut image, c);
    }
    image
}

/// Rays traced inside cells, by their point on a rasterisation's lattice
/// (column, row): where each landed, and its power density.
type Traced = HashMap<(i64, i64), (Corner, f64)>;

/// What every cell of one rasterisation shares: the path traced, the
/// entrance and source its rays start from, the film, the bisection steps
/// that place the light's edge in a mixed cell, and the rays traced inside
/// cells so far (a side's midpoint and the points bisecting it belong to
/// both cells that share it: traced once, read by the second).
#[derive(Clone, Copy)]
struct Grid<'a> {
    tracer: &'a Tracer,
    entrance: &'a Entrance,
    source: &'a Source,
    film: &'a FilmGrid,
    edge_steps: u32,
    /// The entrance square's lower corner, mm.
    origin: [f64; 2],
    /// The lattice every traced point lies on: a cell's side over 2^(most
    /// splits + bisection steps), mm.
    unit: f64,
    /// The rays traced inside cells, by their lattice point.
    traced: &'a RefCell<Traced>,
}

/// A cell of the entrance grid or of its splits: its lower corner `xy`
/// and side (mm), its corners' rays `c` (counter-clockwise from the lower
/// left) and how many times the grid's cells were split to make it.
#[derive(Clone, Copy)]
struct Cell {
    xy: [f64; 2],
    side: f64,
    c: [(Corner, f64); 4],
    depth: u32,
}

impl Cell {
    /// Its corners' entrance points, counter-clockwise from the lower left.
    fn points(&self) -> [[f64; 2]; 4] {
        let ([x, y], side) = (self.xy, self.side);
        [[x, y], [x + side, y], [x + side, y + side], [x, y + side]]
    }

    /// The points that split it in four: the midpoints of its bottom,
    /// right, top and left sides, and its centre.
    fn split_points(&self) -> [[f64; 2]; 5] {
        let ([x, y], side, h) = (self.xy, self.side, self.side / 2.0);
        [(h, 0.0), (side, h), (h, side), (0.0, h), (h, h)].map(|(dx, dy)| [x + dx, y + dy])
    }

    /// Its four quarters, from the rays `[b, r, t, l, m]` at its
    /// [`Self::split_points`].
    fn quarters(&self, [b, r, t, l, m]: [(Corner, f64); 5]) -> [Cell; 4] {
        let ([x, y], h, c, depth) = (self.xy, self.side / 2.0, self.c, self.depth + 1);
        [
            Cell { xy: [x, y], side: h, c: [c[0], b, m, l], depth },
            Cell { xy: [x + h, y], side: h, c: [b, c[1], r, m], depth },
            Cell { xy: [x + h, y + h], side: h, c: [m, r, c[2], t], depth },
            Cell { xy: [x, y + h], side: h, c: [l, m, t, c[3]], depth },
        ]
    }

    /// Side `k` (from corner k to corner k + 1) where one end reached the
    /// film and the other did not: its ends, from the one that reached.
    fn mixed_side(&self, k: usize) -> Option<([f64; 2], [f64; 2])> {
        let (a, b, at) = (k, (k + 1) % 4, self.points());
        match (self.c[a].0.is_some(), self.c[b].0.is_some()) {
            (true, false) => Some((at[a], at[b])),
            (false, true) => Some((at[b], at[a])),
            _ => None,
        }
    }
}

/// A mixed side of an edge cell being bisected: the ends that reached and
/// did not.
struct Bisect {
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Grid<'_> {
    /// The lattice point of the entrance point (x, y).
    fn key(&self, x: f64, y: f64) -> (i64, i64) {
        (((x - self.origin[0]) / self.unit).round() as i64, ((y - self.origin[1]) / self.unit).round() as i64)
    }

    /// The ray through the entrance point (x, y), traced once per lattice
    /// point (read from what [`Self::trace_ahead`] traced).
    fn corner(&self, x: f64, y: f64) -> (Corner, f64) {
        let key = self.key(x, y);
        if let Some(c) = self.traced.borrow().get(&key) {
            return *c;
        }
        let c = corner(self.tracer, self.entrance, self.source, x, y);
        self.traced.borrow_mut().insert(key, c);
        c
    }

    /// Traces the points of `at` not traced yet, together, and keeps them.
    fn trace_all(&self, at: &[[f64; 2]]) {
        let mut seen = std::collections::HashSet::new();
        let (keys, fresh): (Vec<(i64, i64)>, Vec<[f64; 2]>) = {
            let traced = self.traced.borrow();
            at.iter()
                .map(|&p| (self.key(p[0], p[1]), p))
                .filter(|(k, _)| !traced.contains_key(k) && seen.insert(*k))
                .unzip()
        };
        if fresh.is_empty() {
            return;
        }
        let out = corners(self.tracer, self.entrance, self.source, &fresh);
        self.traced.borrow_mut().extend(keys.into_iter().zip(out));
    }

    /// Traces ahead, a level at a time and each level's rays together,
    /// every point [`cell`] and [`edge_cell`] will ask for from the cells
    /// `todo`: the midpoints of the cells to split, level by level, then
    /// the bisections of the finest mixed cells' sides, step by step. The
    /// same decisions as theirs from the same rays, so that they then find
    /// every ray traced (and the image is the same bits as tracing each
    /// when asked).
    fn trace_ahead(&self, mut todo: Vec<Cell>) {
        let mut edges: Vec<Cell> = Vec::new();
        while !todo.is_empty() {
            let mut split = Vec::new();
            for t in todo {
                let reached = t.c.iter().filter(|k| k.0.is_some()).count();
                if reached == 0 || reached == 4 {
                    continue;
                }
                if t.depth >= MAX_SPLITS {
                    edges.push(t);
                } else {
                    split.push(t);
                }
            }
            let points: Vec<[f64; 2]> = split.iter().flat_map(Cell::split_points).collect();
            self.trace_all(&points);
            todo = split.iter().flat_map(|t| t.quarters(t.split_points().map(|[x, y]| self.corner(x, y)))).collect();
        }
        // the finest mixed cells' mixed sides, bisected a step at a time
        let mut sides: Vec<Bisect> = edges
            .iter()
            .flat_map(|t| (0..4).filter_map(|k| t.mixed_side(k)))
            .map(|(lo, hi)| Bisect { lo, hi })
            .collect();
        for _ in 0..self.edge_steps {
            let mids: Vec<[f64; 2]> =
                sides.iter().map(|b| [(b.lo[0] + b.hi[0]) / 2.0, (b.lo[1] + b.hi[1]) / 2.0]).collect();
            self.trace_all(&mids);
            for (b, mid) in sides.iter_mut().zip(mids) {
                match self.corner(mid[0], mid[1]) {
                    (Some(_), _) => b.lo = mid,
                    _ => b.hi = mid,
                }
            }
        }
    }
}

/// Bisection steps that place the edge of the light where it crosses a
/// mixed cell's side (to 1/16 of the side).
pub const EDGE_STEPS: u32 = 4;

/// A cell still mixed at the finest split: the part of it whose rays reach
/// the film, bounded by its corners that reached and by the points where
/// the light's edge crosses its sides (each found by bisection along the
/// side, the last point that reached), deposited as that polygon's fan of
/// film triangles, each with its share of the polygon's area on the
/// entrance. Where fewer than three points bound it, the power lands on
/// the segment or point they make.
fn edge_cell(g: &Grid, image: &mut GhostImage, cell: &Cell) {
    let (film, steps) = (g.film, g.edge_steps);
    let (c, side, at) = (cell.c, cell.side, cell.points());
    // (entrance point, film point, Fresnel weight, density)
    let mut poly: Vec<([f64; 2], [f64; 2], f64, f64)> = Vec::with_capacity(8);
    for k in 0..4 {
        if let Some((f, w)) = c[k].0 {
            poly.push((at[k], f, w, c[k].1));
        }
        // from the end that reached toward the one that did not
        let Some((mut lo, mut hi)) = cell.mixed_side(k) else { continue };
        let mut last = None;
        for _ in 0..steps {
            let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
            match g.corner(mid[0], mid[1]) {
                (Some((f, w)), d) => {
                    lo = mid;
                    last = Some((mid, f, w, d));
                }
                _ => hi = mid,
            }
        }
        if let Some(v) = last {
            poly.push(v);
        }
    }
    let area_of = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() / 2.0
    };
    let n = poly.len() as f64;
    let density = poly.iter().map(|v| v.3).sum::<f64>() / n;
    let weight = poly.iter().map(|v| v.2).sum::<f64>() / n;
    if poly.len() >= 3 {
        for k in 1..poly.len() - 1 {
            let a = area_of(poly[0].0, poly[k].0, poly[k + 1].0);
            image.deposit_triangle(film, a * density * weight, [poly[0].1, poly[k].1, poly[k + 1].1]);
        }
        return;
    }
    // a sliver the bisection did not open: the corners' share of the cell
    let p: Vec<([f64; 2], f64)> = c.iter().filter_map(|k| k.0).collect();
    let power = side * side * density * p.iter().map(|k| k.1).sum::<f64>() / 4.0;
    match poly.as_slice() {
        [a, b] => {
            const ALONG: usize = 8;
            for k in 0..ALONG {
                let f = (k as f64 + 0.5) / ALONG as f64;
                let at = [a.1[0] + f * (b.1[0] - a.1[0]), a.1[1] + f * (b.1[1] - a.1[1])];
                image.deposit_point(film, power / ALONG as f64, at);
            }
        }
        [a] => image.deposit_point(film, power, a.1),
        _ => {}
    }
}

/// One cell of the entrance grid (or of its splits): deposited, or split
/// where its corners disagree.
fn cell(g: &Grid, image: &mut GhostImage, here: Cell) {
    let (film, c, side) = (g.film, here.c, here.side);
    let reached = c.iter().filter(|k| k.0.is_some()).count();
    if reached == 0 {
        return;
    }
    let density = c.iter().map(|k| k.1).sum::<f64>() / 4.0;
    let area = side * side;
    if reached == 4 {
        let p: Vec<([f64; 2], f64)> = c.iter().filter_map(|k| k.0).collect();
        let w = p.iter().map(|k| k.1).sum::<f64>() / 4.0;
        let power = area * density * w;
        // the quad as two triangles, half the cell's power each (the
        // cell's own halves are equal)
        image.deposit_triangle(film, power / 2.0, [p[0].0, p[1].0, p[2].0]);
        image.deposit_triangle(film, power / 2.0, [p[0].0, p[2].0, p[3].0]);
        return;
    }
    if here.depth >= MAX_SPLITS {
        edge_cell(g, image, &here);
        return;
    }
    for quarter in here.quarters(here.split_points().map(|[x, y]| g.corner(x, y))) {
        cell(g, image, quarter);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of no pixels keeps only the sums (total, centroid).
    #[test]
    fn a_grid_of_no_pixels_keeps_the_sums() {
        let none = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 1.0, nx: 0, ny: 0 };
        let mut image = GhostImage::empty(&none);
        image.deposit_triangle(&none, 2.0, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        image.deposit_point(&none, 1.0, [0.0, 0.0]);
        assert_eq!(image.total, 3.0);
        // the triangle counted at its centroid (1/3, 1/3) with weight 2
        for c in image.centroid_mm {
            assert!((c - 2.0 / 9.0).abs() < 1e-15, "{c}");
        }
        assert!(image.power.is_empty());
    }
}
