//! Cameras: a pinhole, a thin lens and a real lens prescription. Each maps a
//! film position (u, v in [0, 1], v down) and two aperture uniforms to a
//! scene ray and a weight (0 when the ray is blocked inside the lens).

pub mod aperture;
pub mod pupil;
pub mod real_lens;

use crate::geometry::Ray;
use crate::spectrum::sampled::N;
use crate::spectrum::SampledWavelengths;
use aperture::Aperture;
use glam::DVec3;

/// Why a camera could not be built. The lens crate's error is kept as the
/// source.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// The look-at point equals the position.
    #[error("camera look_at equals position: move one of them")]
    LookAtPosition,
    /// The up direction is parallel to the viewing direction.
    #[error("camera up is parallel to the viewing direction: change up")]
    UpParallel,
    /// A sensor size that is not two positive lengths.
    #[error("sensor_mm = [{width}, {height}]: give two positive sizes in mm")]
    Sensor {
        /// Width, mm.
        width: f64,
        /// Height, mm.
        height: f64,
    },
    /// The lens cannot be focused or set up as asked.
    #[error(transparent)]
    Optics(#[from] lens::OpticsError),
    /// No ray from the film centre passes the lens.
    #[error("no ray from the film centre passes the lens: check the stop and clear apertures")]
    NoLight,
}

/// One camera sample: a film position (u, v in [0, 1], v down), two
/// aperture uniforms in [0, 1), and the wavelength its path carries through
/// a dispersive lens (`None`: RGB, the lens at its primary wavelength).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSample {
    /// Film position (u, v).
    pub film: (f64, f64),
    /// Aperture uniforms.
    pub aperture: (f64, f64),
    /// Wavelength, nm.
    pub wavelength_nm: Option<f64>,
}

impl CameraSample {
    /// An RGB sample.
    pub fn new(film: (f64, f64), aperture: (f64, f64)) -> Self {
        CameraSample { film, aperture, wavelength_nm: None }
    }
}

/// One wavelength of a spectral camera sample: where the film-side ray
/// that leaves the lens as the sample's scene ray at this wavelength
/// starts, the stop's transmission along it, and the density (relative to
/// the measure of scene rays, normalised like the weights) with which the
/// camera would have drawn that scene ray had this wavelength been the
/// hero. The render combines the wavelengths by the balance heuristic over
/// these densities (docs/rendering.md), so a dispersive lens keeps all four
/// wavelengths of a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralLane {
    /// Film position (u, v) at this wavelength.
    pub film: (f64, f64),
    /// The stop's transmission (1 for a round stop; 0: blocked).
    pub transmission: f64,
    /// 1 / the camera weight: the density of drawing this scene ray
    /// (0: blocked at this wavelength).
    pub density: f64,
}

impl SpectralLane {
    /// A wavelength the lens blocks.
    pub const BLOCKED: SpectralLane = SpectralLane { film: (f64::NAN, f64::NAN), transmission: 0.0, density: 0.0 };
}

/// A thin lens's glass: its focal length at each wavelength from the
/// glass's dispersion (thin-lens lensmaker: f(λ) (n(λ) - 1) is constant),
/// with the film where the d line focuses.
#[derive(Debug, Clone, PartialEq)]
pub struct ThinGlass {
    /// The glass.
    pub glass: std::sync::Arc<lens::glass::PreparedIndex>,
    /// Its index at the d line.
    pub nd: f64,
    /// Focal length at the d line, m.
    pub focal_length: f64,
    /// Lens to film, m.
    pub film_distance: f64,
}

impl ThinGlass {
    /// 1 / (distance to the plane in focus) at `nm`, 1/m (0: infinity;
    /// negative: no real plane is sharp).
    pub fn inverse_focus(&self, nm: f64) -> f64 {
        let n = self.glass.index(nm).unwrap_or(self.nd);
        (n - 1.0) / ((self.nd - 1.0) * self.focal_length) - 1.0 / self.film_distance
    }
}

