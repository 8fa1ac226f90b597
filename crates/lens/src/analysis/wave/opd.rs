//! Optical path difference over the pupil of one field: the wavefront
//! error every wave analysis starts from.
//!
//! Rays through the cells of a [`PupilGrid`] are launched as the other
//! analyses launch them (the field's aiming), traced to the image plane, and
//! walked back along their image-space direction to the **reference
//! sphere**: centred on the chief ray's image point, through the paraxial
//! exit pupil's centre on the axis (Zemax's "Reference OPD: Exit Pupil",
//! optiland's chief-ray sphere). The wavefront error of a ray is
//!
//! W = (S_chief - S_ray) / lambda, in waves,
//!
//! with S the optical path from the object (for an object at infinity,
//! from the plane wave through the chief ray's start) to the sphere, so
//! W(chief) = 0 and W > 0 where a ray's path is shorter than the chief
//! ray's (a wavefront ahead of the reference). Each path is summed ray by
//! ray in double precision from the start (hundreds of mm at most, so the
//! difference keeps ~1e-13 mm, 1e-9 waves: an ideal system gives |W| below
//! 1e-6 waves). Rays the lens blocks (or real aiming cannot place) are
//! outside the pupil: the pupil's shape is the vignetted one.

use super::pupil::PupilGrid;
use crate::analysis::bundle;
use crate::analysis::fan::ImagePlane;
use crate::analysis::{Field, Launcher};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::first_order::Pupil;
use crate::trace::{RayBatch, Tracer};
use glam::DVec3;
use rayon::prelude::*;

/// The wavefront error of one field at one wavelength over a pupil grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Wavefront {
    /// The field.
    pub field: Field,
    /// The wavelength traced, nm.
    pub wavelength_nm: f64,
    /// The image plane the rays were traced to, and its z from the first
    /// vertex (mm).
    pub plane: ImagePlane,
    /// z of the image plane, mm from the first vertex.
    pub image_z: f64,
    /// The pupil grid sampled (normalised entrance-pupil coordinates as
    /// launched, before the design's vignetting factors).
    pub grid: PupilGrid,
    /// Per grid cell: W in waves where its ray reached the image, `None`
    /// where the lens blocked it or aiming could not place it.
    pub opd_waves: Vec<Option<f64>>,
    /// Per grid cell: where its ray crosses the reference sphere (global
    /// frame, mm), `None` where it did not reach the image.
    pub sphere_points: Vec<Option<DVec3>>,
    /// The chief ray's image point (global frame, mm): the reference
    /// sphere's centre.
    pub chief_image: DVec3,
    /// The chief ray's direction in image space (unit).
    pub chief_direction: DVec3,
    /// The reference sphere's radius, mm: from the chief ray's image point
    /// to the paraxial exit pupil's centre (signed: negative when the exit
    /// pupil lies behind the image plane).
    pub reference_radius: f64,
    /// The paraxial exit pupil (`None` when image space is telecentric;
    /// the sphere then reaches back to the last vertex's plane along the
    /// chief ray).
    pub exit_pupil: Option<Pupil>,
    /// Index of image space.
    pub image_index: f64,
    /// Cells whose ray did not reach the image.
    pub vignetted: usize,
}

impl Wavefront {
    /// The cells whose ray reached the image: (normalised pupil point,
    /// cell area share, W in waves).
    pub fn passing(&self) -> impl Iterator<Item = ((f64, f64), f64, f64)> + '_ {
        self.grid.cells.iter().zip(&self.opd_waves).filter_map(|(c, w)| w.map(|w| (c.centre, c.area, w)))
    }

    /// The wavelength in mm.
    pub fn wavelength_mm(&self) -> f64 {
        self.wavelength_nm * 1e-6
    }
}

