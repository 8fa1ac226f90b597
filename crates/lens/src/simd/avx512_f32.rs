//! Sixteen f32 lanes in one AVX-512 register, implementing [`Real`] with
//! one instruction per operation, as [`super::avx512`] does for eight f64
//! lanes: the numbers an asphere's start is computed in for two of the
//! eight-lane vectors at once (`trace/asphere.rs`), lane for lane those of
//! the one-ray path's `f32`. Masks are the mask registers' bits.
//!
//! Values of these types are made only inside functions compiled with
//! `#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]` (module
//! invariant, as in [`super::avx512`]).

use crate::simd::avx512::F64x8;
use crate::simd::lanes::{Real, RingRows, SIGN32};
use std::arch::x86_64::*;

/// Sixteen f32 lanes.
#[derive(Clone, Copy)]
pub(crate) struct F32x16(__m512);

/// Sixteen truth values, bit `j` for lane `j`.
#[derive(Clone, Copy)]
pub(crate) struct M32x16(__mmask16);

impl F32x16 {
    /// `lo`'s eight lanes then `hi`'s, each rounded to the nearest f32.
    #[inline(always)]
    pub(crate) fn narrow(lo: F64x8, hi: F64x8) -> Self {
        // SAFETY: AVX-512F is available (module invariant); the halves are
        // joined as four f64's worth of bits each (an f32x8 insert would
        // need AVX-512DQ).
        unsafe {
            let l = _mm256_castps_pd(_mm512_cvtpd_ps(lo.raw()));
            let h = _mm256_castps_pd(_mm512_cvtpd_ps(hi.raw()));
            F32x16(_mm512_castpd_ps(_mm512_insertf64x4::<1>(_mm512_castpd256_pd512(l), h)))
        }
    }

    /// The first eight lanes and the last eight, as f64 (exactly).
    #[inline(always)]
    pub(crate) fn widen(self) -> (F64x8, F64x8) {
        // SAFETY: AVX-512F is available (module invariant).
        unsafe {
            let lo = _mm512_cvtps_pd(_mm512_castps512_ps256(self.0));
            let hi = _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd::<1>(_mm512_castps_pd(self.0))));
            (F64x8::from_raw(lo), F64x8::from_raw(hi))
        }
    }

    /// The lanes held in the 64 bytes of `s[0..8]` (as [`Self::store_bits`]
    /// left them).
    #[inline(always)]
    pub(crate) fn load_bits(s: &[f64; 8]) -> Self {
        // SAFETY: AVX-512F is available (module invariant); the array has 64
        // bytes, read unaligned.
        F32x16(unsafe { _mm512_loadu_ps(s.as_ptr().cast::<f32>()) })
    }

    /// Stores the lanes into the 64 bytes of `s[0..8]`.
    #[inline(always)]
    pub(crate) fn store_bits(self, s: &mut [f64; 8]) {
        // SAFETY: as in `load_bits`.
        unsafe { _mm512_storeu_ps(s.as_mut_ptr().cast::<f32>(), self.0) }
    }

    #[inline(always)]
    fn bits(self) -> __m512i {
        // SAFETY: AVX-512F is available (module invariant).
        unsafe { _mm512_castps_si512(self.0) }
    }

    #[inline(always)]
    fn of_bits(b: __m512i) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F32x16(unsafe { _mm512_castsi512_ps(b) })
    }
}

lane_ops!(F32x16: Add add _mm512_add_ps, Sub sub _mm512_sub_ps, Mul mul _mm512_mul_ps, Div div _mm512_div_ps);
lane_neg!(F32x16);
mask_bits_ops!(M32x16, 0xffff);