/// An orthonormal camera frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Position, m.
    pub origin: DVec3,
    /// Viewing direction.
    pub forward: DVec3,
    /// Image right.
    pub right: DVec3,
    /// Image up.
    pub up: DVec3,
}

impl Frame {
    /// From a position, a look-at point and an up hint. Errors when the
    /// directions are degenerate.
    pub fn look_at(position: DVec3, target: DVec3, up: DVec3) -> Result<Self, CameraError> {
        let forward = (target - position).try_normalize().ok_or(CameraError::LookAtPosition)?;
        let right = forward.cross(up).try_normalize().ok_or(CameraError::UpParallel)?;
        Ok(Frame { origin: position, forward, right, up: right.cross(forward) })
    }
}

/// A camera.
#[derive(Debug, Clone)]
pub enum Camera {
    /// Ideal pinhole.
    Pinhole {
        /// Frame.
        frame: Frame,
        /// tan(vertical fov / 2).
        tan_half: f64,
        /// Width / height.
        aspect: f64,
    },
    /// Cook-style thin lens.
    ThinLens {
        /// Frame (the lens centre).
        frame: Frame,
        /// tan(vertical fov / 2).
        tan_half: f64,
        /// Width / height.
        aspect: f64,
        /// Aperture radius, m.
        radius: f64,
        /// Distance to the plane in focus, m.
        focus: f64,
        /// Aperture shape.
        aperture: Aperture,
        /// Focal shortening at the rim (fraction).
        focus_shift: f64,
        /// A glass: focus follows the wavelength.
        glass: Option<ThinGlass>,
    },
    /// Real lens.
    Real(Box<real_lens::RealLensCamera>),
}

impl Camera {
    /// Whether rays depend on wavelength (a real lens or thin lens with
    /// glass).
    pub fn is_dispersive(&self) -> bool {
        match self {
            Camera::Pinhole { .. } => false,
            Camera::ThinLens { glass, .. } => glass.is_some(),
            Camera::Real(c) => c.prescription().is_dispersive(),
        }
    }

    /// The glasses whose data bound the wavelengths a render may use.
    pub fn glasses(&self) -> Vec<&lens::glass::Glass> {
        match self {
            Camera::Pinhole { .. } => vec![],
            Camera::ThinLens { glass, .. } => glass.iter().map(|g| g.glass.glass()).collect(),
            Camera::Real(c) => c.prescription().glasses().iter().collect(),
        }
    }

    /// The camera ray through film position (u, v) with aperture sample
    /// `a`, and its weight (RGB: the lens at its primary wavelength).
    pub fn ray(&self, u: f64, v: f64, a: (f64, f64)) -> Option<(Ray, f64)> {
        self.ray_at(u, v, a, None)
    }

    /// [`Self::ray`] at wavelength `nm` (`None`: the primary).
    pub fn ray_at(&self, u: f64, v: f64, a: (f64, f64), nm: Option<f64>) -> Option<(Ray, f64)> {
        match self {
            Camera::Pinhole { frame, tan_half, aspect } => {
                let d = pinhole_dir(frame, *tan_half, *aspect, u, v);
                Some((Ray { origin: frame.origin, dir: d }, 1.0))
            }
            Camera::ThinLens { frame, tan_half, aspect, radius, focus, aperture, focus_shift, glass } => {
                let d = pinhole_dir(frame, *tan_half, *aspect, u, v);
                if *radius == 0.0 {
                    return Some((Ray { origin: frame.origin, dir: d }, 1.0));
                }
                let (ax, ay) = aperture.sample(a);
                let rho = (ax * ax + ay * ay).sqrt();
                let inv_focus = match (glass, nm) {
                    (Some(g), Some(nm)) => g.inverse_focus(nm),
                    _ => 1.0 / focus,
                };
                // the study's trick: focus nearer for samples far from the centre
                let inv_focus = inv_focus / (1.0 - focus_shift * rho);
                // a thin lens bends the ray through aperture point a by
                // -a / s: toward the point of the plane in focus (distance
                // s) that the central ray meets, or away from a virtual one
                let offset = frame.right * (ax * radius) + frame.up * (ay * radius);
                let dir = (d / d.dot(frame.forward) - offset * inv_focus).normalize();
                Some((Ray { origin: frame.origin + offset, dir }, 1.0))
            }
            Camera::Real(c) => c.ray_at(u, v, a, nm),
        }
    }