/// What turns normalised pupil points of one field into their wavefront
/// error: the launcher, the tracer to the image plane, the chief ray's path
/// to its reference sphere (made once, then asked for any points).
pub struct Probe<'a> {
    launcher: &'a Launcher,
    tracer: Tracer,
    vignetting: crate::model::spec::VignettingFactors,
    chief: Hit,
    s_chief: f64,
    radius: f64,
    n_obj: f64,
    n_img: f64,
    lambda: f64,
    /// z of the image plane, mm from the first vertex.
    pub image_z: f64,
    /// The paraxial exit pupil (`None`: telecentric image space).
    pub exit_pupil: Option<Pupil>,
}

impl<'a> Probe<'a> {
    /// The probe of `launcher`'s field traced through `traced` (the
    /// prescription at the wavelength analysed; `p` at its primary
    /// wavelength gives the image plane, the exit pupil and the design's
    /// vignetting factors) to `plane`. Errors when the chief ray is lost.
    pub fn new(
        p: &Prescription,
        traced: &Prescription,
        launcher: &'a Launcher,
        plane: ImagePlane,
    ) -> Result<Self, OpticsError> {
        let field = launcher.field();
        let image_z = plane.z(p, launcher)?;
        let tracer = Tracer::forward_to_film(traced, image_z - traced.last_vertex_z());
        let vignetting = launcher.vignetting(p)?;
        let chief = trace_chunk(launcher, &tracer, [(0.0, 0.0)].into_iter(), |e| e)?[0].ok_or_else(|| {
            OpticsError::ChiefRayLost {
                field: field.describe(),
                why: "the lens blocks it, or real aiming found no ray through the stop's centre".into(),
            }
        })?;
        let exit_pupil = launcher.first_order().exit_pupil;
        let c = chief.at;
        // the reference sphere: centre at the chief ray's image point,
        // through the paraxial exit pupil's centre (or, telecentric, back
        // along the chief ray to the last vertex's plane)
        let radius = match exit_pupil {
            Some(xp) => {
                let r = (c - DVec3::new(0.0, 0.0, xp.z)).length();
                if xp.z <= c.z {
                    r
                } else {
                    -r
                }
            }
            None => (c.z - traced.last_vertex_z()) / chief.direction.z,
        };
        if !(radius.is_finite() && radius != 0.0) {
            return Err(OpticsError::BadInput {
                name: "reference sphere radius",
                value: radius,
                expected: "an exit pupil away from the image plane",
            });
        }
        let mut probe = Probe {
            launcher,
            tracer,
            vignetting,
            chief,
            s_chief: 0.0,
            radius,
            n_obj: traced.index_before(0),
            n_img: traced.image_index(),
            lambda: traced.wavelength_nm() * 1e-6,
            image_z,
            exit_pupil,
        };
        probe.s_chief = probe.path(&chief).map(|(s, _)| s).ok_or_else(|| OpticsError::ChiefRayLost {
            field: field.describe(),
            why: "it does not meet its own reference sphere".into(),
        })?;
        Ok(probe)
    }

    /// The optical path of a ray to the reference sphere and where it
    /// meets it; for an object at infinity, from the plane wave through
    /// the chief ray's start. `None` where the ray misses the sphere.
    fn path(&self, e: &Hit) -> Option<(f64, DVec3)> {
        let q = e.at - self.chief.at;
        let b = q.dot(e.direction);
        let disc = b * b - (q.length_squared() - self.radius * self.radius);
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let t = if self.radius > 0.0 { b + disc.sqrt() } else { b - disc.sqrt() };
        let launch = match self.launcher.field() {
            Field::Angle(_) | Field::Angles { .. } => self.n_obj * e.launch_direction.dot(e.launch - self.chief.launch),
            Field::Height { .. } | Field::Point { .. } => 0.0,
        };
        Some((e.opl - self.n_img * t + launch, e.at - e.direction * t))
    }

    /// W in waves, and where the ray meets the reference sphere, at each
    /// normalised pupil point (the design's vignetting factors applied
    /// before launching); `None` where the ray does not reach the image.
    /// Traced in chunks on all cores.
    pub fn at(&self, points: &[(f64, f64)]) -> Result<Vec<Option<(f64, DVec3)>>, OpticsError> {
        self.each(points, |w, at| (w, at))
    }

