//! The number types the kernels are written over: `f64` for one ray and,
//! on x86-64, four f64 lanes in an AVX2 register or eight in an AVX-512 one
//! ([`lanes`] says why all round alike); and the f32 lanes an asphere's
//! start is computed in (`f32`, eight in an AVX2 register, sixteen in an
//! AVX-512 one). A leaf: the tracing step (`trace::step`) and the glass
//! formulas the batch tracer evaluates per ray (`glass::kernel`) both build
//! on it.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2_f32;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512_f32;
pub(crate) mod lanes;
