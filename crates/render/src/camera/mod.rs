//! Cameras: a pinhole, a thin lens and a real lens prescription. Each maps a
//! film position (u, v in [0, 1], v down) and two aperture uniforms to a
//! scene ray and a weight (0 when the ray is blocked inside the lens).

pub mod aperture;
pub mod diffraction;
pub mod flare;
pub mod lamp_light;
pub mod pupil;
pub mod real_lens;
pub mod sky_patches;

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
    /// The lens has decentred or tilted surfaces, which the real-lens
    /// camera does not render yet.
    #[error(
        "the lens has decentred or tilted surfaces (decenter_mm, tilt_deg or elements): the real-lens camera's \
         exit-pupil bounds assume a lens symmetric about its axis, so it renders co-axial lenses only; remove the \
         motions to render this lens (the lens analyses take them)"
    )]
    Tilted,
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

/// Camera-side sampling of small lamps through a thin lens's aperture: a
/// lamp behind or in front of the plane in focus is seen from a film point
/// through a small patch of the aperture (the lamp's cone from the point of
/// the plane in focus that the film point sees, cut by the lens plane);
/// uniform aperture samples rarely land there, so a defocused lamp comes
/// out as speckles. A share of the samples is drawn in those cones instead,
/// and every sample is weighted by the balance heuristic over the mixture
/// of both ways of drawing, so the estimate stays unbiased.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LampAim {
    /// Centre and radius of each lamp, m.
    pub lamps: Vec<(DVec3, f64)>,
    /// The share of samples aimed at lamps (0: off).
    pub share: f64,
}

/// The most lamps aimed at.
pub const MAX_AIMED_LAMPS: usize = 64;

impl LampAim {
    /// Lamp aiming for a thin lens with `aperture` and `focus_shift`: on
    /// for round and polygonal apertures without focus shift.
    pub fn new(lamps: Vec<(DVec3, f64)>, aperture: &Aperture, focus_shift: f64) -> Self {
        let usable = matches!(aperture, Aperture::Circle | Aperture::Polygon { .. })
            && focus_shift == 0.0
            && !lamps.is_empty()
            && lamps.len() <= MAX_AIMED_LAMPS;
        if usable {
            LampAim { lamps, share: 0.5 }
        } else {
            LampAim::default()
        }
    }

    /// The lamps that can be seen from the plane-in-focus point `p` through
    /// the lens (centre `origin`, axis `forward`, radius `radius`): those
    /// whose cone from `p` meets the cone from `p` to the lens's bounding
    /// disc (on either side of `p`). Only they are aimed at from `p`.
    fn visible(&self, p: DVec3, origin: DVec3, radius: f64) -> ([u8; MAX_AIMED_LAMPS], usize) {
        let mut out = [0u8; MAX_AIMED_LAMPS];
        let mut n = 0;
        let to_lens = origin - p;
        let lens_dist = to_lens.length();
        if lens_dist <= radius {
            // p at the lens: every lamp
            for (k, o) in out.iter_mut().enumerate().take(self.lamps.len()) {
                *o = k as u8;
            }
            return (out, self.lamps.len());
        }
        let lens_axis = to_lens / lens_dist;
        // sine and cosine of the lens's half angle from p
        let (sl, cl) = (radius / lens_dist, (1.0 - (radius / lens_dist).powi(2)).max(0.0).sqrt());
        for (k, &(c, r)) in self.lamps.iter().enumerate() {
            let axis = c - p;
            let d = axis.length();
            if d <= r {
                continue;
            }
            let (sh, ch) = (r / d, (1.0 - (r / d) * (r / d)).max(0.0).sqrt());
            // the lines' angle is within the two half angles: compare
            // cosines, cos(h + l) = cos h cos l - sin h sin l (h + l < pi)
            let cos = (axis.dot(lens_axis) / d).abs();
            if cos >= ch * cl - sh * sl {
                out[n] = k as u8;
                n += 1;
            }
        }
        (out, n)
    }

    /// The density (per lens-plane area, m^-2) with which lamp aiming draws
    /// the lens point `a` for the plane-in-focus point `p`, aiming at the
    /// lamps `which`: the mean over them of the uniform cone density
    /// turned into area.
    fn density(&self, p: DVec3, a: DVec3, forward: DVec3, which: &[u8]) -> f64 {
        let to_a = a - p;
        let dist2 = to_a.length_squared();
        if dist2 <= 0.0 {
            return 0.0;
        }
        let dir = to_a / dist2.sqrt();
        let cos_plane = dir.dot(forward).abs();
        let mut sum = 0.0;
        for &k in which {
            let (c, r) = self.lamps[k as usize];
            let axis = c - p;
            let d = axis.length();
            if d <= r {
                continue;
            }
            let cos_max = (1.0 - (r / d) * (r / d)).max(0.0).sqrt();
            // the line through p and a meets the lamp on either side of p
            let cos = dir.dot(axis) / d;
            if cos.abs() >= cos_max {
                let solid = std::f64::consts::TAU * (1.0 - cos_max);
                sum += cos_plane / (dist2 * solid);
            }
        }
        sum / which.len() as f64
    }
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
        /// Small emissive spheres (centre, radius, m) that half of the
        /// samples aim at through the aperture (empty: none; see
        /// [`LampAim`]).
        lamps: LampAim,
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

