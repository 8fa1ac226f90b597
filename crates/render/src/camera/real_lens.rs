//! The real-lens camera: each camera ray starts on the film, is aimed at a
//! point inside the exit-pupil bounds for its film position, and is traced
//! surface by surface through the prescription into the scene by the lens
//! crate's batch tracer (a whole row of samples at once). Vignetting,
//! cos^4 fall-off, distortion, aberrations and bokeh shapes all come out of
//! the trace.
//!
//! The estimator: a film point's irradiance is the integral over the rear
//! vertex plane of L cos^4(theta) / d^2 (d the film-to-plane distance) over
//! the points whose rays pass the lens. Targets are drawn uniformly over a
//! set of cells that contains every passing point ([`super::pupil`]), so
//! the weight of a sample is the cells' area times cos^4 / d^2 (times a
//! mask's transmission), and rays that do not pass have weight 0.

use super::aperture::Aperture;
use super::pupil::PupilTables;
use super::{CameraError, CameraSample, Frame};
use crate::geometry::Ray;
use lens::{DVec3, Prescription, RayBatch, Tracer};

/// A real lens in a scene.
#[derive(Debug, Clone)]
pub struct RealLensCamera {
    frame: Frame,
    prescription: Prescription,
    /// Film to object space (round stop), or film to the stop and the stop
    /// to object space (shaped stop: the shape is tested at the stop).
    trace: LensTrace,
    /// z of the film, mm from the first vertex.
    z_film: f64,
    /// z of the rear vertex plane, where rays are aimed.
    z_rear: f64,
    sensor: [f64; 2],
    tables: PupilTables,
    aperture: Aperture,
    stop_sd: f64,
    /// Mean unnormalised weight at the film centre: weights are divided by
    /// it, so the centre of the image has exposure 1.
    norm: f64,
}

/// How camera rays go through the lens.
#[derive(Debug, Clone)]
pub(crate) enum LensTrace {
    /// One trace, film to object space.
    Whole(Tracer),
    /// Film to the stop (inclusive), then on to object space (`None` when
    /// the stop is the first surface).
    AtStop(Tracer, Option<Tracer>),
}

impl LensTrace {
    fn new(p: &Prescription, aperture: &Aperture) -> Self {
        if *aperture == Aperture::Circle {
            return LensTrace::Whole(Tracer::reverse(p));
        }
        let (stop, n) = (p.stop_index(), p.surfaces().len());
        let rest = (stop > 0).then(|| Tracer::reverse_range(p, 0..stop));
        LensTrace::AtStop(Tracer::reverse_range(p, stop..n), rest)
    }

    /// Traces `batch` (film rays, global frame, mm) in place; afterwards a
    /// ray with status 0 has passed. For a shaped stop, `shape(x, y)` (the
    /// stop hit, mm) gives the transmission there, written to `t`; rays it
    /// does not transmit are given a non-zero status.
    pub(crate) fn trace(&self, batch: &mut RayBatch, t: &mut Vec<f64>, shape: impl Fn(f64, f64) -> f64) {
        t.clear();
        t.resize(batch.len(), 1.0);
        match self {
            LensTrace::Whole(tr) => tr.trace_soa(batch),
            LensTrace::AtStop(to_stop, rest) => {
                to_stop.trace_soa(batch);
                for (i, ti) in t.iter_mut().enumerate() {
                    if batch.status[i] == 0 {
                        *ti = shape(batch.x[i], batch.y[i]);
                        if *ti <= 0.0 {
                            batch.status[i] = u64::MAX;
                        }
                    }
                }
                if let Some(rest) = rest {
                    rest.trace_soa(batch);
                }
            }
        }
    }
}

/// Camera samples traced together per batch.
const BATCH: usize = 4096;

impl RealLensCamera {
    /// Builds the camera: focuses the lens so the plane `focus_m` metres from
    /// the film is sharp (exact paraxial focus, not a thick-lens guess), then
    /// bounds the exit pupil for each film position.
    pub fn new(
        frame: Frame,
        p: &Prescription,
        focus_m: f64,
        sensor: [f64; 2],
        aperture: Aperture,
    ) -> Result<Self, CameraError> {
        if !(sensor[0] > 0.0 && sensor[1] > 0.0 && sensor[0].is_finite() && sensor[1].is_finite()) {
            return Err(CameraError::Sensor { width: sensor[0], height: sensor[1] });
        }
        let film = lens::paraxial::film_for_focus_from_film(p, focus_m * 1e3)?;
        let p = p.with_film_distance(film)?;
        let z_film = p.total_track();
        let z_rear = p.last_vertex_z();
        let half_diag = 0.5 * (sensor[0].hypot(sensor[1]));
        let trace = LensTrace::new(&p, &aperture);
        let stop_sd = p.stop_semi_diameter();
        let tables = PupilTables::build(&p, &aperture, z_film, z_rear, half_diag);
        let mut cam = RealLensCamera {
            frame,
            trace,
            stop_sd,
            prescription: p,
            z_film,
            z_rear,
            sensor,
            tables,
            aperture,
            norm: 1.0,
        };
        let centre = cam.mean_weight_at_centre();
        if !(centre.is_finite() && centre > 0.0) {
            return Err(CameraError::NoLight);
        }
        cam.norm = centre;
        Ok(cam)
    }

