//! The number type the tracing kernel is written over.
//!
//! The intersection, refraction and step kernels are written once, generic
//! over [`Real`]: `f64` traces one ray (the one-ray path), and
//! `crate::simd::avx2::F64x4` four rays at a time in AVX2 registers (the batch
//! path). Every operation of the trait is one IEEE 754 operation with the
//! same rounding in both (a `mul_add` is one fused multiply-add, rounded
//! once; comparisons are ordered, false on NaN), so both paths give the same
//! bits for every ray.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// Bit pattern of the sign of an f64.
pub(crate) const SIGN: u64 = 1 << 63;

/// Bit pattern of the sign of an f32.
pub(crate) const SIGN32: u32 = 1 << 31;

/// Numbers for one ray (`f64`) or for several rays at once (one per lane).
pub(crate) trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// One truth value per lane.
    type Mask: Mask;
    /// `v` in every lane.
    fn splat(v: f64) -> Self;
    /// `self * a + b`, rounded once.
    fn fma(self, a: Self, b: Self) -> Self;
    /// Correctly rounded square root.
    fn sqrt(self) -> Self;
    /// The sign bit of `self` alone: `+0` or `-0`.
    fn sign_bit(self) -> Self;
    /// Bitwise exclusive or: `x.xor(s.sign_bit())` flips the sign of `x`
    /// where `s` is negative.
    fn xor(self, o: Self) -> Self;
    /// Bitwise or: `m.or(s.sign_bit())` is `copysign(m, s)` for `m >= +0`.
    fn or(self, o: Self) -> Self;
    /// `|self| < infinity`: false on infinities and NaN.
    fn is_finite(self) -> Self::Mask;
    /// The sign bit: true where `self` is negative or `-0` (or a NaN with
    /// its sign bit set). No operation for a vector, whose masks are read by
    /// their sign bits; `!x.is_neg()` is `x >= 0` but for `-0` and NaN.
    fn is_neg(self) -> Self::Mask;
    /// `|self|`.
    fn abs(self) -> Self;
    /// `self <= o`, ordered: false where either is NaN.
    fn le(self, o: Self) -> Self::Mask;
    /// `a` where `m` is true, `b` elsewhere.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// A mask held as a number, negative where true (so that
    /// [`Self::is_neg`] reads it back): for a vector the mask's own bits.
    fn from_mask(m: Self::Mask) -> Self;
    /// The f32 lanes an asphere's start is computed in (`trace/asphere.rs`):
    /// `f32` for one ray, and for a vector of f64 lanes the f32 vector of
    /// the same width in bytes, which holds two of its vectors' lanes (the
    /// batch narrows two vectors into one); `Self` for the f32 types.
    type F32: Real + RingRows;
}

/// The f32 lanes that read a ring's conic from a table of 32 or 128 rows
/// (`trace/zones.rs`).
pub(crate) trait RingRows: Real {
    /// Row `i` of a table of three columns of 32 numbers in each lane
    /// (`cols[k][i]` for each k), `i` the lane's `at` clamped to `0..=31`
    /// (NaN to 0) and truncated: by columns, which the vector types read
    /// with permutes instead of a load per lane.
    fn rows32(cols: [&[f32; 32]; 3], at: Self) -> [Self; 3];
    /// [`Self::rows32`] for columns of 128 (`at` clamped to `0..=127`).
    fn rows128(cols: [&[f32; 128]; 3], at: Self) -> [Self; 3];
}

/// Truth values, one per lane.
pub(crate) trait Mask: Copy + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> {
    /// True in every lane.
    fn all_true() -> Self;
    /// Whether any lane is true.
    fn any(self) -> bool;
}

