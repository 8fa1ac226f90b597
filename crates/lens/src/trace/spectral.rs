//! Rays of mixed wavelengths in one batch. Each ray carries its
//! wavelength; the tracer evaluates every glass's index for each ray (the
//! formulas written once over the lane type, `glass::kernel`, four rays at
//! a time) and refracts each ray with its own indices. A ray traced here
//! ends exactly where the one-wavelength tracer of
//! [`Prescription::at_wavelength`](crate::Prescription::at_wavelength) at
//! its wavelength puts it, to the bit; constant indices are the same at
//! every wavelength.

use super::batch::RayBatch;
#[cfg(target_arch = "x86_64")]
use super::batch::{Wide, VECTORS};
use super::ray::{Outcome, Ray};
use super::step::{lanes_at, Indices, Lane, StepLanes, NO_GLASS};
use super::tracer::Tracer;
use crate::error::OpticsError;
use crate::glass::kernel::{Kernel, Lambda};
#[cfg(target_arch = "x86_64")]
use crate::simd::avx512::F64x8;

/// Rays and the wavelength of each: a [`RayBatch`] with one more array.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpectralBatch {
    /// The rays (global frame, mm); after [`Tracer::trace_spectral`], where
    /// and how each ended, as for [`Tracer::trace_soa`].
    pub rays: RayBatch,
    /// The wavelength of each ray, nm (in air, as the catalogues' indices
    /// are), one per ray.
    pub wavelength_nm: Vec<f64>,
}

impl SpectralBatch {
    /// An empty batch with room for `n` rays.
    pub fn with_capacity(n: usize) -> Self {
        SpectralBatch { rays: RayBatch::with_capacity(n), wavelength_nm: Vec::with_capacity(n) }
    }

    /// Appends a ray of wavelength `wavelength_nm` (status 0, path length 0).
    pub fn push(&mut self, r: Ray, wavelength_nm: f64) {
        self.rays.push(r);
        self.wavelength_nm.push(wavelength_nm);
    }

    /// Appends a placeholder the tracer leaves alone, at `wavelength_nm`
    /// ([`RayBatch::push_skipped`]).
    pub fn push_skipped(&mut self, wavelength_nm: f64) {
        self.rays.push_skipped();
        self.wavelength_nm.push(wavelength_nm);
    }

    /// Number of rays.
    pub fn len(&self) -> usize {
        self.rays.len()
    }

    /// Whether the batch is empty.
    pub fn is_empty(&self) -> bool {
        self.rays.is_empty()
    }

    /// Removes every ray, keeping the allocations.
    pub fn clear(&mut self) {
        self.rays.clear();
        self.wavelength_nm.clear();
    }
}

/// Each glass's index for the rays of one chunk, and
/// its inverse where a ray enters the glass from air.
#[derive(Default)]
pub(crate) struct ChunkIndices {
    #[cfg(target_arch = "x86_64")]
    pub(super) n: Vec<[[f64; 4]; VECTORS]>,
    #[cfg(target_arch = "x86_64")]
    pub(super) inv: Vec<[[f64; 4]; VECTORS]>,
    /// Whether a ray enters glass `g` from index 1 (and so takes `inv`).
    from_air: Vec<bool>,
    /// Whether a glass's formula takes 1/λ² (the Sellmeier ones do not).
    inv_l2: bool,
}

/// The indices of vector `j` of a chunk.
#[cfg(target_arch = "x86_64")]
pub(super) struct Vector<'a> {
    ix: &'a ChunkIndices,
    j: usize,
}

#[cfg(target_arch = "x86_64")]
impl ChunkIndices {
    /// The indices of the rays of vector `j` (of [`Wide::N`] rays).
    #[inline(always)]
    pub(super) fn vector(&self, j: usize) -> Vector<'_> {
        Vector { ix: self, j }
    }
}

#[cfg(target_arch = "x86_64")]
impl<W: Wide> Indices<W> for Vector<'_> {
    #[inline(always)]
    fn n(&self, g: usize) -> W {
        W::at(self.ix.n[g].as_flattened(), self.j)
    }
    #[inline(always)]
    fn inv(&self, g: usize) -> W {
        W::at(self.ix.inv[g].as_flattened(), self.j)
    }
}

/// One ray's indices of each glass and their inverses.
struct OneRay {
    n: Vec<f64>,
    inv: Vec<f64>,
}