    /// W in waves at each normalised pupil point, `None` where the ray does
    /// not reach the image ([`Self::at`] without the sphere points).
    pub fn opd(&self, points: &[(f64, f64)]) -> Result<Vec<Option<f64>>, OpticsError> {
        self.each(points, |w, _| w)
    }

    /// `keep` of each point's W (waves) and sphere point, in chunks on all
    /// cores, `None` where the ray does not reach the image.
    fn each<T: Send>(
        &self,
        points: &[(f64, f64)],
        keep: impl Fn(f64, DVec3) -> T + Sync,
    ) -> Result<Vec<Option<T>>, OpticsError> {
        let chunks: Vec<Result<Vec<Option<T>>, OpticsError>> = points
            .par_chunks(CHUNK)
            .map(|chunk| {
                let launched = chunk.iter().map(|&(x, y)| self.vignetting.apply(x, y));
                trace_chunk(self.launcher, &self.tracer, launched, |e| {
                    let (s, at) = self.path(&e?)?;
                    Some(keep((self.s_chief - s) / self.lambda, at))
                })
            })
            .collect();
        let mut out = Vec::with_capacity(points.len());
        for c in chunks {
            out.extend(c?);
        }
        Ok(out)
    }

    /// The chief ray's image point (global frame, mm).
    pub fn chief_image(&self) -> DVec3 {
        self.chief.at
    }

    /// The chief ray's image-space direction (unit).
    pub fn chief_direction(&self) -> DVec3 {
        self.chief.direction
    }

    /// The reference sphere's radius, mm (negative: the exit pupil lies
    /// behind the image plane).
    pub fn reference_radius(&self) -> f64 {
        self.radius
    }

    /// The index of image space.
    pub fn image_index(&self) -> f64 {
        self.n_img
    }

    /// The wavelength, mm.
    pub fn wavelength_mm(&self) -> f64 {
        self.lambda
    }

    /// The field.
    pub fn field(&self) -> Field {
        self.launcher.field()
    }
}

/// The wavefront of `launcher`'s field over an `n` x `n` pupil grid,
/// traced through `traced` (the prescription at the wavelength analysed;
/// `p` at its primary wavelength gives the image plane, the exit pupil and
/// the design's vignetting factors), on `plane`.
///
/// Errors: the chief ray lost, every ray vignetted, or a grid too coarse
/// for the wavefront ([`OpticsError::PupilUndersampled`], with a grid that
/// is fine enough).
pub fn wavefront(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    n: usize,
    plane: ImagePlane,
) -> Result<Wavefront, OpticsError> {
    if !(2..=MAX_GRID).contains(&n) {
        return Err(OpticsError::BadInput {
            name: "pupil grid",
            value: n as f64,
            expected: "a grid of 2 to 4096 samples across the pupil",
        });
    }
    let probe = Probe::new(p, traced, launcher, plane)?;
    let field = launcher.field();
    let grid = PupilGrid::new(n);
    let at = probe.at(&grid.points())?;
    let opd_waves: Vec<Option<f64>> = at.iter().map(|a| a.map(|a| a.0)).collect();
    let sphere_points: Vec<Option<DVec3>> = at.iter().map(|a| a.map(|a| a.1)).collect();
    let vignetted = opd_waves.iter().filter(|w| w.is_none()).count();
    if vignetted == opd_waves.len() {
        return Err(OpticsError::NoRealRays {
            why: format!("all {vignetted} rays of the pupil grid are vignetted at {}", field.describe()),
        });
    }
    let w = Wavefront {
        field,
        wavelength_nm: traced.wavelength_nm(),
        plane,
        image_z: probe.image_z,
        grid,
        opd_waves,
        sphere_points,
        chief_image: probe.chief_image(),
        chief_direction: probe.chief_direction(),
        reference_radius: probe.reference_radius(),
        exit_pupil: probe.exit_pupil,
        image_index: probe.image_index(),
        vignetted,
    };
    check_sampling(&w)?;
    Ok(w)
}