impl Mask for bool {
    #[inline(always)]
    fn all_true() -> Self {
        true
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
}

/// [`Real`] for the one-ray scalar `$t` (`f64`, or `f32` for an asphere's
/// start), its sign bit `$sign`; `$t` from an f64 as
/// `$from` gives it (rounded to nearest for `f32`, as the vector types'
/// conversions).
macro_rules! scalar_real {
    ($t:ident, $sign:expr, |$v:ident| $from:expr) => {
        impl Real for $t {
            type Mask = bool;
            type F32 = f32;

            #[inline(always)]
            fn splat($v: f64) -> Self {
                $from
            }
            #[inline(always)]
            fn fma(self, a: Self, b: Self) -> Self {
                $t::mul_add(self, a, b)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $t::sqrt(self)
            }
            #[inline(always)]
            fn sign_bit(self) -> Self {
                $t::from_bits(self.to_bits() & $sign)
            }
            #[inline(always)]
            fn xor(self, o: Self) -> Self {
                $t::from_bits(self.to_bits() ^ o.to_bits())
            }
            #[inline(always)]
            fn or(self, o: Self) -> Self {
                $t::from_bits(self.to_bits() | o.to_bits())
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                self.abs() < $t::INFINITY
            }
            #[inline(always)]
            fn is_neg(self) -> bool {
                self.is_sign_negative()
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $t::abs(self)
            }
            #[inline(always)]
            fn le(self, o: Self) -> bool {
                self <= o
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
            #[inline(always)]
            fn from_mask(m: bool) -> Self {
                if m {
                    -1.0
                } else {
                    1.0
                }
            }
        }
    };
}

scalar_real!(f64, SIGN, |v| v);
scalar_real!(f32, SIGN32, |v| v as f32);

impl RingRows for f32 {
    #[inline(always)]
    fn rows32(cols: [&[f32; 32]; 3], at: Self) -> [Self; 3] {
        // `as` truncates, and takes a NaN to 0
        let i = at.clamp(0.0, 31.0) as usize;
        cols.map(|c| c[i])
    }
    #[inline(always)]
    fn rows128(cols: [&[f32; 128]; 3], at: Self) -> [Self; 3] {
        let i = at.clamp(0.0, 127.0) as usize;
        cols.map(|c| c[i])
    }
}

/// What the vector types' tests of [`RingRows`] share: a table, the
/// indices to read it at, and the check against the one-ray rows.
#[cfg(test)]
pub(crate) mod ring_rows_check {
    use super::RingRows;

    /// Row `i` of the table: numbers distinct in every row and column.
    pub(crate) fn row(i: usize) -> [f32; 3] {
        [i as f32 + 0.25, -(i as f32) * 3.0, 1e-3 * i as f32]
    }

    /// The table's 128 rows by columns.
    pub(crate) fn table() -> [[f32; 128]; 3] {
        std::array::from_fn(|k| std::array::from_fn(|i| row(i)[k]))
    }

    /// The first 32 rows of the table, by columns.
    pub(crate) fn first32(cols: &[[f32; 128]; 3]) -> [&[f32; 32]; 3] {
        cols.each_ref().map(|c| c.first_chunk::<32>().expect("32 of 128"))
    }

    /// Indices inside, at and past both ends of either table, fractional,
    /// infinite and NaN (clamped to the table, NaN to row 0).
    pub(crate) const AT: [f32; 21] = [
        -5.0,
        0.0,
        0.99,
        7.5,
        8.0,
        15.999,
        16.0,
        23.5,
        24.0,
        31.0,
        31.7,
        40.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        63.5,
        64.0,
        100.2,
        127.0,
        127.9,
        200.0,
    ];

    /// Every window of `N` consecutive indices of [`AT`] (wrapping) read by
    /// `read` (the 32-row table's rows, the 128-row table's, each as `N`
    /// lanes a number) gives the one-ray path's rows lane for lane, and
    /// those are the table's rows at the clamped index.
    pub(crate) fn check<const N: usize>(read: impl Fn(&[f32; N]) -> ([[f32; N]; 3], [[f32; N]; 3])) {
        let cols = table();
        for start in 0..AT.len() {
            let lanes: [f32; N] = std::array::from_fn(|j| AT[(start + j) % AT.len()]);
            let (got32, got128) = read(&lanes);
            for (j, a) in lanes.iter().enumerate() {
                let want32 = f32::rows32(first32(&cols), *a);
                let want128 = f32::rows128(cols.each_ref(), *a);
                let clamped = |last: f32| if a.is_nan() { 0 } else { a.clamp(0.0, last) as usize };
                assert_eq!((want32, want128), (row(clamped(31.0)), row(clamped(127.0))), "at {a}");
                for k in 0..3 {
                    assert_eq!(got32[k][j].to_bits(), want32[k].to_bits(), "32 rows, lane {j} at {a}");
                    assert_eq!(got128[k][j].to_bits(), want128[k].to_bits(), "128 rows, lane {j} at {a}");
                }
            }
        }
    }
}
