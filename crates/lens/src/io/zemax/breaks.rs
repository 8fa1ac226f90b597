//! Coordinate breaks in a Zemax file: the runs of surfaces a pair of
//! `COORDBRK`s decentres and tilts, read as elements or as a surface's own
//! motion, with the thicknesses along the co-axial axis (docs/zemax.md,
//! "Coordinate breaks").

use super::read::{err, Block, ZemaxError};

/// A run of surfaces between a coordinate break and the one that undoes
/// it: 0-based among the real surfaces, the motion in mm and degrees.
pub(super) struct Moved {
    pub(super) first: usize,
    pub(super) last: usize,
    pub(super) decenter: [f64; 2],
    pub(super) tilt: [f64; 2],
}

/// The surfaces of a file that are not coordinate breaks, each with its
/// thickness along the co-axial axis (lens units).
pub(super) type RealSurfaces<'a> = Vec<(&'a Block, f64)>;

/// The real surfaces of `blocks` (between object and image) with each one's
/// thickness along the co-axial axis (lens units), and the runs moved by
/// coordinate-break pairs: a break of order 0 with no z tilt and no
/// thickness (decentre, then tilt about x and the new y) before a run, and
/// after it the break that undoes it (the negated values, order 1; or
/// order 0 for a decentre alone or one tilt alone), the thicknesses
/// bringing the axis back to where it was (Zemax's tilt/decenter element
/// with a coordinate return). Runs nest two deep (a surface's own motion
/// inside an element's). `s` is the lens unit in mm.
pub(super) fn coordinate_breaks(blocks: &[Block], s: f64) -> Result<(RealSurfaces<'_>, Vec<Moved>), ZemaxError> {
    let is_break = |b: &Block| b.kind.as_deref() == Some("COORDBRK");
    let mut real: Vec<(&Block, f64)> = Vec::new();
    // open breaks: the block, its motion, the first real surface after it
    let mut open: Vec<(&Block, [f64; 2], [f64; 2], usize)> = Vec::new();
    let mut moved = Vec::new();
    for b in blocks {
        if !is_break(b) {
            real.push((b, b.disz.unwrap_or(0.0)));
            continue;
        }
        let (decenter, tilt) = ([b.parm[1] * s, b.parm[2] * s], [b.parm[3], b.parm[4]]);
        let order = b.parm[6] != 0.0;
        let disz = b.disz.unwrap_or(0.0) * s;
        if b.parm[5] != 0.0 {
            return Err(err(
                b.line,
                format!("surface {}: a coordinate break tilted about z is not supported", b.number),
            ));
        }
        let undoes = open.last().is_some_and(|(_, d, t, first)| {
            let close = |a: f64, b: f64| (a + b).abs() <= 1e-12 * (1.0 + a.abs());
            // a decentre alone, or a tilt about one axis alone, is undone
            // in either order
            let pure = (*d == [0.0; 2] && (t[0] == 0.0 || t[1] == 0.0)) || *t == [0.0; 2];
            *first < real.len()
                && close(d[0], decenter[0])
                && close(d[1], decenter[1])
                && close(t[0], tilt[0])
                && close(t[1], tilt[1])
                && (order || pure)
        });
        if undoes {
            let (_, d, t, first) = open.pop().expect("an open break");
            let last = real.len() - 1;
            if !open.is_empty() && first != last {
                return Err(err(
                    b.line,
                    format!(
                        "surface {}: a run of {} surfaces moved inside another moved run: only one surface's own \
                         decentre and tilt may nest inside an element's",
                        b.number,
                        last - first + 1
                    ),
                ));
            }
            // where the axis is after the run: it must be back on the axis
            let rotation = crate::model::Placement::of_motion(d, t).rotation;
            let h: f64 = real[first..last].iter().map(|r| r.1 * s).sum();
            let along = rotation * glam::DVec3::new(0.0, 0.0, h + real[last].1 * s);
            if along.x.hypot(along.y) > 1e-9 * (1.0 + along.length()) {
                return Err(err(
                    b.line,
                    format!(
                        "surface {}: after this coordinate break the axis is {:.6} mm off where it was: the \
                         thickness of the last tilted surface (SURF {}) must bring the coordinates back to the \
                         run's first vertex ({} mm) before the break undoes the tilt",
                        b.number,
                        along.x.hypot(along.y),
                        real[last].0.number,
                        -h / s
                    ),
                ));
            }
            real[last].1 = (along.z + disz - h) / s;
            moved.push(Moved { first, last, decenter: d, tilt: t });
        } else if !order && disz == 0.0 && open.len() < 2 {
            open.push((b, decenter, tilt, real.len()));
        } else {
            return Err(err(
                b.line,
                format!(
                    "surface {}: a coordinate break is read only as a decentre and tilt (order 0, no thickness) \
                     of a run of surfaces, undone by a later break (order 1, the negated values); this one {}",
                    b.number,
                    if open.len() >= 2 { "nests three deep" } else { "neither opens nor closes such a run" }
                ),
            ));
        }
    }
    if let Some((b, ..)) = open.last() {
        return Err(err(
            b.line,
            format!(
                "surface {}: this coordinate break is never undone: the surfaces after it would stay moved, \
                 which is not supported (add the break that undoes it after the moved surfaces)",
                b.number
            ),
        ));
    }
    // in the order they close: a surface's own run before its element's
    Ok((real, moved))
}
