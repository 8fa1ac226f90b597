//! The number types the kernels are written over: `f64` for one ray and,
//! on x86-64, four f64 lanes in an AVX2 register ([`lanes`] says why both
//! round alike). A leaf: the tracing step (`trace::step`) and the glass
//! formulas the batch tracer evaluates per ray (`glass::kernel`) both build
//! on it.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
pub(crate) mod lanes;
