//! Where a source's light can enter the lens for the flare's first look,
//! stopped down: the source's footprint (where its rays that pass the
//! stop entered) and, for a ghost reflected twice in front of the stop,
//! the cells whose rays meet the stop's opening.

use super::{Bright, LOOK_CELLS};
use lens::ghost::image::Entrance;
use lens::ghost::Source;
use lens::{Prescription, Tracer};
use rayon::prelude::*;

/// Each source's footprint: the part of its entrance square (a square
/// of the plane [`Entrance::of`] gives) whose rays pass the front
/// surfaces and the stop of `p`, from a grid of about eight points across
/// the paraxial entrance pupil (at least 32 across the square), widened by
/// one of its cells; `None` where no point's ray passes. Stopped down, the
/// light of the primary image and of every ghost reflected at or past the
/// stop entered there, a few of the square's look cells or fewer.
pub(super) fn footprints(p: &Prescription, sources: &[Bright]) -> Vec<Option<Entrance>> {
    let stop = p.stop_index();
    let to_stop = Tracer::forward_range(p, 0..stop + 1);
    let pupil = lens::paraxial::FirstOrder::of(p).ok().map(|f| f.entrance_pupil.diameter.abs());
    sources
        .iter()
        .map(|b| {
            let e = Entrance::of(p, &b.source);
            let cells = match pupil {
                Some(d) if d > 0.0 => (16.0 * e.half_mm / d).ceil().clamp(32.0, 256.0) as usize,
                _ => 32,
            };
            e.around_passing(&to_stop, &b.source, cells, 1)
        })
        .collect()
}

/// The part of `square` (a source's entrance square) whose rays can pass
/// the stop of `p` along `path` (a ghost reflected twice in front of it):
/// the cells of a [`LOOK_CELLS`] grid over it where the points its
/// corners' rays meet the stop surface (those that get there, blocked by
/// the stop or not), widened by half their spread, reach the stop's
/// opening, and one cell more each side; `None` where no cell's do.
/// Stopped down, that part is a few cells or less of the square, which
/// the look's corners would step over. `None` too where the stop is
/// decentred or tilted (its opening is then not about the axis).
pub(super) fn toward_stop(path: &Tracer, p: &Prescription, source: &Source, square: &Entrance) -> Option<Entrance> {
    let (stop, sd) = (p.stop_index(), p.stop_semi_diameter());
    if p.placements().get(stop).is_some_and(|m| m.is_some()) {
        return None;
    }
    let n = LOOK_CELLS;
    let side = 2.0 * square.half_mm / n as f64;
    let at = |i: usize, j: usize| {
        [square.centre[0] - square.half_mm + i as f64 * side, square.centre[1] - square.half_mm + j as f64 * side]
    };
    let hits: Vec<Option<[f64; 2]>> = (0..(n + 1) * (n + 1))
        .into_par_iter()
        .map(|k| {
            let [x, y] = at(k % (n + 1), k / (n + 1));
            let (ray, _) = square.ray_at(source, x, y)?;
            path.trace_at_surface(ray, stop).1.map(|v| [v.x, v.y])
        })
        .collect();
    let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
    for j in 0..n {
        for i in 0..n {
            let c: Vec<[f64; 2]> = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                .iter()
                .filter_map(|&(a, b)| hits[b * (n + 1) + a])
                .collect();
            if c.is_empty() {
                continue;
            }
            let lo = c.iter().fold([f64::INFINITY; 2], |m, v| [m[0].min(v[0]), m[1].min(v[1])]);
            let hi = c.iter().fold([f64::NEG_INFINITY; 2], |m, v| [m[0].max(v[0]), m[1].max(v[1])]);
            let grow = 0.5 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
            // the box's nearest point to the stop's centre, on the axis
            let near = |a: f64, b: f64| {
                if a - grow > 0.0 {
                    a - grow
                } else if b + grow < 0.0 {
                    b + grow
                } else {
                    0.0
                }
            };
            if near(lo[0], hi[0]).hypot(near(lo[1], hi[1])) <= sd {
                (i0, i1, j0, j1) = (i0.min(i), i1.max(i + 1), j0.min(j), j1.max(j + 1));
            }
        }
    }
    if i0 == usize::MAX {
        return None;
    }
    let (lo, hi) = (at(i0.saturating_sub(1), j0.saturating_sub(1)), at((i1 + 1).min(n), (j1 + 1).min(n)));
    Some(Entrance {
        z_mm: square.z_mm,
        centre: [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0],
        half_mm: ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 2.0).min(square.half_mm),
    })
}
