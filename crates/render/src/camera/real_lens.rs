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
//!
//! Colour: a sample may carry a wavelength; the batch then goes through the
//! lens crate's mixed-wavelength tracer, each ray refracted by its glasses'
//! indices at its own wavelength, so axial and lateral colour and coloured
//! bokeh rims come out of the trace. The weights do not depend on
//! wavelength; the pupil bounds hold the passing targets of every
//! wavelength a render samples.

use super::aperture::Aperture;
pub use super::pupil::SharedPupil;
use super::pupil::{bounded_ends, PupilTables};
use super::{CameraError, CameraSample, Frame, SpectralLane};
use crate::geometry::Ray;
use crate::spectrum::sampled::N;
use crate::spectrum::SampledWavelengths;
use glam::DVec2;
use lens::trace::SpectralBatch;
use lens::{DVec3, Prescription, RayBatch, Tracer};
use std::sync::Arc;

/// A real lens in a scene.
#[derive(Debug, Clone)]
pub struct RealLensCamera {
    frame: Frame,
    prescription: Prescription,
    /// Film to object space (round stop), or film to the stop and the stop
    /// to object space (shaped stop: the shape is tested at the stop).
    trace: LensTrace,
    /// The same, scene to film (for a scene ray's film point at another
    /// wavelength).
    back: LensTrace,
    /// z of the film, mm from the first vertex.
    z_film: f64,
    /// z of the rear vertex plane, where rays are aimed.
    z_rear: f64,
    sensor: [f64; 2],
    tables: Arc<PupilTables>,
    aperture: Aperture,
    stop_sd: f64,
    /// Mean unnormalised weight at the film centre: weights are divided by
    /// it, so the centre of the image has exposure 1.
    norm: f64,
    /// How this film sees the pupil bounds (1 unless they were made for a
    /// sequence at another film: [`super::pupil::pupil_scale`]).
    pupil_scale: f64,
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

    /// Scene to film: the whole lens, or object to the stop (inclusive)
    /// and on to the film.
    fn new_forward(p: &Prescription, aperture: &Aperture) -> Self {
        if *aperture == Aperture::Circle {
            return LensTrace::Whole(Tracer::forward(p));
        }
        let (stop, n) = (p.stop_index(), p.surfaces().len());
        LensTrace::AtStop(Tracer::forward_range(p, 0..stop + 1), Some(Tracer::forward_range(p, stop + 1..n)))
    }

