//! The number types the kernels are written over: `f64` for one ray and,
//! on x86-64, four f64 lanes in an AVX2 register or eight in an AVX-512 one
//! ([`lanes`] says why all round alike); and the f32 lanes an asphere's
//! start is computed in (`f32`, eight in an AVX2 register, sixteen in an
//! AVX-512 one). A leaf: the tracing step (`trace::step`) and the glass
//! formulas the batch tracer evaluates per ray (`glass::kernel`) both build
//! on it.

/// `impl $trait for $t` (each `$trait $method $intrinsic`) by one intrinsic
/// on the lanes' registers: the arithmetic of a vector type, or the
/// bitwise operations of a mask held in a register. The intrinsics need the
/// module's target features, which its values imply (module invariants).
#[cfg(target_arch = "x86_64")]
macro_rules! lane_ops {
    ($t:ident: $($trait:ident $method:ident $intrinsic:ident),+) => {
        $(
            impl std::ops::$trait for $t {
                type Output = $t;
                #[inline(always)]
                fn $method(self, o: $t) -> $t {
                    // SAFETY: the module's target features are available
                    // (module invariant).
                    $t(unsafe { $intrinsic(self.0, o.0) })
                }
            }
        )+
    };
}

/// `Neg` for the vector type `$t`: its sign bits flipped.
#[cfg(target_arch = "x86_64")]
macro_rules! lane_neg {
    ($t:ident) => {
        impl std::ops::Neg for $t {
            type Output = $t;
            #[inline(always)]
            fn neg(self) -> $t {
                self.xor($t::splat(-0.0))
            }
        }
    };
}

/// The bitwise operations and [`lanes::Mask`] for `$m`, a mask held as the
/// bits of an AVX-512 mask register (bit `j` for lane `j`), all lanes true
/// as `$all`.
#[cfg(target_arch = "x86_64")]
macro_rules! mask_bits_ops {
    ($m:ident, $all:expr) => {
        impl std::ops::BitAnd for $m {
            type Output = $m;
            #[inline(always)]
            fn bitand(self, o: $m) -> $m {
                $m(self.0 & o.0)
            }
        }
        impl std::ops::BitOr for $m {
            type Output = $m;
            #[inline(always)]
            fn bitor(self, o: $m) -> $m {
                $m(self.0 | o.0)
            }
        }
        impl std::ops::Not for $m {
            type Output = $m;
            #[inline(always)]
            fn not(self) -> $m {
                $m(!self.0)
            }
        }
        impl crate::simd::lanes::Mask for $m {
            #[inline(always)]
            fn all_true() -> Self {
                $m($all)
            }
            #[inline(always)]
            fn any(self) -> bool {
                self.0 != 0
            }
        }
    };
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2_f32;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512_f32;
pub(crate) mod lanes;
