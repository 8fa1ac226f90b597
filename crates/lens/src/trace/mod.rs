//! Exact real-ray tracing. A [`Tracer`] lays a prescription out as steps for
//! one direction of travel; [`step`] carries rays across one surface
//! (intersection, clear aperture, refraction, verdict), [`asphere`] the
//! same for an aspheric surface (Newton's iteration), written once over a
//! lane type (`lanes`) so that the one-ray path and the batch ([`batch`],
//! vectors of four or eight rays; its aspheric step over a chunk in
//! `asphere_chunk`) give the same bits. [`spectral`] traces rays of mixed wavelengths in one batch. [`mod@bench`] is the
//! reproducible workload behind `lens bench`.

pub mod asphere;
#[cfg(target_arch = "x86_64")]
mod asphere_chunk;
pub mod batch;
pub mod bench;
mod frame;
pub mod ray;
pub mod spectral;
pub mod step;
pub mod tracer;
pub(crate) mod zones;

pub use batch::RayBatch;
pub use ray::{Outcome, Ray};
pub use spectral::SpectralBatch;
pub use step::{intersect, refract, Hit};
pub use tracer::{StopShape, Tracer};

/// Uniform numbers in [0, 1) from a xorshift generator seeded with `seed`,
/// for the unit tests: the same sequence on every run.
#[cfg(test)]
pub(crate) fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}