    /// Traces `batch` (film rays, global frame, mm) in place, each ray at
    /// its wavelength when `spectral` (else all at the primary); afterwards
    /// a ray with status 0 has passed. For a shaped stop, `shape(x, y)` (the
    /// stop hit, mm) gives the transmission there, written to `t`; rays it
    /// does not transmit are given a non-zero status.
    pub(crate) fn trace(
        &self,
        batch: &mut SpectralBatch,
        spectral: bool,
        t: &mut Vec<f64>,
        shape: impl Fn(f64, f64) -> f64,
    ) {
        t.clear();
        t.resize(batch.len(), 1.0);
        let run = |tr: &Tracer, b: &mut SpectralBatch| {
            if !spectral {
                tr.trace_soa(&mut b.rays);
            } else if tr.trace_spectral(b).is_err() {
                // the render samples only wavelengths inside every glass's
                // data; a wavelength outside blocks its ray
                b.rays.status.fill(u64::MAX);
            }
        };
        match self {
            LensTrace::Whole(tr) => run(tr, batch),
            LensTrace::AtStop(to_stop, rest) => {
                run(to_stop, batch);
                let rays = &mut batch.rays;
                for (i, ti) in t.iter_mut().enumerate() {
                    if rays.status[i] == 0 {
                        *ti = shape(rays.x[i], rays.y[i]);
                        if *ti <= 0.0 {
                            rays.status[i] = u64::MAX;
                        }
                    }
                }
                if let Some(rest) = rest {
                    run(rest, batch);
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
        if p.is_tilted() {
            return Err(CameraError::Tilted);
        }
        let film = lens::paraxial::film_for_focus_from_film(p, focus_m * 1e3)?;
        Self::with_film_distance(frame, p, film, sensor, aperture, None)
    }

    /// Builds the camera with its film `film_mm` behind the last vertex
    /// (autofocus's real-ray best focus), then bounds the exit pupil as
    /// [`Self::new`] does, or takes the bounds `shared` by a frame
    /// sequence when they were made for this lens, stop and sensor and
    /// their films hold this one.
    pub fn with_film_distance(
        frame: Frame,
        p: &Prescription,
        film_mm: f64,
        sensor: [f64; 2],
        aperture: Aperture,
        shared: Option<&SharedPupil>,
    ) -> Result<Self, CameraError> {
        if !(sensor[0] > 0.0 && sensor[1] > 0.0 && sensor[0].is_finite() && sensor[1].is_finite()) {
            return Err(CameraError::Sensor { width: sensor[0], height: sensor[1] });
        }
        if p.is_tilted() {
            return Err(CameraError::Tilted);
        }
        let shared =
            shared.filter(|s| s.holds(p, &aperture, sensor, film_mm)).map(|s| (s.tables.clone(), s.z_ref, s.z_xp));
        let p = p.with_film_distance(film_mm)?;
        let z_film = p.total_track();
        let z_rear = p.last_vertex_z();
        let half_diag = 0.5 * (sensor[0].hypot(sensor[1]));
        let trace = LensTrace::new(&p, &aperture);
        let back = LensTrace::new_forward(&p, &aperture);
        let stop_sd = p.stop_semi_diameter();
        let (tables, pupil_scale) = match shared {
            Some((t, z_ref, z_xp)) => (t, super::pupil::pupil_scale(z_ref, z_film, z_rear, z_xp)),
            None => {
                let t = PupilTables::build(&p, &aperture, &[z_film], z_film, z_rear, half_diag, &bounded_ends(&p));
                (Arc::new(t), 1.0)
            }
        };
        let mut cam = RealLensCamera {
            frame,
            trace,
            back,
            stop_sd,
            prescription: p,
            z_film,
            z_rear,
            sensor,
            tables,
            aperture,
            norm: 1.0,
            pupil_scale,
        };
        let centre = cam.mean_weight_at_centre();
        if !(centre.is_finite() && centre > 0.0) {
            return Err(CameraError::NoLight);
        }
        cam.norm = centre;
        Ok(cam)
    }

    /// The camera's pose (the film's frame).
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The prescription (focused: its film where the plane in focus is sharp).
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
            .map(|k| CameraSample::new((0.5, 0.5), ((k as f64 + 0.5) / N as f64, (k as f64 * g).fract())))
            .collect();
        let mut sum = 0.0;
        self.lens_rays(&samples, |_, _, _, t, w| sum += t * w);
        sum / N as f64
    }

    /// The lens-frame film point and rear-plane target of a sample, and the
    /// inverse of the density (per mm^2 of the rear plane) it was drawn
    /// with: the area of the pupil bounds it was drawn from uniformly.
    fn target(&self, s: &CameraSample) -> Option<(DVec3, DVec3, f64)> {
        // the lens inverts the image: film point opposite the scene point
        let fx = -(s.film.0 - 0.5) * self.sensor[0];
        let fy = -(0.5 - s.film.1) * self.sensor[1];
        let film = DVec3::new(fx, fy, self.z_film);
        let (area, (bx, by)) = self.pupil_sample(fx, fy, s.aperture)?;
        Some((film, DVec3::new(bx, by, self.z_rear), area))
    }

    /// The area (mm^2 of the rear plane) of the region targets are drawn
    /// from at film point (fx, fy): the pupil bounds' own, scaled for this
    /// film ([`super::pupil::pupil_scale`]).
    fn pupil_area(&self, fx: f64, fy: f64) -> Option<f64> {
        let k = self.pupil_scale;
        self.tables.area_at(fx, fy).map(|a| if k == 1.0 { a } else { a * k * k })
    }

    /// A target drawn uniformly from the pupil bounds at film point (fx,
    /// fy), scaled for this film, and the area of the region it was drawn
    /// from (see [`Self::pupil_area`]).
    fn pupil_sample(&self, fx: f64, fy: f64, a: (f64, f64)) -> Option<(f64, (f64, f64))> {
        let (area, (bx, by)) = self.tables.sample(fx, fy, a)?;
        let k = self.pupil_scale;
        if k == 1.0 {
            return Some((area, (bx, by)));
        }
        Some((area * k * k, (fx + (bx - fx) * k, fy + (by - fy) * k)))
    }

    /// Traces `samples` (each at its wavelength, if it has one and the
    /// lens has glasses) and hands each passing ray (lens frame, leaving
    /// the first surface, mm) with its unnormalised weight to `emit`, in
    /// order, with the sample's index; blocked samples are skipped.
    fn lens_rays(&self, samples: &[CameraSample], mut emit: impl FnMut(usize, &RayBatch, usize, f64, f64)) {
        let d = self.z_film - self.z_rear;
        let inv_d2 = 1.0 / (d * d);
        let primary = self.prescription.wavelength_nm();
        let spectral = self.prescription.is_dispersive() && samples.iter().any(|s| s.wavelength_nm.is_some());
        let mut batch = SpectralBatch::with_capacity(BATCH.min(samples.len()));
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
                let nm = s.wavelength_nm.unwrap_or(primary);
                match aimed {
                    Some((origin, direction, area)) => {
                        batch.push(lens::Ray { origin, direction }, nm);
                        factor.push(area * direction.z.powi(4) * inv_d2);
                    }
                    None => {
                        batch.push_skipped(nm);
                        factor.push(0.0);
                    }
                }
            }
            self.trace.trace(&mut batch, spectral, &mut t, shape);
            for i in 0..chunk.len() {
                if batch.rays.status[i] == 0 && t[i] * factor[i] > 0.0 {
                    emit(c * BATCH + i, &batch.rays, i, t[i], factor[i]);
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
        let inv_norm = 1.0 / self.norm;
        self.lens_rays(samples, |k, b, i, t, w| {
            out[k] = Some((self.to_scene(b, i), t * w * inv_norm));
        });
    }

    /// Ray `i` of `b` (lens frame, mm: x right, y up, z from the first
    /// vertex toward the film) as a scene ray (m). A rotation of a unit
    /// direction: unit already.
    fn to_scene(&self, b: &RayBatch, i: usize) -> Ray {
        self.lens_to_scene(DVec3::new(b.x[i], b.y[i], b.z[i]), DVec3::new(b.dx[i], b.dy[i], b.dz[i]))
    }

    /// A lens-frame point (mm) and direction as a scene ray (m).
    fn lens_to_scene(&self, p: DVec3, d: DVec3) -> Ray {
        let f = &self.frame;
        let to_world = |x: f64, y: f64, z_back: f64| f.right * x + f.up * y + f.forward * z_back;
        let origin = f.origin + to_world(p.x, p.y, self.z_film - p.z) * 1e-3;
        Ray { origin, dir: to_world(d.x, d.y, -d.z) }
    }

    /// The chief rays of film positions (u, v in [0, 1], v down) at the
    /// primary wavelength, as scene rays leaving the first surface: the ray
    /// from each film point that crosses the stop at its centre, found by
    /// the secant method on its aim at the rear vertex plane (the lens is
    /// symmetric about its axis, so the aim lies on the film point's
    /// radius) to 1e-9 mm at the stop, traced with no clear aperture
    /// clipping (a vignetted chief ray still says where the pixel looks).
    /// `None` where no such ray gets through the surfaces (it misses one or
    /// is totally reflected).
    pub fn chief_rays(&self, film: &[(f64, f64)]) -> Vec<Option<Ray>> {
        let p = &self.prescription;
        let tracer = Tracer::reverse_unclipped(p);
        let stop = p.stop_index();
        let d = self.z_film - self.z_rear;
        let xp = lens::paraxial::FirstOrder::of(p).ok().and_then(|f| f.exit_pupil).map(|x| x.z);
        film.iter()
            .map(|&(u, v)| {
                let (fx, fy) = (-(u - 0.5) * self.sensor[0], -(0.5 - v) * self.sensor[1]);
                let r = fx.hypot(fy);
                let e = if r > 0.0 { DVec2::new(fx, fy) / r } else { DVec2::X };
                let origin = DVec3::new(fx, fy, self.z_film);
                let ray_to = |t: f64| {
                    let to = DVec3::new(e.x * t, e.y * t, self.z_rear);
                    lens::Ray { origin, direction: (to - origin).normalize() }
                };
                // the stop height (along e) of the ray aimed t along e
                let height = |t: f64| match tracer.trace_at_surface(ray_to(t), stop) {
                    (_, Some(hit)) => Some(hit.x * e.x + hit.y * e.y),
                    _ => None,
                };
                // from the paraxial aim at the exit pupil's centre
                let guess = match xp {
                    Some(z) if (z - self.z_film).abs() > 1e-9 => r * (z - self.z_rear) / (z - self.z_film),
                    _ => 0.0,
                };
                let (mut t0, mut t1) = (guess, guess + 1e-3 * d.max(1.0));
                let (mut g0, mut g1) = (height(t0)?, height(t1)?);
                for _ in 0..60 {
                    if g1.abs() <= 1e-9 || g1 == g0 {
                        break;
                    }
                    let mut t2 = t1 - g1 * (t1 - t0) / (g1 - g0);
                    // a step whose ray misses a surface is halved back
                    let mut g2 = height(t2);
                    for _ in 0..40 {
                        if g2.is_some() {
                            break;
                        }
                        t2 = 0.5 * (t1 + t2);
                        g2 = height(t2);
                    }
                    (t0, g0) = (t1, g1);
                    (t1, g1) = (t2, g2?);
                }
                if g1.is_nan() || g1.abs() > 1e-6 {
                    return None;
                }
                match tracer.trace(ray_to(t1)) {
                    lens::Outcome::Reached { ray, .. } => Some(self.lens_to_scene(ray.origin, ray.direction)),
                    _ => None,
                }
            })
            .collect()
    }

    /// The lens's full (geometric) blur diameter on the film, mm, of an
    /// on-axis point at each of `distances` (m from the film, as the
    /// camera's focus distance is measured), from the lens crate's circle
    /// of confusion (its real on-axis bundle at this film); `None` for a
    /// distance inside the lens.
    pub fn blur_diameters_mm(&self, distances: &[f64]) -> Result<Vec<Option<f64>>, lens::OpticsError> {
        let p = &self.prescription;
        let object_of = |z_m: f64| {
            let o = z_m * 1e3 - self.z_film;
            (o > 0.0).then_some(o)
        };
        let objects: Vec<f64> = distances.iter().filter_map(|&z| object_of(z)).collect();
        // the object the film is focused on (exact paraxial focus)
        let focus = match lens::paraxial::object_distance_in_focus(p, self.z_film - self.z_rear)? {
            lens::paraxial::ObjectDistance::Finite(d) => d,
            lens::paraxial::ObjectDistance::Infinity => f64::INFINITY,
        };
        let table = lens::analysis::coc::circle_of_confusion(p, focus, &objects)?;
        let mut rows = table.rows.iter();
        Ok(distances.iter().map(|&z| object_of(z).and_then(|_| rows.next().map(|r| r.geo_diameter))).collect())
    }

    /// Sensor width and height, mm.
    pub fn sensor_mm(&self) -> [f64; 2] {
        self.sensor
    }

    /// How far in front of the film the lens's first vertex is, m: nearer
    /// points are inside the lens.
    pub fn front_distance_m(&self) -> f64 {
        self.z_film * 1e-3
    }

    /// The distance from the film to the plane in focus (exact paraxial
    /// focus of the film as placed), m; infinity when focused there.
    pub fn focus_distance_m(&self) -> f64 {
        match lens::paraxial::object_distance_in_focus(&self.prescription, self.z_film - self.z_rear) {
            Ok(lens::paraxial::ObjectDistance::Finite(d)) => (d + self.z_film) * 1e-3,
            _ => f64::INFINITY,
        }
    }

    /// The inverse of [`Self::to_scene`]: a scene ray's point and direction
    /// in the lens frame (mm).
    fn to_lens(&self, ray: &Ray) -> (DVec3, DVec3) {
        let f = &self.frame;
        let v = (ray.origin - f.origin) * 1e3;
        let p = DVec3::new(v.dot(f.right), v.dot(f.up), self.z_film - v.dot(f.forward));
        let d = DVec3::new(ray.dir.dot(f.right), ray.dir.dot(f.up), -ray.dir.dot(f.forward));
        (p, d)
    }

    /// Scene rays for samples that carry four wavelengths each (the hero,
    /// `samples[k].wavelength_nm`, and `wavelengths[k].nm[1..]`), with
    /// what each wavelength needs for the render's combination of them
    /// ([`SpectralLane`]): the hero's ray is traced film to scene
    /// ([`Self::heroes`]); then the scene ray is traced back, scene to
    /// film, at each companion wavelength ([`Self::companions`]).
    pub fn rays_spectral(
        &self,
        samples: &[CameraSample],
        wavelengths: &[SampledWavelengths],
        out: &mut Vec<Option<(Ray, [SpectralLane; N])>>,
    ) {
        self.heroes(samples, out);
        let all: Vec<usize> = (0..samples.len()).collect();
        self.companions(wavelengths, out, &all);
    }

    /// The heroes of [`Self::rays_spectral`]: each sample's scene ray at
    /// its own wavelength with its lane (the companions' lanes blocked
    /// until [`Self::companions`] fills them).
    pub fn heroes(&self, samples: &[CameraSample], out: &mut Vec<Option<(Ray, [SpectralLane; N])>>) {
        out.clear();
        out.resize(samples.len(), None);
        self.lens_rays(samples, |k, b, i, t, w| {
            let hero = SpectralLane { film: samples[k].film, transmission: t, density: self.norm / w };
            let mut lanes = [SpectralLane::BLOCKED; N];
            lanes[0] = hero;
            out[k] = Some((self.to_scene(b, i), lanes));
        });
    }

    /// The companions' lanes of the samples `selected` (indices into
    /// `out`, as [`Self::heroes`] left it): each scene ray traced back,
    /// scene to film, at each companion wavelength, finding the film point
    /// and rear-plane target that send light of that wavelength along the
    /// same scene ray.
    pub fn companions(
        &self,
        wavelengths: &[SampledWavelengths],
        out: &mut [Option<(Ray, [SpectralLane; N])>],
        selected: &[usize],
    ) {
        let mut back = SpectralBatch::with_capacity(3 * selected.len());
        let mut owner = Vec::with_capacity(3 * selected.len());
        for &k in selected {
            let Some((ray, _)) = &out[k] else { continue };
            let (p, d) = self.to_lens(ray);
            // into the lens from a millimetre in front of where it left
            let start = p + d;
            for (j, nm) in wavelengths[k].nm.iter().enumerate().skip(1) {
                back.push(lens::Ray { origin: start, direction: -d }, *nm);
                owner.push((k, j));
            }
        }
        let mut t = Vec::new();
        let shape = |x: f64, y: f64| self.aperture.transmission(x / self.stop_sd, y / self.stop_sd);
        self.back.trace(&mut back, true, &mut t, shape);
        let d = self.z_film - self.z_rear;
        let r = &back.rays;
        for (i, &(k, j)) in owner.iter().enumerate() {
            if r.status[i] != 0 || !(t[i] > 0.0 && r.dz[i] > 0.0) {
                continue;
            }
            let (fx, fy) = (r.x[i], r.y[i]);
            let cos = r.dz[i];
            let Some(area) = self.pupil_area(fx, fy) else { continue };
            let w = area * cos.powi(4) / (d * d);
            if let Some((_, lanes)) = &mut out[k] {
                lanes[j] = SpectralLane {
                    film: (0.5 - fx / self.sensor[0], 0.5 + fy / self.sensor[1]),
                    transmission: t[i],
                    density: self.norm / w,
                };
            }
        }
    }

    /// Traces `batch` (lens frame, mm, rays from object space toward the
    /// film) through the lens onto the film, each ray at its wavelength
    /// when `spectral`; afterwards a ray with status 0 reached the film
    /// point (x, y) it holds, with the stop shape's transmission in `t`.
    /// What light traced from a lamp goes through ([`super::lamp_light`]).
    pub(crate) fn trace_to_film(&self, batch: &mut SpectralBatch, spectral: bool, t: &mut Vec<f64>) {
        let shape = |x: f64, y: f64| self.aperture.transmission(x / self.stop_sd, y / self.stop_sd);
        self.back.trace(batch, spectral, t, shape);
    }

    /// The stop's shape (unit scale: the stop's clear radius is 1).
    pub fn aperture(&self) -> &Aperture {
        &self.aperture
    }

    /// The film position (u, v in [0, 1], v down) of a lens-frame film
    /// point (mm): the inverse of the film mapping of [`Self::rays`].
    pub(crate) fn film_uv(&self, fx: f64, fy: f64) -> (f64, f64) {
        (0.5 - fx / self.sensor[0], 0.5 + fy / self.sensor[1])
    }

    /// A scene point (m) in the lens frame (mm: x right, y up, z from the
    /// first vertex toward the film).
    pub fn point_to_lens(&self, p: DVec3) -> DVec3 {
        self.to_lens(&Ray { origin: p, dir: self.frame.forward }).0
    }

    /// A scene direction in the lens frame.
    pub(crate) fn dir_to_lens(&self, d: DVec3) -> DVec3 {
        self.to_lens(&Ray { origin: self.frame.origin, dir: d }).1
    }

    /// A lens-frame point (mm) and direction as a scene ray (m).
    pub(crate) fn ray_to_scene(&self, p: DVec3, d: DVec3) -> Ray {
        self.lens_to_scene(p, d)
    }

    /// The scene ray through one film position and its weight (see
    /// [`Self::rays`]), at wavelength `nm` (`None`: the primary).
    pub fn ray_at(&self, u: f64, v: f64, a: (f64, f64), nm: Option<f64>) -> Option<(Ray, f64)> {
        let mut out = Vec::with_capacity(1);
        self.rays(&[CameraSample { film: (u, v), aperture: a, wavelength_nm: nm }], &mut out);
        out.pop().flatten()
    }
}
