//! Pupil sampling patterns: normalised (px, py) points inside the unit
//! disc, each with a weight (its share of the pupil area), so that a
//! weighted mean over the points estimates a mean over the pupil.

use super::quadrature::gauss_legendre;

/// How the pupil is sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pattern {
    /// Gauss–Legendre rings (the default): n rings at the Gauss–Legendre
    /// nodes of r^2 on [0, 1], each with 4n + 4 points evenly spaced in
    /// azimuth, weighted by the ring's quadrature weight. A smooth
    /// aberration's mean square over the pupil converges fast (exactly for
    /// a polynomial of degree < 2n in r^2 and < 4n + 4 in azimuth).
    #[default]
    Gauss,
    /// The points of an n x n grid on [-1, 1]^2 that lie inside the unit
    /// circle (n odd includes the centre); equal weights.
    Square,
    /// The centre and n rings; ring k (1..=n) at radius k/n holds 6k points.
    /// Equal weights, as design programs use it: it over-weights the rim
    /// (the rings are evenly spaced in radius, not in area), so its RMS
    /// converges to a biased value.
    Hexapolar,
    /// n points uniform over the disc, from a fixed-seed generator
    /// (SplitMix64), so a run is reproducible; equal weights.
    Random,
}

impl Pattern {
    /// How many points the pattern of size `n` has (an upper bound for the
    /// square grid, whose corners fall outside the disc), as f64 so that
    /// huge sizes do not overflow.
    pub fn count(self, n: usize) -> f64 {
        let n = n as f64;
        match self {
            Pattern::Gauss => n * (4.0 * n + 4.0),
            Pattern::Square => n * n,
            Pattern::Hexapolar => 1.0 + 3.0 * n * (n + 1.0),
            Pattern::Random => n,
        }
    }

    /// The pattern's name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Pattern::Gauss => "gauss",
            Pattern::Square => "square",
            Pattern::Hexapolar => "hexapolar",
            Pattern::Random => "random",
        }
    }
}

/// Calls `f(px, py, weight)` for every point of `pattern` with size
/// parameter `n` (rings, grid width or point count), in a fixed order,
/// without storing them. The weights of a pattern sum to its point count
/// for the equal-weight patterns and to the number of points for Gauss
/// rings too (each ring's weight is spread over its points).
pub fn for_each(pattern: Pattern, n: usize, mut f: impl FnMut(f64, f64, f64)) {
    match pattern {
        Pattern::Gauss => {
            if n == 0 {
                return;
            }
            let (nodes, weights) = gauss_legendre(n, 0.0, 1.0);
            let m = 4 * n + 4;
            let scale = m as f64 * n as f64;
            // alternate rings start half a step apart: two tables of
            // (cos, sin), made once
            let table = |offset: f64| -> Vec<(f64, f64)> {
                (0..m).map(|j| (std::f64::consts::TAU * (j as f64 + offset) / m as f64).sin_cos()).collect()
            };
            let tables = [table(0.0), table(0.5)];
            for (k, (u, w)) in nodes.iter().zip(&weights).enumerate() {
                let r = u.sqrt();
                for &(sin, cos) in &tables[k % 2] {
                    f(r * cos, r * sin, w * scale / m as f64);
                }
            }
        }
        Pattern::Square => {
            if n == 1 {
                f(0.0, 0.0, 1.0);
                return;
            }
            for i in 0..n {
                for j in 0..n {
                    let x = -1.0 + 2.0 * j as f64 / (n - 1) as f64;
                    let y = -1.0 + 2.0 * i as f64 / (n - 1) as f64;
                    if x * x + y * y <= 1.0 + 1e-12 {
                        f(x, y, 1.0);
                    }
                }
            }
        }
        Pattern::Hexapolar => {
            f(0.0, 0.0, 1.0);
            for k in 1..=n {
                let r = k as f64 / n as f64;
                for j in 0..6 * k {
                    let a = std::f64::consts::TAU * j as f64 / (6 * k) as f64;
                    f(r * a.cos(), r * a.sin(), 1.0);
                }
            }
        }
        Pattern::Random => {
            // uniform over the disc by rejection from the square (no
            // trigonometry: as fast as the trace of the ray it launches)
            let mut rng = SplitMix64(0x5eed_1e45);
            let mut made = 0;
            while made < n {
                let (x, y) = (2.0 * rng.unit() - 1.0, 2.0 * rng.unit() - 1.0);
                if x * x + y * y <= 1.0 {
                    f(x, y, 1.0);
                    made += 1;
                }
            }
        }
    }
}

/// The pupil points of `pattern` with size parameter `n` (without weights).
///
/// ```
/// use lens::analysis::pattern::{points, Pattern};
/// assert_eq!(points(Pattern::Hexapolar, 2).len(), 1 + 6 + 12);
/// assert_eq!(points(Pattern::Gauss, 3).len(), 3 * 16);
/// assert!(points(Pattern::Square, 101).iter().all(|(x, y)| x * x + y * y <= 1.0 + 1e-12));
/// ```
pub fn points(pattern: Pattern, n: usize) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for_each(pattern, n, |x, y, _| v.push((x, y)));
    v
}

/// SplitMix64 (Steele, Lea & Flood 2014): a small, well-mixed generator.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Gauss rings integrate r^2 and r^4 over the unit disc exactly
    /// (mean 1/2 and 1/3), as the equal-weight hexapolar rings do not.
    #[test]
    fn gauss_rings_have_area_weights() {
        let mean = |pattern, n, k: i32| {
            let (mut s, mut w) = (0.0, 0.0);
            for_each(pattern, n, |x: f64, y: f64, wt| {
                s += wt * (x * x + y * y).powi(k);
                w += wt;
            });
            s / w
        };
        assert!((mean(Pattern::Gauss, 4, 1) - 0.5).abs() < 1e-14);
        assert!((mean(Pattern::Gauss, 4, 2) - 1.0 / 3.0).abs() < 1e-14);
        assert!((mean(Pattern::Hexapolar, 12, 1) - 0.5).abs() > 0.01);
    }
}
