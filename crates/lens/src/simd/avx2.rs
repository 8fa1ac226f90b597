//! Four f64 lanes in one AVX2 register, implementing [`Real`] with one
//! instruction per operation (fused multiply-add from the FMA extension).
//!
//! Values of these types are made only inside functions compiled with
//! `#[target_feature(enable = "avx2,fma")]`, which the batch tracer calls
//! only after `trace::step::simd_fma` found both extensions; every
//! intrinsic below relies on that.

use crate::simd::avx2_f32::F32x8;
use crate::simd::lanes::{Mask, Real, SIGN};
use std::arch::x86_64::*;
use std::ops::Not;

/// Four f64 lanes.
#[derive(Clone, Copy)]
pub(crate) struct F64x4(__m256d);

/// Four truth values, one per lane, held in the lane's sign bit: a
/// comparison sets all bits of a lane (true) or none, [`Real::is_neg`] is
/// the number itself. Masks are only combined bitwise and read by
/// `movemask`, which reads the sign bits alone.
#[derive(Clone, Copy)]
pub(crate) struct M64x4(__m256d);

impl F64x4 {
    /// The four values `[a, b, c, d]`, gathered in registers.
    #[inline(always)]
    pub(crate) fn new(a: f64, b: f64, c: f64, d: f64) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_setr_pd(a, b, c, d) })
    }

    /// Loads four values from `s[0..4]`.
    #[inline(always)]
    pub(crate) fn load(s: &[f64; 4]) -> Self {
        // SAFETY: AVX is available (module invariant); the array has 4 lanes.
        F64x4(unsafe { _mm256_loadu_pd(s.as_ptr()) })
    }

    /// The register itself (for the eight-lane type's halves).
    #[inline(always)]
    pub(crate) fn raw(self) -> __m256d {
        self.0
    }

    /// Four lanes from a register.
    #[inline(always)]
    pub(crate) fn from_raw(v: __m256d) -> Self {
        F64x4(v)
    }

    /// Stores the four lanes into `s[0..4]`.
    #[inline(always)]
    pub(crate) fn store(self, s: &mut [f64; 4]) {
        // SAFETY: as in `load`.
        unsafe { _mm256_storeu_pd(s.as_mut_ptr(), self.0) }
    }
}

/// Four rows of six numbers each (`rows[0..24]`, row `i` at `6 i`) as six
/// vectors, one per column: lane `i` of vector `k` is `rows[6 i + k]`.
#[inline(always)]
pub(crate) fn rows_to_columns(rows: &[f64; 24]) -> [F64x4; 6] {
    let p = rows.as_ptr();
    // SAFETY: AVX is available (module invariant); every load reads inside
    // the 24 numbers (the last, 2 at 22).
    unsafe {
        let (a, b) = (_mm256_loadu_pd(p), _mm256_loadu_pd(p.add(6)));
        let (c, d) = (_mm256_loadu_pd(p.add(12)), _mm256_loadu_pd(p.add(18)));
        let (t0, t1) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
        let (t2, t3) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
        let e = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p.add(4))), _mm_loadu_pd(p.add(16)));
        let f = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p.add(10))), _mm_loadu_pd(p.add(22)));
        [
            F64x4(_mm256_permute2f128_pd::<0x20>(t0, t2)),
            F64x4(_mm256_permute2f128_pd::<0x20>(t1, t3)),
            F64x4(_mm256_permute2f128_pd::<0x31>(t0, t2)),
            F64x4(_mm256_permute2f128_pd::<0x31>(t1, t3)),
            F64x4(_mm256_unpacklo_pd(e, f)),
            F64x4(_mm256_unpackhi_pd(e, f)),
        ]
    }
}

