//! A reproducible tracing workload and its timing, behind `lens bench` and
//! the criterion benchmark: full-aperture bundles over a range of fields.

use super::batch::RayBatch;
use super::ray::Ray;
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::FirstOrder;
use crate::trace::{SpectralBatch, Tracer};
use glam::DVec3;
use std::time::{Duration, Instant};

/// Most rays a workload holds.
pub const MAX_RAYS: usize = 20_000_000;

/// Largest field angle of the workload, degrees.
pub const MAX_FIELD_DEG: f64 = 10.0;

/// `n` rays filling the paraxial entrance pupil at fields from 0 to
/// [`MAX_FIELD_DEG`] (object at infinity), placed by a low-discrepancy
/// (R3) sequence, and a forward tracer for them.
#[derive(Debug, Clone)]
pub struct Workload {
    /// The forward tracer (object to film).
    pub tracer: Tracer,
    /// The rays as launched.
    pub rays: RayBatch,
    /// Surfaces in the prescription (the film plane is not counted).
    pub surfaces: usize,
    /// A wavelength for each ray, every one different, spread over
    /// 400-700 nm (a golden-ratio sequence): the batch of mixed
    /// wavelengths that [`Workload::measure_spectral`] traces.
    pub wavelength_nm: Vec<f64>,
}

/// A timing of the batch tracer on the calling thread.
///
/// The headline figures are those of the fastest pass: on a shared machine
/// other work only ever slows a pass down, so the fastest is the closest to
/// what the code does (the minimum is the usual estimator of a benchmark's
/// time under such noise); the median pass is given beside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// Passes over the whole workload.
    pub passes: usize,
    /// Seconds spent tracing, all passes (copies excluded).
    pub seconds: f64,
    /// Rays traced per second, fastest pass.
    pub rays_per_second: f64,
    /// Ray-surface intersections per second, fastest pass, counting the
    /// prescription's surfaces (not the final transfer to the film plane).
    pub ray_surface_per_second: f64,
    /// Rays traced per second, median pass.
    pub median_rays_per_second: f64,
    /// Ray-surface intersections per second, median pass.
    pub median_ray_surface_per_second: f64,
    /// Fraction of rays that reached the film.
    pub reached_fraction: f64,
}

impl Workload {
    /// Builds the workload of `n` rays.
    pub fn new(p: &Prescription, n: usize) -> Result<Self, OpticsError> {
        if n == 0 || n > MAX_RAYS {
            return Err(OpticsError::BadInput {
                name: "rays",
                value: n as f64,
                expected: "between 1 and 20 million rays (64 bytes each)",
            });
        }
        let f = FirstOrder::of(p)?;
        let ep = f.entrance_pupil;
        let r_ep = ep.diameter / 2.0;
        let z_start = ep.z.min(0.0) - 10.0;
        let mut rays = RayBatch::with_capacity(n);
        // R3 sequence (Roberts): fractional parts of k * (1/g, 1/g^2, 1/g^3)
        // with g the plastic-number generalisation for 3 dimensions.
        let g = 1.220_744_084_605_759_5_f64;
        let a = [1.0 / g, 1.0 / (g * g), 1.0 / (g * g * g)];
        for k in 0..n {
            let u = a.map(|ai| (0.5 + ai * k as f64).fract());
            let r = r_ep * u[0].sqrt();
            let phi = std::f64::consts::TAU * u[1];
            let theta = (MAX_FIELD_DEG * u[2]).to_radians();
            let d = DVec3::new(0.0, theta.sin(), theta.cos());
            let aim = DVec3::new(r * phi.cos(), r * phi.sin(), ep.z);
            let origin = aim - d * ((ep.z - z_start) / d.z);
            rays.push(Ray { origin, direction: d });
        }
        let wavelength_nm =
            (0..n).map(|k| 400.0 + 300.0 * (0.5 + 0.618_033_988_749_894_9 * k as f64).fract()).collect();
        Ok(Workload { tracer: Tracer::forward(p), rays, surfaces: p.surfaces().len(), wavelength_nm })
    }

    /// The monochromatic trace and the trace of mixed wavelengths
    /// ([`Tracer::trace_spectral`], every ray at its own wavelength, the
    /// glasses' indices evaluated per ray inside the timing), passes
    /// alternating so that both see the same machine, for at least
    /// `budget` each (and at least 3 passes each). Errors where a glass
    /// has no data over 400-700 nm.
    pub fn measure_spectral(&self, budget: Duration) -> Result<(Measurement, Measurement), OpticsError> {
        let spectral = SpectralBatch { rays: self.rays.clone(), wavelength_nm: self.wavelength_nm.clone() };
        let mut work = spectral.clone();
        self.tracer.trace_spectral(&mut work)?;
        let (mut mono, mut mixed) = (Vec::new(), Vec::new());
        let mut traced = Duration::ZERO;
        while traced < 2 * budget || mono.len() < 3 {
            restore(&mut work.rays, &self.rays);
            let t = Instant::now();
            self.tracer.trace_soa(&mut work.rays);
            let dt = t.elapsed();
            mono.push(dt.as_secs_f64().max(1e-9));
            restore(&mut work.rays, &self.rays);
            let t = Instant::now();
            self.tracer.trace_spectral(&mut work)?;
            let ds = t.elapsed();
            mixed.push(ds.as_secs_f64().max(1e-9));
            traced += dt + ds;
        }
        let reached = work.rays.status.iter().filter(|s| **s == 0).count() as f64 / self.rays.len().max(1) as f64;
        let m = self.summarise(&mut mono, traced.as_secs_f64() / 2.0, reached);
        Ok((m, self.summarise(&mut mixed, traced.as_secs_f64() / 2.0, reached)))
    }

    /// The figures of a list of pass times.
    fn summarise(&self, times: &mut [f64], seconds: f64, reached_fraction: f64) -> Measurement {
        times.sort_by(f64::total_cmp);
        let rays = self.rays.len() as f64;
        let per_surface = self.surfaces as f64;
        let (best, median) = (rays / times[0], rays / times[times.len() / 2]);
        Measurement {
            passes: times.len(),
            seconds,
            rays_per_second: best,
            ray_surface_per_second: best * per_surface,
            median_rays_per_second: median,
            median_ray_surface_per_second: median * per_surface,
            reached_fraction,
        }
    }

    /// Traces the workload repeatedly for at least `budget` (and at least 3
    /// passes) and reports the throughput on this thread.
    pub fn measure(&self, budget: Duration) -> Measurement {
        let mut work = self.rays.clone();
        let mut traced = Duration::ZERO;
        let mut times = Vec::new();
        while traced < budget || times.len() < 3 {
            restore(&mut work, &self.rays);
            let t = Instant::now();
            self.tracer.trace_soa(&mut work);
            let dt = t.elapsed();
            traced += dt;
            times.push(dt.as_secs_f64().max(1e-9));
        }
        let reached = work.status.iter().filter(|s| **s == 0).count() as f64 / self.rays.len().max(1) as f64;
        self.summarise(&mut times, traced.as_secs_f64(), reached)
    }
}

/// Copies the launched rays back over a traced batch.
pub fn restore(work: &mut RayBatch, from: &RayBatch) {
    work.x.copy_from_slice(&from.x);
    work.y.copy_from_slice(&from.y);
    work.z.copy_from_slice(&from.z);
    work.dx.copy_from_slice(&from.dx);
    work.dy.copy_from_slice(&from.dy);
    work.dz.copy_from_slice(&from.dz);
    work.opl.copy_from_slice(&from.opl);
    work.status.copy_from_slice(&from.status);
}