    /// The camera rays of samples that carry four wavelengths each (the
    /// hero is `samples[k].wavelength_nm`, `wavelengths[k].nm[0]`), with
    /// each wavelength's [`SpectralLane`]. A camera whose rays do not
    /// depend on wavelength gives every wavelength the hero's lane (its
    /// weight as the transmission, density 1).
    pub fn rays_spectral(
        &self,
        samples: &[CameraSample],
        wavelengths: &[SampledWavelengths],
        out: &mut Vec<Option<(Ray, [SpectralLane; N])>>,
    ) {
        match self {
            Camera::Real(c) if c.prescription().is_dispersive() => c.rays_spectral(samples, wavelengths, out),
            Camera::ThinLens { frame, tan_half, aspect, radius, aperture, focus_shift, glass: Some(g), .. } => {
                out.clear();
                for (s, wl) in samples.iter().zip(wavelengths) {
                    let d = pinhole_dir(frame, *tan_half, *aspect, s.film.0, s.film.1);
                    let chief = d / d.dot(frame.forward);
                    let (ax, ay) = if *radius > 0.0 { aperture.sample(s.aperture) } else { (0.0, 0.0) };
                    let shift = 1.0 - focus_shift * (ax * ax + ay * ay).sqrt();
                    let offset = frame.right * (ax * radius) + frame.up * (ay * radius);
                    // the hero's ray as `ray_at` makes it; then the central
                    // ray of each wavelength that leaves along it: its slope
                    // plus the bend the lens gives it there
                    let slope = chief - offset * (g.inverse_focus(wl.nm[0]) / shift);
                    let mut lanes = [SpectralLane { film: s.film, transmission: 1.0, density: 1.0 }; N];
                    for (lane, nm) in lanes.iter_mut().zip(&wl.nm).skip(1) {
                        let c = slope + offset * (g.inverse_focus(*nm) / shift);
                        lane.film = (
                            0.5 + 0.5 * c.dot(frame.right) / (tan_half * aspect),
                            0.5 - 0.5 * c.dot(frame.up) / tan_half,
                        );
                    }
                    out.push(Some((Ray { origin: frame.origin + offset, dir: slope.normalize() }, lanes)));
                }
            }
            _ => {
                let mut plain = Vec::with_capacity(samples.len());
                self.rays(samples, &mut plain);
                out.clear();
                out.extend(plain.into_iter().zip(samples).map(|(r, s)| {
                    r.map(|(ray, w)| (ray, [SpectralLane { film: s.film, transmission: w, density: 1.0 }; N]))
                }));
            }
        }
    }

    /// The camera rays of a batch of samples, with their weights (`None`
    /// where the lens blocks the ray): a real lens traces them all as one
    /// batch through the lens crate's batch tracer.
    pub fn rays(&self, samples: &[CameraSample], out: &mut Vec<Option<(Ray, f64)>>) {
        match self {
            Camera::Real(c) => c.rays(samples, out),
            _ => {
                out.clear();
                out.extend(samples.iter().map(|s| self.ray_at(s.film.0, s.film.1, s.aperture, s.wavelength_nm)));
            }
        }
    }
}

/// The pinhole direction through film position (u, v).
fn pinhole_dir(f: &Frame, tan_half: f64, aspect: f64, u: f64, v: f64) -> DVec3 {
    let sx = (2.0 * u - 1.0) * tan_half * aspect;
    let sy = (1.0 - 2.0 * v) * tan_half;
    (f.forward + f.right * sx + f.up * sy).normalize()
}
