//! Cell bounds: a grid over the passing region's box, edge cells split, for
//! regions that are not star-shaped (see the module above).

use super::{passing_box, FilmPoint, Probe, PupilBounds, CELLS, SUB};

/// The cells of one bin (see the module's description).
pub(super) fn cells_bin(probe: &Probe, radii: &[FilmPoint], rear: f64) -> PupilBounds {
    let Some(b) = passing_box(probe, radii, rear) else { return PupilBounds::Empty };
    let side = (b[1] - b[0]).max(b[3] - b[2]);
    let (x0, y0) = (b[0], b[2]);
    let fine = CELLS * SUB;
    let h = side / fine as f64;
    // corners on the fine grid, (fine + 1)^2 of them; probed: the corners
    // of the coarse cells, then every corner of the edge cells
    let w = fine + 1;
    let mut known = vec![false; w * w];
    let mut pass = vec![false; w * w];
    let run = |idx: &[usize], known: &mut Vec<bool>, pass: &mut Vec<bool>| {
        let todo: Vec<usize> = idx.iter().copied().filter(|&k| !known[k]).collect();
        let targets: Vec<(f64, f64)> =
            todo.iter().map(|&k| (x0 + h * (k % w) as f64, y0 + h * (k / w) as f64)).collect();
        for (&k, p) in todo.iter().zip(probe.passes(radii, &targets)) {
            known[k] = true;
            pass[k] = p;
        }
    };
    let corner = |ci: usize, cj: usize| cj * SUB * w + ci * SUB;
    let coarse: Vec<usize> = (0..=CELLS).flat_map(|j| (0..=CELLS).map(move |i| corner(i, j))).collect();
    run(&coarse, &mut known, &mut pass);
    let cell_corners =
        |ci: usize, cj: usize| [corner(ci, cj), corner(ci + 1, cj), corner(ci, cj + 1), corner(ci + 1, cj + 1)];
    let hit: Vec<bool> =
        (0..CELLS * CELLS).map(|k| cell_corners(k % CELLS, k / CELLS).iter().any(|&c| pass[c])).collect();
    let near_hit = |ci: usize, cj: usize| {
        (cj.saturating_sub(1)..=(cj + 1).min(CELLS - 1))
            .any(|j| (ci.saturating_sub(1)..=(ci + 1).min(CELLS - 1)).any(|i| hit[j * CELLS + i]))
    };
    // whole cells: every corner passes and so do the cells around; edge
    // cells: the rest of those near a passing corner
    let mut whole = vec![false; CELLS * CELLS];
    let mut edge = vec![false; CELLS * CELLS];
    for cj in 0..CELLS {
        for ci in 0..CELLS {
            if !near_hit(ci, cj) {
                continue;
            }
            let all = cell_corners(ci, cj).iter().all(|&c| pass[c]);
            let around = (cj.saturating_sub(1)..=(cj + 1).min(CELLS - 1))
                .all(|j| (ci.saturating_sub(1)..=(ci + 1).min(CELLS - 1)).all(|i| hit[j * CELLS + i]));
            if all && around && ci > 0 && cj > 0 && ci + 1 < CELLS && cj + 1 < CELLS {
                whole[cj * CELLS + ci] = true;
            } else {
                edge[cj * CELLS + ci] = true;
            }
        }
    }
    let mut fine_corners = Vec::new();
    for k in (0..CELLS * CELLS).filter(|&k| edge[k]) {
        let (ci, cj) = (k % CELLS, k / CELLS);
        for j in 0..=SUB {
            for i in 0..=SUB {
                fine_corners.push((cj * SUB + j) * w + ci * SUB + i);
            }
        }
    }
    run(&fine_corners, &mut known, &mut pass);
    // a corner inside a whole cell counts as passing
    let passes = |fx: usize, fy: usize| {
        let k = fy * w + fx;
        pass[k] || {
            let (ci, cj) = ((fx / SUB).min(CELLS - 1), (fy / SUB).min(CELLS - 1));
            whole[cj * CELLS + ci] && !fx.is_multiple_of(SUB) && !fy.is_multiple_of(SUB)
        }
    };
    let big = side / CELLS as f64;
    let (mut whole_cells, mut sub) = (Vec::new(), Vec::new());
    for k in 0..CELLS * CELLS {
        let (ci, cj) = (k % CELLS, k / CELLS);
        if whole[k] {
            whole_cells.push([x0 + big * ci as f64, y0 + big * cj as f64]);
        } else if edge[k] {
            for j in 0..SUB {
                for i in 0..SUB {
                    let (fx, fy) = (ci * SUB + i, cj * SUB + j);
                    // kept when a passing corner lies within one sub-cell
                    let keep = (fy.saturating_sub(1)..=(fy + 2).min(fine))
                        .any(|y| (fx.saturating_sub(1)..=(fx + 2).min(fine)).any(|x| passes(x, y)));
                    if keep {
                        sub.push([x0 + h * fx as f64, y0 + h * fy as f64]);
                    }
                }
            }
        }
    }
    if whole_cells.is_empty() && sub.is_empty() {
        return PupilBounds::Empty;
    }
    PupilBounds::Cells { whole: whole_cells, whole_side: big, sub, sub_side: h }
}
