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

use crate::simd::avx2::F64x4;
use crate::simd::lanes::{Mask, Real, SIGN};
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

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

    /// The low and high four lanes.
    #[inline(always)]
    fn halves(self) -> (F64x4, F64x4) {
        // SAFETY: AVX-512F is available (module invariant).
        unsafe {
            let lo = _mm512_castpd512_pd256(self.0);
            let hi = _mm512_extractf64x4_pd::<1>(self.0);
            (F64x4::from_raw(lo), F64x4::from_raw(hi))
        }
    }

    /// `lo` in lanes 0-3, `hi` in lanes 4-7.
    #[inline(always)]
    fn join(lo: F64x4, hi: F64x4) -> Self {
        // SAFETY: AVX-512F is available (module invariant).
        F64x8(unsafe { _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo.raw()), hi.raw()) })
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

macro_rules! binary {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for F64x8 {
            type Output = F64x8;
            #[inline(always)]
            fn $method(self, o: F64x8) -> F64x8 {
                // SAFETY: AVX-512F is available (module invariant).
                F64x8(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}

binary!(Add, add, _mm512_add_pd);
binary!(Sub, sub, _mm512_sub_pd);
binary!(Mul, mul, _mm512_mul_pd);
binary!(Div, div, _mm512_div_pd);

impl Neg for F64x8 {
    type Output = F64x8;
    #[inline(always)]
    fn neg(self) -> F64x8 {
        self.xor(F64x8::splat(-0.0))
    }
}

impl BitAnd for M64x8 {
    type Output = M64x8;
    #[inline(always)]
    fn bitand(self, o: M64x8) -> M64x8 {
        M64x8(self.0 & o.0)
    }
}

impl BitOr for M64x8 {
    type Output = M64x8;
    #[inline(always)]
    fn bitor(self, o: M64x8) -> M64x8 {
        M64x8(self.0 | o.0)
    }
}

impl Not for M64x8 {
    type Output = M64x8;
    #[inline(always)]
    fn not(self) -> M64x8 {
        M64x8(!self.0)
    }
}

impl Mask for M64x8 {
    #[inline(always)]
    fn all_true() -> Self {
        M64x8(0xff)
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0 != 0
    }
}

impl Real for F64x8 {
    type Mask = M64x8;

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
    #[inline(always)]
    fn rows(table: &[[f64; 4]], at: Self) -> [Self; 4] {
        // each half as four lanes do it; written out, no closure (one not
        // inlined runs without this module's target features)
        let (lo, hi) = at.halves();
        let ([l0, l1, l2, l3], [h0, h1, h2, h3]) = (F64x4::rows(table, lo), F64x4::rows(table, hi));
        [F64x8::join(l0, h0), F64x8::join(l1, h1), F64x8::join(l2, h2), F64x8::join(l3, h3)]
    }
    #[inline(always)]
    fn rows32(_: &[[f64; 4]; 32], cols: &[[f64; 32]; 3], at: Self) -> [Self; 3] {
        // SAFETY: AVX-512F is available (module invariant); the index is
        // clamped to 0..=31 as in `rows` (max_pd gives 0 for a NaN), and a
        // permute reads only its four low bits, the blend the fifth.
        unsafe {
            let clamped = _mm512_min_pd(_mm512_max_pd(at.0, _mm512_setzero_pd()), _mm512_set1_pd(31.0));
            let i = _mm512_cvtepu32_epi64(_mm512_cvttpd_epi32(clamped));
            let high = _mm512_test_epi64_mask(i, _mm512_set1_epi64(16));
            [pick(&cols[0], i, high), pick(&cols[1], i, high), pick(&cols[2], i, high)]
        }
    }
}

/// Entry `i` (its five low bits, the fifth also in `high`) of `col` in each
/// lane: two permutes over two registers each, and a blend. A function, not
/// a closure (one not inlined runs outside the caller's target features).
///
/// # Safety
///
/// AVX-512F must be available (module invariant).
#[inline(always)]
unsafe fn pick(col: &[f64; 32], i: __m512i, high: __mmask8) -> F64x8 {
    // SAFETY: AVX-512F is available (the caller's); each load reads 8 of
    // the column's 32 numbers.
    unsafe {
        let p = col.as_ptr();
        let lo = _mm512_permutex2var_pd(_mm512_loadu_pd(p), i, _mm512_loadu_pd(p.add(8)));
        let hi = _mm512_permutex2var_pd(_mm512_loadu_pd(p.add(16)), i, _mm512_loadu_pd(p.add(24)));
        F64x8(_mm512_mask_blend_pd(high, lo, hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eight lanes' rows of a table, by rows and by columns, are the
    /// one-ray path's for every index: inside, at and past both ends,
    /// fractional, infinite and NaN (clamped to the table, NaN to row 0).
    #[test]
    fn rows_by_permutes_are_the_one_ray_rows() {
        if !(std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl")) {
            return;
        }
        let rows: [[f64; 4]; 32] = std::array::from_fn(|i| [i as f64 + 0.25, -(i as f64) * 3.0, 1e-3 * i as f64, 0.0]);
        let cols: [[f64; 32]; 3] = std::array::from_fn(|k| std::array::from_fn(|i| rows[i][k]));
        let at = [-5.0, 0.0, 0.99, 7.5, 15.999, 16.0, 31.0, 31.7, 40.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
        for start in 0..at.len() {
            let lanes: [f64; 8] = std::array::from_fn(|j| at[(start + j) % at.len()]);
            // SAFETY: the CPU has AVX-512F and VL (checked above).
            let (by_rows, by_cols) = unsafe { both(&rows, &cols, &lanes) };
            for (j, a) in lanes.iter().enumerate() {
                let want = f64::rows(&rows, *a);
                for k in 0..3 {
                    assert_eq!(by_rows[k][j].to_bits(), want[k].to_bits(), "rows, lane {j} at {a}");
                    assert_eq!(by_cols[k][j].to_bits(), want[k].to_bits(), "cols, lane {j} at {a}");
                }
            }
        }
    }

    /// [`F64x8::rows`] and [`F64x8::rows32`] at `at`, stored.
    ///
    /// # Safety
    ///
    /// The CPU must have AVX2, AVX-512F and AVX-512VL.
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
    unsafe fn both(rows: &[[f64; 4]; 32], cols: &[[f64; 32]; 3], at: &[f64; 8]) -> ([[f64; 8]; 3], [[f64; 8]; 3]) {
        let v = F64x8::load(at);
        let [r0, r1, r2, _] = F64x8::rows(rows, v);
        let [c0, c1, c2] = F64x8::rows32(rows, cols, v);
        let mut out = ([[0.0; 8]; 3], [[0.0; 8]; 3]);
        r0.store(&mut out.0[0]);
        r1.store(&mut out.0[1]);
        r2.store(&mut out.0[2]);
        c0.store(&mut out.1[0]);
        c1.store(&mut out.1[1]);
        c2.store(&mut out.1[2]);
        out
    }
}