impl Indices<f64> for OneRay {
    #[inline(always)]
    fn n(&self, g: usize) -> f64 {
        self.n[g]
    }
    #[inline(always)]
    fn inv(&self, g: usize) -> f64 {
        self.inv[g]
    }
}

impl Tracer {
    /// Traces every ray of `batch` at its own wavelength, in place (as
    /// [`Self::trace_soa`] does at the prescription's). Errors, tracing
    /// nothing, when the batch's arrays differ in length or a wavelength
    /// lies outside a glass's data (the error names the glass and its
    /// range). A prescription without glasses traces as
    /// [`Self::trace_soa`].
    ///
    /// ```
    /// use glam::DVec3;
    /// use lens::{Prescription, Ray, Tracer, trace::SpectralBatch};
    /// let p = Prescription::from_json_str(r#"{"surfaces": [
    ///   {"radius": 51.5, "thickness": 3.6, "glass": "SCHOTT:N-BK7", "semi_diameter": 12.7, "stop": true},
    ///   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
    /// let mut b = SpectralBatch::default();
    /// let ray = Ray::new(DVec3::new(0.0, 5.0, -10.0), DVec3::Z).unwrap();
    /// b.push(ray, 486.1327);
    /// b.push(ray, 656.2725);
    /// Tracer::forward(&p).trace_spectral(&mut b).unwrap();
    /// // blue bends more: it crosses the axis sooner, so it lands lower
    /// assert!(b.rays.y[0] < b.rays.y[1]);
    /// ```
    pub fn trace_spectral(&self, batch: &mut SpectralBatch) -> Result<(), OpticsError> {
        if batch.wavelength_nm.len() != batch.rays.len() {
            return Err(OpticsError::BadInput {
                name: "wavelength_nm",
                value: batch.wavelength_nm.len() as f64,
                expected: "one wavelength per ray",
            });
        }
        self.check_wavelengths(&batch.wavelength_nm)?;
        if self.glasses.is_empty() || self.steps.is_empty() {
            self.trace_soa(&mut batch.rays);
            return Ok(());
        }
        let t = self.spectral();
        #[cfg(target_arch = "x86_64")]
        if super::step::simd_fma() {
            let mut ix = t.chunk_buffers();
            // SAFETY: the CPU has AVX2 and FMA (checked by simd_fma).
            unsafe { t.trace_soa_avx2::<true>(&mut batch.rays, &batch.wavelength_nm, &mut ix) };
            return Ok(());
        }
        let nm = &batch.wavelength_nm;
        t.each_ray(&mut batch.rays, |i, l| t.walk_at(l, nm[i]));
        Ok(())
    }

    /// Traces one ray at `wavelength_nm`: what [`Self::trace_spectral`]
    /// does to it in a batch, bit for bit. Errors outside a glass's data.
    pub fn trace_at(&self, ray: Ray, wavelength_nm: f64) -> Result<Outcome, OpticsError> {
        self.check_wavelengths(&[wavelength_nm])?;
        let t = self.spectral();
        let (l, k, kind) = t.walk_at(Lane::of_ray(&ray), wavelength_nm);
        Ok(t.outcome(l, k, kind))
    }

    /// An error naming the first glass without data at one of the
    /// wavelengths (checked at the shortest and the longest; NaN fails).
    fn check_wavelengths(&self, nm: &[f64]) -> Result<(), OpticsError> {
        // branch-free, so that it vectorises: the check costs well under a
        // nanosecond a ray
        let (mut lo, mut hi, mut nan) = (f64::INFINITY, f64::NEG_INFINITY, false);
        for &w in nm {
            lo = if w < lo { w } else { lo };
            hi = if w > hi { w } else { hi };
            nan |= w.is_nan();
        }
        if nan {
            (lo, hi) = (f64::NAN, f64::NAN);
        }
        if nm.is_empty() {
            return Ok(());
        }
        if !(lo > 0.0 && hi.is_finite()) {
            let bad = nm.iter().copied().find(|w| !(w.is_finite() && *w > 0.0)).unwrap_or(lo);
            return Err(OpticsError::BadInput {
                name: "wavelength_nm",
                value: bad,
                expected: "a positive, finite wavelength in nm",
            });
        }
        for g in self.glasses.iter() {
            g.check_band(lo, hi, crate::glass::GlassRange::Extrapolate)?;
        }
        Ok(())
    }