    /// The focused prescription.
    pub fn prescription(&self) -> &Prescription {
        &self.prescription
    }

    /// The mean unnormalised estimator weight at the film centre (1/mm^2,
    /// the integral of cos^4 / d^2 over the passing part of the rear
    /// vertex plane): what weights are divided by.
    pub fn centre_weight(&self) -> f64 {
        self.norm
    }

    /// Mean estimator weight at the film centre (before normalisation), by
    /// 65,536 targets stratified over the centre's cells (a Kronecker
    /// sequence in the second coordinate): the centre's pupil integral to
    /// about 1e-4.
    fn mean_weight_at_centre(&self) -> f64 {
        const N: usize = 65_536;
        let g = 0.618_033_988_749_894_9;
        let samples: Vec<CameraSample> = (0..N)
            .map(|k| CameraSample { film: (0.5, 0.5), aperture: ((k as f64 + 0.5) / N as f64, (k as f64 * g).fract()) })
            .collect();
        let mut sum = 0.0;
        self.lens_rays(&samples, |_, _, _, w| sum += w);
        sum / N as f64
    }

    /// The lens-frame film point and rear-plane target of a sample, and the
    /// area of the region the target was drawn from (mm^2).
    fn target(&self, s: &CameraSample) -> Option<(DVec3, DVec3, f64)> {
        // the lens inverts the image: film point opposite the scene point
        let fx = -(s.film.0 - 0.5) * self.sensor[0];
        let fy = -(0.5 - s.film.1) * self.sensor[1];
        let (area, (bx, by)) = self.tables.sample(fx, fy, s.aperture)?;
        Some((DVec3::new(fx, fy, self.z_film), DVec3::new(bx, by, self.z_rear), area))
    }

    /// Traces `samples` and hands each passing ray (lens frame, leaving the
    /// first surface, mm) with its unnormalised weight to `emit`, in order,
    /// with the sample's index; blocked samples are skipped.
    fn lens_rays(&self, samples: &[CameraSample], mut emit: impl FnMut(usize, &RayBatch, usize, f64)) {
        let d = self.z_film - self.z_rear;
        let inv_d2 = 1.0 / (d * d);
        let mut batch = RayBatch::with_capacity(BATCH.min(samples.len()));
        let mut t = Vec::new();
        // per sample: the bounds' area times the film-side cos^4 (taken
        // before the trace moves the rays)
        let mut factor = Vec::with_capacity(BATCH);
        let shape = |x: f64, y: f64| self.aperture.transmission(x / self.stop_sd, y / self.stop_sd);
        for (c, chunk) in samples.chunks(BATCH).enumerate() {
            batch.clear();
            factor.clear();
            for s in chunk {
                let aimed = self.target(s).and_then(|(f, to, b)| {
                    let dir = to - f;
                    let len2 = dir.length_squared();
                    (len2 > 0.0 && len2.is_finite()).then(|| (f, dir / len2.sqrt(), b))
                });
                match aimed {
                    Some((origin, direction, area)) => {
                        batch.push(lens::Ray { origin, direction });
                        factor.push(area * direction.z.powi(4) * inv_d2);
                    }
                    None => {
                        batch.push(lens::Ray::default());
                        let last = batch.len() - 1;
                        batch.status[last] = u64::MAX;
                        factor.push(0.0);
                    }
                }
            }
            self.trace.trace(&mut batch, &mut t, shape);
            for i in 0..chunk.len() {
                let w = t[i] * factor[i];
                if batch.status[i] == 0 && w > 0.0 {
                    emit(c * BATCH + i, &batch, i, w);
                }
            }
        }
    }

    /// Scene rays for a batch of samples (film position u, v in [0, 1], v
    /// down; aperture uniforms), each with its weight (normalised to 1 on
    /// average at the film centre), `None` where the lens blocks the ray.
    pub fn rays(&self, samples: &[CameraSample], out: &mut Vec<Option<(Ray, f64)>>) {
        out.clear();
        out.resize(samples.len(), None);
        let f = &self.frame;
        let inv_norm = 1.0 / self.norm;
        // lens frame: x = right, y = up, z = against the viewing direction
        let to_world = |x: f64, y: f64, z_back: f64| f.right * x + f.up * y + f.forward * z_back;
        self.lens_rays(samples, |k, b, i, w| {
            let origin = f.origin + to_world(b.x[i], b.y[i], self.z_film - b.z[i]) * 1e-3;
            // a rotation of a unit vector: unit already
            let dir = to_world(b.dx[i], b.dy[i], -b.dz[i]);
            out[k] = Some((Ray { origin, dir }, w * inv_norm));
        });
    }

    /// The scene ray through one film position and its weight (see
    /// [`Self::rays`]).
    pub fn ray(&self, u: f64, v: f64, a: (f64, f64)) -> Option<(Ray, f64)> {
        let mut out = Vec::with_capacity(1);
        self.rays(&[CameraSample { film: (u, v), aperture: a }], &mut out);
        out.pop().flatten()
    }
}
