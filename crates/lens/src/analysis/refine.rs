//! Which nodes of a square grid pass a test, found without testing every
//! node, as a quadtree: the test runs on a coarse sub-grid first; a block
//! whose corners disagree has the nodes halfway between them tested, and
//! so on down to single cells, while the blocks whose corners agree take
//! their corners' common answer. Where a tested edge shows the boundary
//! entering a block with agreeing corners, that block is refined too (the
//! boundary followed from block to block).
//!
//! Field curves count the rays of a pupil grid that reach the image
//! (vignetting, relative illumination). The rays that pass fill the
//! preimage of every clear aperture at once, an intersection of nearly
//! convex regions (the apertures are discs): its boundary is one closed
//! curve, which crosses a block with agreeing corners only by entering and
//! leaving through its edges, where a tested neighbour's nodes show it. A
//! region that touches no coarse node at all (narrower than a coarse block
//! everywhere) would be missed; apertures make none.

/// Spacing of the coarse sub-grid, in grid cells.
pub(crate) const BLOCK: usize = 4;

/// Whether each node of an `n` x `n` grid passes (index `i * n + j`, row
/// `i`, column `j`), with `test` called on batches of node indices (it
/// returns one answer per index, in order): first the coarse nodes (every
/// [`BLOCK`]th row and column, and the last), then level by level, halving
/// the spacing, the nodes of the blocks whose corners disagree and of each
/// block next to a refined one whose shared edge has a node that disagrees
/// with the block's corners, where `wanted` holds. A node of another block
/// takes its corners' answer; a node that is not wanted and was not tested
/// is `false`.
pub(crate) fn passing_nodes(
    n: usize,
    wanted: impl Fn(usize) -> bool,
    mut test: impl FnMut(&[usize]) -> Vec<bool>,
) -> Vec<bool> {
    if n == 0 {
        return Vec::new();
    }
    // the grid lines at spacing `s`, and the last
    let lines = |s: usize| {
        let mut v: Vec<usize> = (0..n).step_by(s).collect();
        if v.last() != Some(&(n - 1)) {
            v.push(n - 1);
        }
        v
    };
    let mut known: Vec<Option<bool>> = vec![None; n * n];
    let mut tested = vec![false; n * n];
    let mut cur = lines(BLOCK);
    let first: Vec<usize> = cur.iter().flat_map(|&i| cur.iter().map(move |&j| i * n + j)).collect();
    for (&k, pass) in first.iter().zip(test(&first)) {
        (known[k], tested[k]) = (Some(pass), true);
    }
    // the blocks of this level to look at: all at first, then the halves
    // of those refined
    let mut s = BLOCK;
    let mut look: Vec<usize> = (0..(cur.len() - 1).pow(2)).collect();
    while s > 1 && cur.len() > 1 {
        let finer = lines(s / 2);
        let m = cur.len() - 1;
        // the finer lines from line `a` to line `a + 1` of this level, both
        // included (as positions in `finer`), and the nodes of block b on them
        // (line a of this level, a multiple of s, is line 2a of the finer
        // level; the last line is the last of both)
        let span = |a: usize| 2 * a..if a + 1 == m { finer.len() } else { 2 * a + 3 };
        let fine = &finer;
        let nodes = |b: usize| {
            let (rows, cols) = (span(b / m), span(b % m));
            fine[rows].iter().flat_map(move |&i| fine[cols.clone()].iter().map(move |&j| i * n + j))
        };
        let corners = |known: &[Option<bool>], b: usize| {
            let (bi, bj) = (b / m, b % m);
            [(bi, bj), (bi, bj + 1), (bi + 1, bj), (bi + 1, bj + 1)].map(|(a, c)| known[cur[a] * n + cur[c]])
        };
        // (a corner neither tested nor filled, one not wanted, counts as
        // disagreeing: the block's wanted nodes are then tested)
        let mut refine = vec![false; m * m];
        let mut round = Vec::new();
        for &b in &look {
            let c = corners(&known, b);
            if c.iter().any(|v| *v != c[0]) {
                refine[b] = true;
                round.push(b);
            }
        }
        let mut refined = Vec::new();
        while !round.is_empty() {
            let mut todo = Vec::new();
            for &b in &round {
                for k in nodes(b) {
                    if !tested[k] && wanted(k) {
                        // marked so that a node two blocks share is tested once
                        tested[k] = true;
                        todo.push(k);
                    }
                }
            }
            for (&k, pass) in todo.iter().zip(test(&todo)) {
                known[k] = Some(pass);
            }
            // the neighbours a refined block's edge shows the boundary entering
            let mut next = Vec::new();
            for &b in &round {
                let (bi, bj) = (b / m, b % m);
                let sides = [
                    (bi > 0).then(|| b - m),
                    (bi + 1 < m).then_some(b + m),
                    (bj > 0).then(|| b - 1),
                    (bj + 1 < m).then_some(b + 1),
                ];
                for nb in sides.into_iter().flatten() {
                    if refine[nb] {
                        continue;
                    }
                    let Some(answer) = corners(&known, nb).into_iter().flatten().next() else { continue };
                    let (rows, cols) = (span(bi), span(bj));
                    let mut shared = nodes(nb)
                        .filter(|k| finer[rows.clone()].contains(&(k / n)) && finer[cols.clone()].contains(&(k % n)));
                    if shared.any(|k| tested[k] && known[k] != Some(answer)) {
                        refine[nb] = true;
                        next.push(nb);
                    }
                }
            }
            refined.append(&mut round);
            round = next;
        }
        // every node of a block looked at and not refined takes its
        // corners' answer (it is not looked at again)
        for &b in look.iter().filter(|&&b| !refine[b]) {
            let (bi, bj) = (b / m, b % m);
            let Some(answer) = corners(&known, b).into_iter().flatten().next() else { continue };
            for i in cur[bi]..=cur[bi + 1] {
                for k in known[i * n + cur[bj]..=i * n + cur[bj + 1]].iter_mut().filter(|k| k.is_none()) {
                    *k = Some(answer);
                }
            }
        }
        // the refined blocks' halves are the next level's to look at
        let mf = finer.len() - 1;
        look = refined
            .iter()
            .flat_map(|&b| {
                let (rows, cols) = (span(b / m), span(b % m));
                let cols = cols.start..cols.end - 1;
                (rows.start..rows.end - 1).flat_map(move |i| cols.clone().map(move |j| i * mf + j))
            })
            .collect();
        (s, cur) = (s / 2, finer);
    }
    known.into_iter().map(|k| k.unwrap_or(false)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grid's answers against testing every node, and how many tests.
    fn compare(n: usize, inside: impl Fn(f64, f64) -> bool) -> (usize, usize) {
        let at = |k: usize| ((k % n) as f64 / (n - 1) as f64, (k / n) as f64 / (n - 1) as f64);
        let mut tested = 0;
        let got = passing_nodes(
            n,
            |_| true,
            |ks| {
                tested += ks.len();
                ks.iter().map(|&k| inside(at(k).0, at(k).1)).collect()
            },
        );
        let wrong = (0..n * n).filter(|&k| got[k] != inside(at(k).0, at(k).1)).count();
        (wrong, tested)
    }

    #[test]
    fn discs_and_their_intersections_are_found_exactly_with_fewer_tests() {
        let disc = |cx: f64, cy: f64, r: f64| move |x: f64, y: f64| (x - cx).powi(2) + (y - cy).powi(2) <= r * r;
        for n in [41, 81, 30] {
            for (cx, cy, r) in [(0.5, 0.5, 0.45), (0.3, 0.6, 0.2), (0.9, 0.1, 0.5), (0.5, 0.5, 0.08)] {
                let (wrong, tested) = compare(n, disc(cx, cy, r));
                assert_eq!(wrong, 0, "n {n} disc ({cx}, {cy}) r {r}");
                assert!(tested < n * n, "n {n}: {tested} tests");
            }
            // a lens (two discs' intersection), the shape of a vignetted pupil
            let (a, b) = (disc(0.45, 0.5, 0.4), disc(0.7, 0.5, 0.35));
            let (wrong, tested) = compare(n, |x, y| a(x, y) && b(x, y));
            assert_eq!(wrong, 0, "n {n} lens");
            assert!(tested * 2 < n * n, "n {n}: {tested} tests");
        }
        // everything and nothing: only the coarse nodes
        assert_eq!(compare(81, |_, _| true), (0, 21 * 21));
        assert_eq!(compare(81, |_, _| false), (0, 21 * 21));
        assert_eq!(compare(1, |_, _| true).0, 0);
    }

    /// Two thousand random intersections of two discs (a vignetted
    /// pupil's shape), each holding two coarse nodes or more, on a 41 x 41
    /// grid: found exactly.
    #[test]
    fn random_vignetted_pupils_are_found_exactly() {
        let mut seed = 12345u64;
        let mut uniform = || {
            // xorshift64
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 41;
        let mut checked = 0;
        for _ in 0..2000 {
            let (cx, cy, r) = (uniform(), uniform(), 0.2 + 0.5 * uniform());
            let (dx, dy, q) = (uniform(), uniform(), 0.2 + 0.5 * uniform());
            let inside = |x: f64, y: f64| {
                (x - cx).powi(2) + (y - cy).powi(2) <= r * r && (x - dx).powi(2) + (y - dy).powi(2) <= q * q
            };
            let coarse = (0..n * n).filter(|&k| k % n % BLOCK == 0 && k / n % BLOCK == 0);
            if coarse.filter(|&k| inside((k % n) as f64 / 40.0, (k / n) as f64 / 40.0)).count() < 2 {
                continue;
            }
            let (wrong, tested) = compare(n, inside);
            assert_eq!(wrong, 0, "discs ({cx}, {cy}, {r}) and ({dx}, {dy}, {q})");
            assert!(tested < n * n);
            checked += 1;
        }
        assert!(checked > 500, "{checked} shapes");
    }

    #[test]
    fn nodes_not_wanted_are_not_tested() {
        let n = 41;
        let wanted = |k: usize| k % n < 20;
        let got = passing_nodes(n, wanted, |ks| {
            // the coarse nodes are tested everywhere, the others only where wanted
            ks.iter().map(|&k| (k % n) < 30 && (k / n) < 25).collect()
        });
        for (k, pass) in got.iter().enumerate().filter(|(k, _)| wanted(*k)) {
            assert_eq!(*pass, (k / n) < 25, "node {k}");
        }
    }
}