    /// This tracer as a batch of mixed wavelengths runs it: a surface
    /// between two different glasses refracts, whatever their indices at
    /// the prescription's wavelength.
    fn spectral(&self) -> Tracer {
        let mut t = self.clone();
        for s in &mut t.steps {
            s.refract |= s.glass_before != s.glass_after;
        }
        t
    }

    /// Each glass's index at `nm` and its inverse, one ray.
    fn indices_at(&self, nm: f64) -> OneRay {
        let w = Lambda::<f64>::of_nm(nm);
        let n: Vec<f64> = self
            .kernels
            .iter()
            .zip(self.glasses.iter())
            .map(|(k, g)| if *k == Kernel::General { g.dispersion.index_general(nm) } else { k.eval(&w) })
            .collect();
        let inv = n.iter().map(|n| 1.0 / n).collect();
        OneRay { n, inv }
    }

    /// Carries one ray (global frame) at `nm` step by step until it stops,
    /// as `walk_lane` does at the prescription's wavelength.
    fn walk_at(&self, l: Lane<f64>, nm: f64) -> (Lane<f64>, usize, u64) {
        let ix = self.indices_at(nm);
        self.walk_lane_by(l, |s| lanes_at(StepLanes::of(s), s, &ix), |_, _, _| {})
    }

    /// Index buffers for one chunk, one per glass.
    #[cfg(target_arch = "x86_64")]
    fn chunk_buffers(&self) -> ChunkIndices {
        let v = [[0.0; 4]; VECTORS];
        let g = self.glasses.len();
        let from_air = (0..g)
            .map(|g| {
                self.steps.iter().any(|s| s.glass_after == g as u32 && s.glass_before == NO_GLASS && s.n_before == 1.0)
            })
            .collect();
        let inv_l2 = self.kernels.iter().any(|k| !matches!(k, Kernel::Sellmeier { .. } | Kernel::General));
        ChunkIndices { n: vec![v; g], inv: vec![v; g], from_air, inv_l2 }
    }

    /// Every glass's index (and inverse, where used) for the rays of one
    /// chunk of wavelengths `nm` (at most a chunk), `W::N` at a time; idle
    /// lanes past the end, up to the chunk's padding (a whole number of
    /// eight rays), take the first ray's wavelength.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn chunk_indices<W: Wide>(&self, nm: &[f64], ix: &mut ChunkIndices) {
        let mut w = [[nm[0]; 4]; VECTORS];
        w.as_flattened_mut()[..nm.len()].copy_from_slice(nm);
        let w = w.as_flattened();
        // as the chunk is padded (`Chunk::pad`): an eight-lane step reads
        // its idle lanes' indices too, which must be a glass's
        let vectors = nm.len().div_ceil(8) * 8 / W::N;
        let mut lambda = [Lambda { l2: W::splat(0.0), inv_l2: W::splat(0.0) }; VECTORS];
        for (j, l) in lambda[..vectors].iter_mut().enumerate() {
            *l = if ix.inv_l2 { Lambda::of_nm(W::at(w, j)) } else { Lambda::squared_only(W::at(w, j)) };
        }
        for (g, (k, glass)) in self.kernels.iter().zip(self.glasses.iter()).enumerate() {
            let out = ix.n[g].as_flattened_mut();
            if *k == Kernel::General {
                for (o, nm) in out[..vectors * W::N].iter_mut().zip(w) {
                    *o = glass.dispersion.index_general(*nm);
                }
            } else {
                for (j, lj) in lambda[..vectors].iter().enumerate() {
                    k.eval(lj).put(out, j);
                }
            }
            if ix.from_air[g] {
                let (n, inv) = (ix.n[g].as_flattened(), ix.inv[g].as_flattened_mut());
                for j in 0..vectors {
                    (W::splat(1.0) / W::at(n, j)).put(inv, j);
                }
            }
        }
    }

    /// [`Self::chunk_indices`] eight rays at a time.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX2, FMA, AVX-512F and AVX-512VL.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    pub(super) unsafe fn chunk_indices_wide(&self, nm: &[f64], ix: &mut ChunkIndices) {
        self.chunk_indices::<F64x8>(nm, ix)
    }
}