impl Real for F32x16 {
    type Mask = M32x16;
    type F32 = F32x16;

    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F32x16(unsafe { _mm512_set1_ps(v as f32) })
    }
    #[inline(always)]
    fn fma(self, a: Self, b: Self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F32x16(unsafe { _mm512_fmadd_ps(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F32x16(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn sign_bit(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_and_si512(self.bits(), _mm512_set1_epi32(SIGN32 as i32)) })
    }
    #[inline(always)]
    fn xor(self, o: Self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_xor_si512(self.bits(), o.bits()) })
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_or_si512(self.bits(), o.bits()) })
    }
    #[inline(always)]
    fn is_finite(self) -> M32x16 {
        // x * 0 is +-0 for finite x, NaN for infinities and NaN
        // SAFETY: AVX-512F is available (module invariant).
        unsafe {
            let zero = _mm512_setzero_ps();
            M32x16(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(_mm512_mul_ps(self.0, zero), zero))
        }
    }
    #[inline(always)]
    fn is_neg(self) -> M32x16 {
        // the sign bit: negative as a signed integer
        // SAFETY: AVX-512F is available (module invariant).
        M32x16(unsafe { _mm512_cmplt_epi32_mask(self.bits(), _mm512_setzero_si512()) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_andnot_si512(_mm512_set1_epi32(SIGN32 as i32), self.bits()) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> M32x16 {
        // SAFETY: AVX-512F is available (module invariant).
        M32x16(unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn select(m: M32x16, a: Self, b: Self) -> Self {
        // blend takes its second operand where the mask is set
        // SAFETY: AVX-512F is available (module invariant).
        F32x16(unsafe { _mm512_mask_blend_ps(m.0, b.0, a.0) })
    }
    #[inline(always)]
    fn from_mask(m: M32x16) -> Self {
        // all ones (a negative NaN) where true, +0 elsewhere
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_maskz_mov_epi32(m.0, _mm512_set1_epi32(-1)) })
    }
}

impl RingRows for F32x16 {
    #[inline(always)]
    fn rows32(cols: [&[f32; 32]; 3], at: Self) -> [Self; 3] {
        // SAFETY: AVX-512F is available (module invariant); the index is
        // clamped to 0..=31 as the one-ray path's (max_ps gives 0 for a
        // NaN), and a two-register permute reads its five low bits: one
        // instruction a column.
        unsafe {
            let i = index(at, 31.0);
            [pick(cols[0], i), pick(cols[1], i), pick(cols[2], i)]
        }
    }
    #[inline(always)]
    fn rows128(cols: [&[f32; 128]; 3], at: Self) -> [Self; 3] {
        // SAFETY: as in rows32, the index clamped to 0..=127: four
        // permutes of 32 entries a column, blended by its sixth and seventh
        // bits.
        unsafe {
            let i = index(at, 127.0);
            let b5 = _mm512_test_epi32_mask(i, _mm512_set1_epi32(32));
            let b6 = _mm512_test_epi32_mask(i, _mm512_set1_epi32(64));
            [pick128(cols[0], i, b5, b6), pick128(cols[1], i, b5, b6), pick128(cols[2], i, b5, b6)]
        }
    }
}

/// `at` clamped to `0..=last` (NaN to 0, as `max_ps` gives its second
/// operand) and truncated.
///
/// # Safety
///
/// AVX-512F must be available (module invariant).
#[inline(always)]
unsafe fn index(at: F32x16, last: f32) -> __m512i {
    // SAFETY: the caller's.
    unsafe { _mm512_cvttps_epi32(_mm512_min_ps(_mm512_max_ps(at.0, _mm512_setzero_ps()), _mm512_set1_ps(last))) }
}

/// Entry `i` (its five low bits) of `col` in each lane. A function, not a
/// closure (one not inlined runs outside the caller's target features).
///
/// # Safety
///
/// AVX-512F must be available (module invariant).
#[inline(always)]
unsafe fn pick(col: &[f32; 32], i: __m512i) -> F32x16 {
    // SAFETY: AVX-512F is available (the caller's); each load reads 16 of
    // the column's 32 numbers.
    unsafe {
        let p = col.as_ptr();
        F32x16(_mm512_permutex2var_ps(_mm512_loadu_ps(p), i, _mm512_loadu_ps(p.add(16))))
    }
}

/// Entry `i` (its seven low bits; the sixth and seventh also in `b5`,
/// `b6`) of `col` in each lane.
///
/// # Safety
///
/// AVX-512F must be available (module invariant).
#[inline(always)]
unsafe fn pick128(col: &[f32; 128], i: __m512i, b5: __mmask16, b6: __mmask16) -> F32x16 {
    // SAFETY: AVX-512F is available (the caller's); each load reads 16 of
    // the column's 128 numbers.
    unsafe {
        let p = col.as_ptr();
        let a = _mm512_permutex2var_ps(_mm512_loadu_ps(p), i, _mm512_loadu_ps(p.add(16)));
        let b = _mm512_permutex2var_ps(_mm512_loadu_ps(p.add(32)), i, _mm512_loadu_ps(p.add(48)));
        let c = _mm512_permutex2var_ps(_mm512_loadu_ps(p.add(64)), i, _mm512_loadu_ps(p.add(80)));
        let d = _mm512_permutex2var_ps(_mm512_loadu_ps(p.add(96)), i, _mm512_loadu_ps(p.add(112)));
        F32x16(_mm512_mask_blend_ps(b6, _mm512_mask_blend_ps(b5, a, b), _mm512_mask_blend_ps(b5, c, d)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::lanes::ring_rows_check::{check, first32, table};

    /// The sixteen lanes' rows of a table of 32 are the one-ray path's for
    /// every index: inside, at and past both ends, fractional, infinite and
    /// NaN; narrowing and widening round as `as f32` and convert exactly as
    /// `as f64`.
    #[test]
    fn rows_by_permutes_are_the_one_ray_rows() {
        if !(std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl")) {
            return;
        }
        let cols = table();
        // SAFETY: the CPU has the module's target features (checked above).
        check::<16>(|lanes| unsafe { rows_of(&cols, lanes) });
        let wide: [f64; 16] = std::array::from_fn(|j| {
            [1.0 + f64::EPSILON, -1e-40, 3.4e39, f64::NAN, 0.1, -2.5, 1e-3][j % 7] * (j + 1) as f64
        });
        // SAFETY: as above.
        let (lo, hi) = unsafe { round_trip(&wide) };
        for (j, w) in wide.iter().enumerate() {
            let got = if j < 8 { lo[j] } else { hi[j - 8] };
            assert_eq!(got.to_bits(), f64::from(*w as f32).to_bits(), "lane {j}: {w}");
        }
    }

    /// [`F32x16::rows32`] (of the first 32 rows) and [`F32x16::rows128`] at
    /// `at`, stored.
    ///
    /// # Safety
    ///
    /// The CPU must have the module's target features.
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    unsafe fn rows_of(cols: &[[f32; 128]; 3], at: &[f32; 16]) -> ([[f32; 16]; 3], [[f32; 16]; 3]) {
        // SAFETY: the module's target features are this function's.
        let v = F32x16(unsafe { _mm512_loadu_ps(at.as_ptr()) });
        let mut out = ([[0.0; 16]; 3], [[0.0; 16]; 3]);
        let got = (F32x16::rows32(first32(cols), v), F32x16::rows128(cols.each_ref(), v));
        for k in 0..3 {
            // SAFETY: as above; each output has 16 lanes.
            unsafe {
                _mm512_storeu_ps(out.0[k].as_mut_ptr(), got.0[k].0);
                _mm512_storeu_ps(out.1[k].as_mut_ptr(), got.1[k].0);
            }
        }
        out
    }

    /// `wide` narrowed to sixteen f32 lanes and widened back.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX2, AVX-512F and AVX-512VL.
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    unsafe fn round_trip(wide: &[f64; 16]) -> ([f64; 8], [f64; 8]) {
        let lo = F64x8::load(&std::array::from_fn(|j| wide[j]));
        let hi = F64x8::load(&std::array::from_fn(|j| wide[8 + j]));
        let (a, b) = F32x16::narrow(lo, hi).widen();
        let mut out = ([0.0; 8], [0.0; 8]);
        a.store(&mut out.0);
        b.store(&mut out.1);
        out
    }
}
