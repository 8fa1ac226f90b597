//! A polygon star-shaped about a centre, drawn from uniformly: one of its
//! triangles (the centre and two neighbouring corners) chosen in proportion
//! to its area by an alias table, then a uniform point in the triangle.

/// A star-shaped polygon and the means to draw uniform points from it.
#[derive(Debug, Clone)]
pub struct Fan {
    /// The centre, mm.
    centre: [f64; 2],
    /// The corners relative to the centre, mm, in counter-clockwise order.
    corners: Vec<[f64; 2]>,
    /// Alias table over the triangles (probability of keeping the
    /// triangle, the other one), for a choice in proportion to area in
    /// constant time.
    alias: Vec<(f64, u32)>,
    /// Total area, mm^2.
    area: f64,
}

impl Fan {
    /// The fan of corners `corners` (absolute, mm, counter-clockwise) about
    /// `centre`; `None` unless every triangle has a positive area (the
    /// polygon is then star-shaped about the centre).
    pub fn new(centre: [f64; 2], corners: &[[f64; 2]]) -> Option<Fan> {
        if corners.len() < 3 {
            return None;
        }
        let rel: Vec<[f64; 2]> = corners.iter().map(|p| [p[0] - centre[0], p[1] - centre[1]]).collect();
        let areas: Vec<f64> = (0..rel.len())
            .map(|k| {
                let (p, q) = (rel[k], rel[(k + 1) % rel.len()]);
                0.5 * (p[0] * q[1] - p[1] * q[0])
            })
            .collect();
        if !areas.iter().all(|a| a.is_finite() && *a >= 0.0) {
            return None;
        }
        let area: f64 = areas.iter().sum();
        (area > 0.0).then(|| Fan { centre, corners: rel, alias: alias_table(&areas), area })
    }

    /// The polygon's area, mm^2.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// The centre, mm.
    pub fn centre(&self) -> [f64; 2] {
        self.centre
    }

    /// The corners, absolute, mm.
    pub fn corners(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.corners.iter().map(|p| [p[0] + self.centre[0], p[1] + self.centre[1]])
    }

    /// A uniform point of the polygon from two uniforms (the first one's
    /// remainder after the alias choice places the point across the
    /// triangle).
    #[inline]
    pub fn sample(&self, a: (f64, f64)) -> (f64, f64) {
        let scaled = a.0 * self.alias.len() as f64;
        let j = (scaled as usize).min(self.alias.len() - 1);
        let u = scaled - j as f64;
        let (keep, other) = self.alias[j];
        let (k, rest) = if u < keep { (j, u / keep) } else { (other as usize, (u - keep) / (1.0 - keep)) };
        let (mut s1, mut t1) = (rest.clamp(0.0, 1.0), a.1);
        if s1 + t1 > 1.0 {
            (s1, t1) = (1.0 - s1, 1.0 - t1);
        }
        let (p, q) = (self.corners[k], self.corners[(k + 1) % self.corners.len()]);
        (self.centre[0] + s1 * p[0] + t1 * q[0], self.centre[1] + s1 * p[1] + t1 * q[1])
    }
}

/// Walker's alias table (Vose's construction) for choosing index k with
/// probability `w[k] / sum(w)`: entry j keeps j with its probability and
/// otherwise gives its alias.
fn alias_table(w: &[f64]) -> Vec<(f64, u32)> {
    let n = w.len();
    let total: f64 = w.iter().sum();
    let mut p: Vec<f64> = w.iter().map(|x| x * n as f64 / total).collect();
    let mut table = vec![(1.0, 0u32); n];
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&k| p[k] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        table[s] = (p[s], l as u32);
        p[l] -= 1.0 - p[s];
        if p[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    for k in small.into_iter().chain(large) {
        table[k] = (1.0, k as u32);
    }
    table
}

/// The part of the polygon `subject` inside the convex polygon `clip` (both
/// counter-clockwise), by Sutherland-Hodgman clipping.
pub fn clip(subject: &[[f64; 2]], clip: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = subject.to_vec();
    for k in 0..clip.len() {
        let (a, b) = (clip[k], clip[(k + 1) % clip.len()]);
        // inside: left of the edge a -> b
        let side = |p: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (p, q) = (input[i], input[(i + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_clipped_by_a_triangle_and_drawn_from_uniformly() {
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let tri = [[-2.0, -2.0], [2.0, -2.0], [0.0, 2.0]];
        let q = clip(&square, &tri);
        let fan = Fan::new([0.0, 0.0], &q).unwrap();
        // the square less two corner triangles of area 1/4 each
        assert!((fan.area() - 3.5).abs() < 1e-12, "{}", fan.area());
        let n = 200_000;
        let mean_y = (0..n)
            .map(|k| fan.sample(((k as f64 + 0.5) / n as f64, (k as f64 * 0.618_033_988_749_895).fract())).1)
            .sum::<f64>()
            / n as f64;
        // centroid of the clipped square: 2 x 0.25 x (2/3) / 3.5 below 0
        assert!((mean_y + 2.0 / 21.0).abs() < 2e-3, "{mean_y}");
    }
}
