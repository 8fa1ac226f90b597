//! Pupil sampling patterns: normalised (px, py) points inside the unit disc.

/// How the pupil is sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pattern {
    /// The points of an n x n grid on [-1, 1]^2 that lie inside the unit
    /// circle (n odd includes the centre).
    Square,
    /// The centre and n rings; ring k (1..=n) at radius k/n holds 6k points.
    Hexapolar,
    /// n points uniform over the disc, from a fixed-seed generator
    /// (SplitMix64), so a run is reproducible.
    Random,
}

/// The pupil points of `pattern` with size parameter `n` (grid width, ring
/// count or point count).
///
/// ```
/// use lens::analysis::pattern::{points, Pattern};
/// assert_eq!(points(Pattern::Hexapolar, 2).len(), 1 + 6 + 12);
/// assert!(points(Pattern::Square, 101).iter().all(|(x, y)| x * x + y * y <= 1.0 + 1e-12));
/// ```
pub fn points(pattern: Pattern, n: usize) -> Vec<(f64, f64)> {
    match pattern {
        Pattern::Square => {
            let mut v = Vec::new();
            if n == 1 {
                return vec![(0.0, 0.0)];
            }
            for i in 0..n {
                for j in 0..n {
                    let x = -1.0 + 2.0 * j as f64 / (n - 1) as f64;
                    let y = -1.0 + 2.0 * i as f64 / (n - 1) as f64;
                    if x * x + y * y <= 1.0 + 1e-12 {
                        v.push((x, y));
                    }
                }
            }
            v
        }
        Pattern::Hexapolar => {
            let mut v = vec![(0.0, 0.0)];
            for k in 1..=n {
                let r = k as f64 / n as f64;
                for j in 0..6 * k {
                    let a = std::f64::consts::TAU * j as f64 / (6 * k) as f64;
                    v.push((r * a.cos(), r * a.sin()));
                }
            }
            v
        }
        Pattern::Random => {
            let mut rng = SplitMix64(0x5eed_1e45);
            (0..n)
                .map(|_| {
                    let r = rng.unit().sqrt();
                    let a = std::f64::consts::TAU * rng.unit();
                    (r * a.cos(), r * a.sin())
                })
                .collect()
        }
    }
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