/// [`wavefront`] on the default grid ([`super::DEFAULT_GRID`]), or, where
/// the wavefront is too steep for it, on the grid its refusal suggests (up
/// to [`super::MAX_AUTO_GRID`] samples across; beyond, the refusal).
pub fn wavefront_auto(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
) -> Result<Wavefront, OpticsError> {
    let mut n = super::DEFAULT_GRID;
    loop {
        match wavefront(p, traced, launcher, n, plane) {
            Err(OpticsError::PupilUndersampled { suggest, .. }) if suggest > n && suggest <= super::MAX_AUTO_GRID => {
                n = suggest
            }
            r => return r,
        }
    }
}

/// The most samples across the pupil.
const MAX_GRID: usize = 4096;

/// Rays launched and traced together.
const CHUNK: usize = 1024;

/// A ray that reached the image plane: where and how it ended, its path
/// length, and where and how it started.
#[derive(Debug, Clone, Copy)]
struct Hit {
    at: DVec3,
    direction: DVec3,
    opl: f64,
    launch: DVec3,
    launch_direction: DVec3,
}

/// Launches and traces one chunk of pupil points (a batch kept by each
/// thread between calls), `keep` of each ray's end (`None` where it did not
/// reach the image) in order.
fn trace_chunk<T>(
    launcher: &Launcher,
    tracer: &Tracer,
    points: impl Iterator<Item = (f64, f64)>,
    mut keep: impl FnMut(Option<Hit>) -> T,
) -> Result<Vec<T>, OpticsError> {
    thread_local! {
        /// Each thread's batch and launch copy between calls.
        static SCRATCH: std::cell::RefCell<(RayBatch, Vec<(DVec3, DVec3)>)> = Default::default();
    }
    let run = |(batch, starts): &mut (RayBatch, Vec<(DVec3, DVec3)>)| {
        bundle::launch(launcher, points, batch)?;
        starts.clear();
        starts.extend((0..batch.len()).map(|i| {
            (DVec3::new(batch.x[i], batch.y[i], batch.z[i]), DVec3::new(batch.dx[i], batch.dy[i], batch.dz[i]))
        }));
        tracer.trace_soa(batch);
        Ok((0..batch.len())
            .map(|i| {
                keep((batch.status[i] == 0).then(|| Hit {
                    at: DVec3::new(batch.x[i], batch.y[i], batch.z[i]),
                    direction: DVec3::new(batch.dx[i], batch.dy[i], batch.dz[i]),
                    opl: batch.opl[i],
                    launch: starts[i].0,
                    launch_direction: starts[i].1,
                }))
            })
            .collect())
    };
    // a fresh batch where this thread's is in use (a nested call)
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut scratch) => run(&mut scratch),
        Err(_) => run(&mut Default::default()),
    })
}

/// Refuses a grid on which neighbouring samples differ by more than half
/// a wave, suggesting one on which they would not.
fn check_sampling(w: &Wavefront) -> Result<(), OpticsError> {
    let n = w.grid.n;
    let mut at = vec![None; n * n];
    for (c, opd) in w.grid.cells.iter().zip(&w.opd_waves) {
        at[c.row * n + c.column] = *opd;
    }
    let mut worst: f64 = 0.0;
    for row in 0..n {
        for col in 0..n {
            let Some(a) = at[row * n + col] else { continue };
            if let Some(Some(b)) = (col + 1 < n).then(|| at[row * n + col + 1]) {
                worst = worst.max((a - b).abs());
            }
            if let Some(Some(b)) = (row + 1 < n).then(|| at[(row + 1) * n + col]) {
                worst = worst.max((a - b).abs());
            }
        }
    }
    if worst > 0.5 {
        let suggest = ((n as f64 * worst / 0.4).ceil() as usize).next_power_of_two();
        return Err(OpticsError::PupilUndersampled { field: w.field.describe(), grid: n, waves: worst, suggest });
    }
    Ok(())
}
