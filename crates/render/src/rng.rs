//! Deterministic random numbers: one generator per pixel, seeded from the
//! render seed and the pixel index, so a render is the same on any number of
//! threads.

use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// A per-pixel sampler.
pub struct Sampler(Xoshiro256PlusPlus);

impl Sampler {
    /// The sampler of pixel `index` for render seed `seed`.
    pub fn new(seed: u64, index: u64) -> Self {
        // SplitMix-style mixing keeps neighbouring pixels' streams apart.
        let mut z = seed ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        Sampler(Xoshiro256PlusPlus::seed_from_u64(z ^ (z >> 31)))
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0.random::<f64>()
    }

    /// Two uniforms in [0, 1).
    pub fn next2(&mut self) -> (f64, f64) {
        (self.uniform(), self.uniform())
    }
}

/// Shuffles `v` uniformly (Fisher-Yates) with the stream `s`.
pub fn shuffle(v: &mut [usize], s: &mut Sampler) {
    for i in (1..v.len()).rev() {
        let j = ((s.uniform() * (i + 1) as f64) as usize).min(i);
        v.swap(i, j);
    }
}

/// The (i, j) cell of an n x n stratification of sample `k` (0 <= k < n^2),
/// jittered by `u`: stratified samples for pixels and apertures.
pub fn stratified(k: usize, n: usize, u: (f64, f64)) -> (f64, f64) {
    let n = n.max(1);
    let (i, j) = (k % n, (k / n) % n);
    ((i as f64 + u.0) / n as f64, (j as f64 + u.1) / n as f64)
}
