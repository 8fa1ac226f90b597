//! How much of a film triangle lies in each pixel: the triangle cut to
//! each pixel row once (Sutherland-Hodgman, on the stack), each pixel's
//! share the difference of the row's areas left of its two sides; what a
//! ghost's rasterisation spreads a cell's power by.

/// Calls `add(i, j, a)` for each pixel (columns i0 to i1, rows j0 to j1,
/// inclusive) with the area `a` > 0 of the triangle `q` (pixel
/// coordinates: pixel (i, j) spans [i, i + 1) x [j, j + 1)) inside it.
/// Parts of the triangle outside those columns and rows are left out.
pub(crate) fn pixel_areas(
    q: &[(f64, f64); 3],
    (i0, i1): (usize, usize),
    (j0, j1): (usize, usize),
    mut add: impl FnMut(usize, usize, f64),
) {
    for j in j0..=j1 {
        let row = Clip::of(q).keep(1, j as f64, false).keep(1, (j + 1) as f64, true);
        let whole = row.area();
        if whole <= 0.0 {
            continue;
        }
        let (x0, x1) = row.span(0);
        let mut left = if x0 >= i0 as f64 { 0.0 } else { row.keep(0, i0 as f64, true).area() };
        for i in i0..=i1 {
            if (i as f64) >= x1 {
                break;
            }
            let side = (i + 1) as f64;
            let right = if side >= x1 { whole } else { row.keep(0, side, true).area() };
            let a = right - left;
            if a > 0.0 {
                add(i, j, a);
            }
            left = right;
        }
    }
}

/// A convex polygon of at most eight vertices, on the stack: a triangle cut
/// by up to five half-planes (Sutherland-Hodgman).
#[derive(Clone, Copy)]
struct Clip {
    v: [(f64, f64); 8],
    n: usize,
}

impl Clip {
    /// The triangle `t`.
    fn of(t: &[(f64, f64); 3]) -> Clip {
        let mut v = [(0.0, 0.0); 8];
        v[..3].copy_from_slice(t);
        Clip { v, n: 3 }
    }

    /// The part with coordinate `axis` (0: x, 1: y) at most (`below`) or at
    /// least `bound`.
    fn keep(&self, axis: usize, bound: f64, below: bool) -> Clip {
        let coord = |p: (f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let inside = |p: (f64, f64)| if below { coord(p) <= bound } else { coord(p) >= bound };
        let mut out = Clip { v: [(0.0, 0.0); 8], n: 0 };
        for k in 0..self.n {
            let (a, b) = (self.v[k], self.v[(k + 1) % self.n]);
            let (ia, ib) = (inside(a), inside(b));
            if ia && out.n < 8 {
                out.v[out.n] = a;
                out.n += 1;
            }
            if ia != ib && out.n < 8 {
                let s = (bound - coord(a)) / (coord(b) - coord(a));
                out.v[out.n] = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
                out.n += 1;
            }
        }
        out
    }

    /// Its area (0 with fewer than three vertices).
    fn area(&self) -> f64 {
        if self.n < 3 {
            0.0
        } else {
            polygon_area(&self.v[..self.n])
        }
    }

    /// The least and greatest coordinate `axis` of its vertices.
    fn span(&self, axis: usize) -> (f64, f64) {
        let c = |p: &(f64, f64)| if axis == 0 { p.0 } else { p.1 };
        self.v[..self.n].iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(c(p)), hi.max(c(p))))
    }
}

/// The area of a polygon (absolute, any winding).
pub(crate) fn polygon_area(p: &[(f64, f64)]) -> f64 {
    let n = p.len();
    (0..n).map(|k| p[k].0 * p[(k + 1) % n].1 - p[(k + 1) % n].0 * p[k].1).sum::<f64>().abs() / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ghost::{FilmGrid, GhostImage};

    /// The area of the triangle `t` inside the unit square [i, i + 1) x [j,
    /// j + 1) (Sutherland-Hodgman clipping by its four edges, on the stack).
    fn clipped_area(t: &[(f64, f64); 3], i: f64, j: f64) -> f64 {
        let inside_corner = |x: f64, y: f64| {
            let e = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0);
            let (e0, e1, e2) = (e(t[0], t[1]), e(t[1], t[2]), e(t[2], t[0]));
            (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0)
        };
        // the whole pixel inside: its four corners are
        if inside_corner(i, j)
            && inside_corner(i + 1.0, j)
            && inside_corner(i, j + 1.0)
            && inside_corner(i + 1.0, j + 1.0)
        {
            return 1.0;
        }
        let mut poly = [(0.0, 0.0); 8];
        let mut n = 3;
        poly[..3].copy_from_slice(t);
        let mut next = [(0.0, 0.0); 8];
        // each edge as (axis, bound, keep below)
        for (axis, bound, below) in [(0, i, false), (0, i + 1.0, true), (1, j, false), (1, j + 1.0, true)] {
            let coord = |p: (f64, f64)| if axis == 0 { p.0 } else { p.1 };
            let inside = |p: (f64, f64)| if below { coord(p) <= bound } else { coord(p) >= bound };
            let mut m = 0;
            for k in 0..n {
                let (a, b) = (poly[k], poly[(k + 1) % n]);
                let (ia, ib) = (inside(a), inside(b));
                if ia {
                    next[m] = a;
                    m += 1;
                }
                if ia != ib {
                    let s = (bound - coord(a)) / (coord(b) - coord(a));
                    next[m] = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
                    m += 1;
                }
            }
            if m < 3 {
                return 0.0;
            }
            poly[..m].copy_from_slice(&next[..m]);
            n = m;
        }
        polygon_area(&poly[..n])
    }

    /// A triangle's power lands in each pixel in proportion to the area of
    /// it there (against clipping it by each pixel's four sides), all of it
    /// on the grid when the triangle is, none of it off.
    #[test]
    fn triangles_spread_by_area() {
        let film = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 0.5, nx: 12, ny: 9 };
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            // film mm: some inside, some across the grid's edge
            let spread = if case % 2 == 0 { 2.5 } else { 4.0 };
            let t: [[f64; 2]; 3] =
                std::array::from_fn(|_| [spread * (2.0 * next() - 1.0), spread * (2.0 * next() - 1.0)]);
            let mut image = GhostImage::empty(&film);
            image.deposit_triangle(&film, 1.0, t);
            let q = t.map(|p| film.to_pixels(p[0], p[1]));
            let area = polygon_area(&q);
            if area < 1e-9 {
                continue;
            }
            let mut on = 0.0;
            for j in 0..film.ny {
                for i in 0..film.nx {
                    let want = clipped_area(&q, i as f64, j as f64) / area;
                    let got = image.power[j * film.nx + i];
                    assert!((got - want).abs() < 1e-12, "case {case} pixel ({i}, {j}): {got} vs {want}");
                    on += want;
                }
            }
            assert!((image.power.iter().sum::<f64>() - on).abs() < 1e-12);
            assert_eq!(image.total, 1.0);
        }
    }
}
