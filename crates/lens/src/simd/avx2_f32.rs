//! Eight f32 lanes in one AVX2 register, implementing [`Real`] with one
//! instruction per operation, as [`super::avx2`] does for four f64 lanes:
//! the numbers an asphere's start is computed in for two of the four-lane
//! vectors at once (`trace/asphere.rs`), lane for lane those of the one-ray
//! path's `f32`.
//!
//! Values of these types are made only inside functions compiled with
//! `#[target_feature(enable = "avx2,fma")]` (module invariant, as in
//! [`super::avx2`]).

use crate::simd::avx2::F64x4;
use crate::simd::lanes::{Mask, Real, RingRows, SIGN32};
use std::arch::x86_64::*;
use std::ops::Not;

/// Eight f32 lanes.
#[derive(Clone, Copy)]
pub(crate) struct F32x8(__m256);

/// Eight truth values in the lanes' sign bits, as [`super::avx2::M64x4`]
/// holds four.
#[derive(Clone, Copy)]
pub(crate) struct M32x8(__m256);

impl F32x8 {
    /// `lo`'s four lanes then `hi`'s, each rounded to the nearest f32.
    #[inline(always)]
    pub(crate) fn narrow(lo: F64x4, hi: F64x4) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe {
            _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(_mm256_cvtpd_ps(lo.raw())), _mm256_cvtpd_ps(hi.raw()))
        })
    }

    /// The first four lanes and the last four, as f64 (exactly).
    #[inline(always)]
    pub(crate) fn widen(self) -> (F64x4, F64x4) {
        // SAFETY: AVX is available (module invariant).
        unsafe {
            let lo = _mm256_cvtps_pd(_mm256_castps256_ps128(self.0));
            let hi = _mm256_cvtps_pd(_mm256_extractf128_ps::<1>(self.0));
            (F64x4::from_raw(lo), F64x4::from_raw(hi))
        }
    }

    /// The lanes held in the 32 bytes of `s[0..4]` (as [`Self::store_bits`] left
    /// them).
    #[inline(always)]
    pub(crate) fn load_bits(s: &[f64; 4]) -> Self {
        // SAFETY: AVX is available (module invariant); the array has 32
        // bytes, read unaligned.
        F32x8(unsafe { _mm256_loadu_ps(s.as_ptr().cast::<f32>()) })
    }

    /// Stores the lanes into the 32 bytes of `s[0..4]`.
    #[inline(always)]
    pub(crate) fn store_bits(self, s: &mut [f64; 4]) {
        // SAFETY: as in `load_bits`.
        unsafe { _mm256_storeu_ps(s.as_mut_ptr().cast::<f32>(), self.0) }
    }

    #[inline(always)]
    fn sign_mask() -> __m256 {
        // SAFETY: AVX is available (module invariant).
        unsafe { _mm256_castsi256_ps(_mm256_set1_epi32(SIGN32 as i32)) }
    }
}

lane_ops!(F32x8: Add add _mm256_add_ps, Sub sub _mm256_sub_ps, Mul mul _mm256_mul_ps, Div div _mm256_div_ps);
lane_ops!(M32x8: BitAnd bitand _mm256_and_ps, BitOr bitor _mm256_or_ps, BitXor bitxor _mm256_xor_ps);
lane_neg!(F32x8);

impl Not for M32x8 {
    type Output = M32x8;
    #[inline(always)]
    fn not(self) -> M32x8 {
        M32x8::all_true() ^ self
    }
}

impl Mask for M32x8 {
    #[inline(always)]
    fn all_true() -> Self {
        // SAFETY: AVX is available (module invariant).
        M32x8(unsafe { _mm256_castsi256_ps(_mm256_set1_epi32(-1)) })
    }
    #[inline(always)]
    fn any(self) -> bool {
        // SAFETY: AVX is available (module invariant).
        unsafe { _mm256_movemask_ps(self.0) != 0 }
    }
}

