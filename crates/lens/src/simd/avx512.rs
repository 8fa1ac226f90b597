//! Eight f64 lanes in one AVX-512 register, implementing [`Real`] with one
//! instruction per operation, as [`super::avx2`] does for four: the same
//! IEEE 754 operations (fused multiply-add rounded once, ordered
//! comparisons), so a lane's bits are those of the one-ray path. Masks are
//! the mask registers' bits, one per lane.
//!
//! Values of these types are made only inside functions compiled with
//! `#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]`, which the
//! batch tracer calls only after `trace::batch` found those extensions;
//! every intrinsic below relies on that.

use crate::simd::avx512_f32::F32x16;
use crate::simd::lanes::{Real, SIGN};
use std::arch::x86_64::*;

/// Eight f64 lanes.
#[derive(Clone, Copy)]
pub(crate) struct F64x8(__m512d);

/// Eight truth values, bit `j` for lane `j`.
#[derive(Clone, Copy)]
pub(crate) struct M64x8(__mmask8);

impl F64x8 {
    /// Loads eight values from `s[0..8]`.
    #[inline(always)]
    pub(crate) fn load(s: &[f64; 8]) -> Self {
        // SAFETY: AVX-512F is available (module invariant); the array has 8
        // lanes.
        F64x8(unsafe { _mm512_loadu_pd(s.as_ptr()) })
    }

    /// Stores the eight lanes into `s[0..8]`.
    #[inline(always)]
    pub(crate) fn store(self, s: &mut [f64; 8]) {
        // SAFETY: as in `load`.
        unsafe { _mm512_storeu_pd(s.as_mut_ptr(), self.0) }
    }

    /// The register itself (for the f32 lanes' conversions).
    #[inline(always)]
    pub(crate) fn raw(self) -> __m512d {
        self.0
    }

    /// Eight lanes from a register.
    #[inline(always)]
    pub(crate) fn from_raw(v: __m512d) -> Self {
        F64x8(v)
    }

    #[inline(always)]
    fn bits(self) -> __m512i {
        // SAFETY: AVX-512F is available (module invariant).
        unsafe { _mm512_castpd_si512(self.0) }
    }

    #[inline(always)]
    fn of_bits(b: __m512i) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_castsi512_pd(b) })
    }
}

impl M64x8 {
    /// One bit per lane (bit j set when lane j is true).
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        u32::from(self.0)
    }

    /// The mask whose lane j is bit j of `bits` ([`Self::bits`] back).
    #[inline(always)]
    pub(crate) fn of_bits(bits: u32) -> Self {
        M64x8(bits as __mmask8)
    }
}

lane_ops!(F64x8: Add add _mm512_add_pd, Sub sub _mm512_sub_pd, Mul mul _mm512_mul_pd, Div div _mm512_div_pd);
lane_neg!(F64x8);
mask_bits_ops!(M64x8, 0xff);

impl Real for F64x8 {
    type Mask = M64x8;
    type F32 = F32x16;

    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_set1_pd(v) })
    }
    #[inline(always)]
    fn fma(self, a: Self, b: Self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_fmadd_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn sign_bit(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_and_si512(self.bits(), _mm512_set1_epi64(SIGN as i64)) })
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
    fn is_finite(self) -> M64x8 {
        // x * 0 is +-0 for finite x, NaN for infinities and NaN (as in
        // avx2.rs)
        // SAFETY: AVX-512F is available (module invariant).
        unsafe {
            let zero = _mm512_setzero_pd();
            M64x8(_mm512_cmp_pd_mask::<_CMP_EQ_OQ>(_mm512_mul_pd(self.0, zero), zero))
        }
    }
    #[inline(always)]
    fn is_neg(self) -> M64x8 {
        // the sign bit: negative as a signed integer
        // SAFETY: AVX-512F is available (module invariant).
        M64x8(unsafe { _mm512_cmplt_epi64_mask(self.bits(), _mm512_setzero_si512()) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_andnot_si512(_mm512_set1_epi64(SIGN as i64), self.bits()) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> M64x8 {
        // SAFETY: AVX-512F is available (module invariant).
        M64x8(unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn select(m: M64x8, a: Self, b: Self) -> Self {
        // blend takes its second operand where the mask is set
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_mask_blend_pd(m.0, b.0, a.0) })
    }
    #[inline(always)]
    fn from_mask(m: M64x8) -> Self {
        // all ones (a negative NaN) where true, +0 elsewhere: is_neg reads
        // it back
        // SAFETY: AVX-512F is available (module invariant).
        Self::of_bits(unsafe { _mm512_maskz_mov_epi64(m.0, _mm512_set1_epi64(-1)) })
    }
}
