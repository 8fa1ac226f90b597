//! The number types the kernels are written over: `f64` for one ray and,
//! on x86-64, four f64 lanes in an AVX2 register or eight in an AVX-512 one
//! ([`lanes`] says why all round alike). A leaf: the tracing step (`trace::step`) and the glass
//! formulas the batch tracer evaluates per ray (`glass::kernel`) both build
//! on it.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
pub(crate) mod lanes;