/// The inverse of [`rows_to_columns`]: six column vectors stored as four
/// rows of six numbers into `rows[0..24]`.
#[inline(always)]
pub(crate) fn columns_to_rows(c: [F64x4; 6], rows: &mut [f64; 24]) {
    let p = rows.as_mut_ptr();
    // SAFETY: AVX is available (module invariant); every store writes
    // inside the 24 numbers.
    unsafe {
        let (t0, t1) = (_mm256_unpacklo_pd(c[0].0, c[1].0), _mm256_unpackhi_pd(c[0].0, c[1].0));
        let (t2, t3) = (_mm256_unpacklo_pd(c[2].0, c[3].0), _mm256_unpackhi_pd(c[2].0, c[3].0));
        let (e, f) = (_mm256_unpacklo_pd(c[4].0, c[5].0), _mm256_unpackhi_pd(c[4].0, c[5].0));
        _mm256_storeu_pd(p, _mm256_permute2f128_pd::<0x20>(t0, t2));
        _mm_storeu_pd(p.add(4), _mm256_castpd256_pd128(e));
        _mm256_storeu_pd(p.add(6), _mm256_permute2f128_pd::<0x20>(t1, t3));
        _mm_storeu_pd(p.add(10), _mm256_castpd256_pd128(f));
        _mm256_storeu_pd(p.add(12), _mm256_permute2f128_pd::<0x31>(t0, t2));
        _mm_storeu_pd(p.add(16), _mm256_extractf128_pd::<1>(e));
        _mm256_storeu_pd(p.add(18), _mm256_permute2f128_pd::<0x31>(t1, t3));
        _mm_storeu_pd(p.add(22), _mm256_extractf128_pd::<1>(f));
    }
}

impl M64x4 {
    /// One bit per lane (bit j set when lane j is true).
    #[inline(always)]
    pub(crate) fn bits(self) -> u32 {
        // SAFETY: AVX is available (module invariant).
        unsafe { _mm256_movemask_pd(self.0) as u32 }
    }
}

lane_ops!(F64x4: Add add _mm256_add_pd, Sub sub _mm256_sub_pd, Mul mul _mm256_mul_pd, Div div _mm256_div_pd);
lane_ops!(M64x4: BitAnd bitand _mm256_and_pd, BitOr bitor _mm256_or_pd, BitXor bitxor _mm256_xor_pd);
lane_neg!(F64x4);

impl Not for M64x4 {
    type Output = M64x4;
    #[inline(always)]
    fn not(self) -> M64x4 {
        M64x4::all_true() ^ self
    }
}

impl Mask for M64x4 {
    #[inline(always)]
    fn all_true() -> Self {
        // SAFETY: AVX is available (module invariant).
        M64x4(unsafe { _mm256_castsi256_pd(_mm256_set1_epi64x(-1)) })
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.bits() != 0
    }
}

impl Real for F64x4 {
    type Mask = M64x4;
    type F32 = F32x8;

    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_set1_pd(v) })
    }
    #[inline(always)]
    fn fma(self, a: Self, b: Self) -> Self {
        // SAFETY: FMA is available (module invariant).
        F64x4(unsafe { _mm256_fmadd_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn sign_bit(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_and_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi64x(SIGN as i64))) })
    }
    #[inline(always)]
    fn xor(self, o: Self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_xor_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn or(self, o: Self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_or_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn is_neg(self) -> M64x4 {
        M64x4(self.0)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> M64x4 {
        // SAFETY: AVX is available (module invariant).
        M64x4(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn select(m: M64x4, a: Self, b: Self) -> Self {
        // blendv reads the sign bit of each lane of the mask, which every
        // mask here sets (module docs)
        // SAFETY: AVX is available (module invariant).
        F64x4(unsafe { _mm256_blendv_pd(b.0, a.0, m.0) })
    }
    #[inline(always)]
    fn from_mask(m: M64x4) -> Self {
        F64x4(m.0)
    }
    #[inline(always)]
    fn is_finite(self) -> M64x4 {
        // x * 0 is +-0 for finite x, NaN for infinities and NaN: no
        // constant to hold but zero
        // SAFETY: AVX is available (module invariant).
        unsafe {
            let zero = _mm256_setzero_pd();
            M64x4(_mm256_cmp_pd::<_CMP_EQ_OQ>(_mm256_mul_pd(self.0, zero), zero))
        }
    }
}