impl Real for F32x8 {
    type Mask = M32x8;
    type F32 = F32x8;

    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_set1_ps(v as f32) })
    }
    #[inline(always)]
    fn fma(self, a: Self, b: Self) -> Self {
        // SAFETY: FMA is available (module invariant).
        F32x8(unsafe { _mm256_fmadd_ps(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn sign_bit(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_and_ps(self.0, Self::sign_mask()) })
    }
    #[inline(always)]
    fn xor(self, o: Self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_xor_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_or_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn is_finite(self) -> M32x8 {
        // x * 0 is +-0 for finite x, NaN for infinities and NaN
        // SAFETY: AVX is available (module invariant).
        unsafe {
            let zero = _mm256_setzero_ps();
            M32x8(_mm256_cmp_ps::<_CMP_EQ_OQ>(_mm256_mul_ps(self.0, zero), zero))
        }
    }
    #[inline(always)]
    fn is_neg(self) -> M32x8 {
        M32x8(self.0)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_andnot_ps(Self::sign_mask(), self.0) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> M32x8 {
        // SAFETY: AVX is available (module invariant).
        M32x8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn select(m: M32x8, a: Self, b: Self) -> Self {
        // blendv reads each lane's sign bit, which every mask sets
        // SAFETY: AVX is available (module invariant).
        F32x8(unsafe { _mm256_blendv_ps(b.0, a.0, m.0) })
    }
    #[inline(always)]
    fn from_mask(m: M32x8) -> Self {
        F32x8(m.0)
    }
}

impl RingRows for F32x8 {
    #[inline(always)]
    fn rows32(cols: [&[f32; 32]; 3], at: Self) -> [Self; 3] {
        // SAFETY: AVX2 is available (module invariant); the index is
        // clamped to 0..=31 as the one-ray path's (max_ps gives 0 for a
        // NaN); a permute reads its three low bits, the blends the fourth
        // and fifth (shifted into the sign).
        unsafe {
            let clamped = _mm256_min_ps(_mm256_max_ps(at.0, _mm256_setzero_ps()), _mm256_set1_ps(31.0));
            let i = _mm256_cvttps_epi32(clamped);
            let bit3 = _mm256_castsi256_ps(_mm256_slli_epi32::<28>(i));
            let bit4 = _mm256_castsi256_ps(_mm256_slli_epi32::<27>(i));
            [pick(cols[0], i, bit3, bit4), pick(cols[1], i, bit3, bit4), pick(cols[2], i, bit3, bit4)]
        }
    }
    #[inline(always)]
    fn rows128(cols: [&[f32; 128]; 3], at: Self) -> [Self; 3] {
        // SAFETY: AVX2 is available (module invariant); the index is
        // clamped to 0..=127 as the one-ray path's, so each gather reads
        // inside its column (gathers measured faster here than a load per
        // lane, and sixteen permutes a column would be more)
        unsafe {
            let clamped = _mm256_min_ps(_mm256_max_ps(at.0, _mm256_setzero_ps()), _mm256_set1_ps(127.0));
            let i = _mm256_cvttps_epi32(clamped);
            [
                F32x8(_mm256_i32gather_ps::<4>(cols[0].as_ptr(), i)),
                F32x8(_mm256_i32gather_ps::<4>(cols[1].as_ptr(), i)),
                F32x8(_mm256_i32gather_ps::<4>(cols[2].as_ptr(), i)),
            ]
        }
    }
}

/// Entry `i` (its five low bits; the fourth and fifth also in the sign
/// bits of `bit3` and `bit4`) of `col` in each lane: four permutes of
/// eight entries each and three blends. A function, not a closure (one not
/// inlined runs outside the caller's target features).
///
/// # Safety
///
/// AVX2 must be available (module invariant).
#[inline(always)]
unsafe fn pick(col: &[f32; 32], i: __m256i, bit3: __m256, bit4: __m256) -> F32x8 {
    // SAFETY: AVX2 is available (the caller's); each load reads 8 of the
    // column's 32 numbers.
    unsafe {
        let p = col.as_ptr();
        let p0 = _mm256_permutevar8x32_ps(_mm256_loadu_ps(p), i);
        let p1 = _mm256_permutevar8x32_ps(_mm256_loadu_ps(p.add(8)), i);
        let p2 = _mm256_permutevar8x32_ps(_mm256_loadu_ps(p.add(16)), i);
        let p3 = _mm256_permutevar8x32_ps(_mm256_loadu_ps(p.add(24)), i);
        let lo = _mm256_blendv_ps(p0, p1, bit3);
        let hi = _mm256_blendv_ps(p2, p3, bit3);
        F32x8(_mm256_blendv_ps(lo, hi, bit4))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::lanes::ring_rows_check::{check, first32, table};

    /// The eight lanes' rows of a table of 32 are the one-ray path's for
    /// every index: inside, at and past both ends, fractional, infinite and
    /// NaN (clamped to the table, NaN to row 0); narrowing and widening
    /// round as `as f32` and convert exactly as `as f64`.
    #[test]
    fn rows_by_permutes_are_the_one_ray_rows() {
        if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")) {
            return;
        }
        let cols = table();
        // SAFETY: the CPU has the module's target features (checked above).
        check::<8>(|lanes| unsafe { rows_of(&cols, lanes) });
        let wide = [1.0 + f64::EPSILON, -1e-40, 3.4e39, f64::NAN, 0.1, -2.5, 1e-3, 7.0];
        // SAFETY: as above.
        let (lo, hi) = unsafe { round_trip(&wide) };
        for (j, w) in wide.iter().enumerate() {
            let got = if j < 4 { lo[j] } else { hi[j - 4] };
            assert_eq!(got.to_bits(), f64::from(*w as f32).to_bits(), "lane {j}: {w}");
        }
    }

    /// [`F32x8::rows32`] (of the first 32 rows) and [`F32x8::rows128`] at
    /// `at`, stored.
    ///
    /// # Safety
    ///
    /// The CPU must have the module's target features.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn rows_of(cols: &[[f32; 128]; 3], at: &[f32; 8]) -> ([[f32; 8]; 3], [[f32; 8]; 3]) {
        // SAFETY: the module's target features are this function's.
        let v = F32x8(unsafe { _mm256_loadu_ps(at.as_ptr()) });
        let mut out = ([[0.0; 8]; 3], [[0.0; 8]; 3]);
        let got = (F32x8::rows32(first32(cols), v), F32x8::rows128(cols.each_ref(), v));
        for k in 0..3 {
            // SAFETY: as above; each output has 8 lanes.
            unsafe {
                _mm256_storeu_ps(out.0[k].as_mut_ptr(), got.0[k].0);
                _mm256_storeu_ps(out.1[k].as_mut_ptr(), got.1[k].0);
            }
        }
        out
    }

    /// `wide` narrowed to eight f32 lanes and widened back.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn round_trip(wide: &[f64; 8]) -> ([f64; 4], [f64; 4]) {
        let lo = F64x4::load(&[wide[0], wide[1], wide[2], wide[3]]);
        let hi = F64x4::load(&[wide[4], wide[5], wide[6], wide[7]]);
        let (a, b) = F32x8::narrow(lo, hi).widen();
        let mut out = ([0.0; 4], [0.0; 4]);
        a.store(&mut out.0);
        b.store(&mut out.1);
        out
    }
}