    /// The camera's pose (for a real lens, the film's frame).
    pub fn frame(&self) -> Option<&Frame> {
        match self {
            Camera::Pinhole { frame, .. } | Camera::ThinLens { frame, .. } => Some(frame),
            Camera::Real(c) => Some(c.frame()),
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
            Camera::ThinLens { frame, tan_half, aspect, radius, focus, aperture, focus_shift, glass, lamps } => {
                let d = pinhole_dir(frame, *tan_half, *aspect, u, v);
                if *radius == 0.0 {
                    return Some((Ray { origin: frame.origin, dir: d }, 1.0));
                }
                if lamps.share > 0.0 && glass.is_none() {
                    return thin_lens_aimed(frame, d, *radius, *focus, aperture, lamps, a);
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

    /// Whether [`Self::rays_spectral`]'s companions cost a trace of their
    /// own (a real lens with glasses), so that a render may ask for them
    /// only where it needs them: [`Self::heroes`], then
    /// [`Self::companions`].
    pub fn companions_cost_a_trace(&self) -> bool {
        matches!(self, Camera::Real(c) if c.prescription().is_dispersive())
    }

    /// The heroes of [`Self::rays_spectral`] (the companions' lanes
    /// blocked) where [`Self::companions_cost_a_trace`]; otherwise all of
    /// it.
    pub fn heroes(
        &self,
        samples: &[CameraSample],
        wavelengths: &[SampledWavelengths],
        out: &mut Vec<Option<(Ray, [SpectralLane; N])>>,
    ) {
        match self {
            Camera::Real(c) if c.prescription().is_dispersive() => c.heroes(samples, out),
            _ => self.rays_spectral(samples, wavelengths, out),
        }
    }

    /// The companions' lanes of the samples `selected`, after
    /// [`Self::heroes`] (nothing to do where they came with the heroes).
    pub fn companions(
        &self,
        wavelengths: &[SampledWavelengths],
        out: &mut [Option<(Ray, [SpectralLane; N])>],
        selected: &[usize],
    ) {
        if let Camera::Real(c) = self {
            if c.prescription().is_dispersive() {
                c.companions(wavelengths, out, selected);
            }
        }
    }

    /// The central ray through each film position (u, v in [0, 1], v
    /// down): the pinhole's ray, the thin lens's ray through its centre
    /// (it is not bent), a real lens's chief ray (through the centre of
    /// its stop, at its primary wavelength). What a pixel "looks at" for
    /// the render passes and autofocus; `None` where no such ray leaves
    /// the lens.
    pub fn central_rays(&self, film: &[(f64, f64)]) -> Vec<Option<Ray>> {
        match self {
            Camera::Pinhole { frame, tan_half, aspect } | Camera::ThinLens { frame, tan_half, aspect, .. } => film
                .iter()
                .map(|&(u, v)| Some(Ray { origin: frame.origin, dir: pinhole_dir(frame, *tan_half, *aspect, u, v) }))
                .collect(),
            Camera::Real(c) => c.chief_rays(film),
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

/// A thin-lens ray drawn from the mixture of uniform aperture sampling and
/// lamp aiming (`lamps.share` of the samples, the first uniform choosing),
/// weighted by the uniform density over the mixture's (the balance
/// heuristic): `d` is the central ray's direction, the plane in focus
/// `focus` m away.
fn thin_lens_aimed(
    frame: &Frame,
    d: DVec3,
    radius: f64,
    focus: f64,
    aperture: &Aperture,
    lamps: &LampAim,
    a: (f64, f64),
) -> Option<(Ray, f64)> {
    let p = frame.origin + d * (focus / d.dot(frame.forward));
    let (which, n) = lamps.visible(p, frame.origin, radius);
    let which = &which[..n];
    // aim only where a lamp can be seen from p
    let q = if n > 0 { lamps.share } else { 0.0 };
    let lens_point = if a.0 < q {
        // a lamp, then a direction in its cone from p, to the lens plane
        let u = a.0 / q * n as f64;
        let j = (u as usize).min(n - 1);
        let k = which[j] as usize;
        let (c, r) = lamps.lamps[k];
        let axis = c - p;
        let dist = axis.length();
        if dist <= r {
            return None;
        }
        let w = axis / dist;
        let cos_max = (1.0 - (r / dist) * (r / dist)).max(0.0).sqrt();
        let cos = 1.0 - (u - j as f64) * (1.0 - cos_max);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = std::f64::consts::TAU * a.1;
        let (t, b) = crate::material::basis(w);
        let dir = w * cos + (t * phi.cos() + b * phi.sin()) * sin;
        let along = dir.dot(frame.forward);
        if along.abs() < 1e-12 {
            return None;
        }
        // p + s dir on the lens plane
        let s = -(p - frame.origin).dot(frame.forward) / along;
        p + dir * s
    } else {
        let (ax, ay) = aperture.sample(((a.0 - q) / (1.0 - q), a.1));
        frame.origin + frame.right * (ax * radius) + frame.up * (ay * radius)
    };
    let off = lens_point - frame.origin;
    let (ax, ay) = (off.dot(frame.right) / radius, off.dot(frame.up) / radius);
    if !aperture.contains(ax, ay) {
        return None;
    }
    let uniform = 1.0 / (aperture.unit_area() * radius * radius);
    let mixture =
        (1.0 - q) * uniform + if q > 0.0 { q * lamps.density(p, lens_point, frame.forward, which) } else { 0.0 };
    let dir = (p - lens_point).normalize();
    Some((Ray { origin: lens_point, dir }, uniform / mixture))
}

/// The pinhole direction through film position (u, v).
fn pinhole_dir(f: &Frame, tan_half: f64, aspect: f64, u: f64, v: f64) -> DVec3 {
    let sx = (2.0 * u - 1.0) * tan_half * aspect;
    let sy = (1.0 - 2.0 * v) * tan_half;
    (f.forward + f.right * sx + f.up * sy).normalize()
}
