//! Render passes for compositing: per pixel, what the camera's central ray
//! through the pixel's centre meets ([`Camera::central_rays`]: the
//! pinhole's ray, the thin lens's ray through its centre, a real lens's
//! chief ray). Depth, position and normal come from that one hit, unfiltered
//! (as compositors expect of a depth pass: a filtered depth mixes
//! foreground and background into a distance where nothing is); the circle
//! of confusion is the camera's blur of a point at the pixel's depth.
//!
//! Channels are named as compositors read them: `Z` (depth), `P.x P.y P.z`
//! (position), `N.x N.y N.z` (normal), `CoC`.

use crate::camera::Camera;
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;

/// One pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    /// `Z`: the distance along the optical axis (the camera's viewing
    /// direction) from the camera position to what the pixel sees, m;
    /// +infinity where it sees the background.
    Depth,
    /// `P.x P.y P.z`: the point the pixel sees, scene coordinates, m (0
    /// where it sees the background).
    Position,
    /// `N.x N.y N.z`: the unit geometric normal there, scene coordinates,
    /// facing out of the shape (0 where it sees the background).
    Normal,
    /// `CoC`: the full diameter, in pixels (of the film's width), of the
    /// blur the lens gives a point at the pixel's depth.
    Coc,
}

impl Pass {
    /// Every pass, in the order channels are listed.
    pub const ALL: [Pass; 4] = [Pass::Depth, Pass::Position, Pass::Normal, Pass::Coc];

    /// The pass's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Pass::Depth => "depth",
            Pass::Position => "position",
            Pass::Normal => "normal",
            Pass::Coc => "coc",
        }
    }

    /// Its EXR channel names.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Pass::Depth => &["Z"],
            Pass::Position => &["P.x", "P.y", "P.z"],
            Pass::Normal => &["N.x", "N.y", "N.z"],
            Pass::Coc => &["CoC"],
        }
    }

    /// A comma-separated list of pass names (`depth,coc`; `all`), each
    /// once.
    pub fn parse_list(s: &str) -> Result<Vec<Pass>, String> {
        let mut out = Vec::new();
        for word in s.split(',').map(str::trim) {
            if word.eq_ignore_ascii_case("all") {
                return Ok(Pass::ALL.to_vec());
            }
            let Some(p) = Pass::ALL.into_iter().find(|p| p.name().eq_ignore_ascii_case(word)) else {
                return Err(format!(
                    "unknown pass \"{word}\": give a comma-separated list of depth, position, normal, coc (or all)"
                ));
            };
            if !out.contains(&p) {
                out.push(p);
            }
        }
        Ok(out)
    }
}

/// Every pass of an image, pixel by pixel from the top left.
#[derive(Debug, Clone, PartialEq)]
pub struct Passes {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Depth along the axis, m (+infinity: background).
    pub depth: Vec<f64>,
    /// Position, m.
    pub position: Vec<DVec3>,
    /// Normal.
    pub normal: Vec<DVec3>,
    /// Circle of confusion, pixels.
    pub coc: Vec<f64>,
}

/// Why the passes could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PassError {
    /// The real lens's blur could not be measured.
    #[error("the circle-of-confusion pass: {0}")]
    Coc(#[from] lens::OpticsError),
}

/// Nodes of the real lens's blur table, spaced evenly in 1 / depth.
const COC_NODES: usize = 129;

impl Passes {
    /// The passes of `scene` (its film size, its camera).
    pub fn of(scene: &Scene) -> Result<Passes, PassError> {
        let (w, h) = (scene.film.width as usize, scene.film.height as usize);
        let camera = &scene.camera;
        let frame = camera.frame().copied();
        let rows: Vec<Vec<(f64, DVec3, DVec3)>> = (0..h)
            .into_par_iter()
            .map(|y| {
                let film: Vec<(f64, f64)> =
                    (0..w).map(|x| ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64)).collect();
                camera
                    .central_rays(&film)
                    .into_iter()
                    .map(|ray| {
                        let (Some(ray), Some(f)) = (ray, frame) else {
                            return (f64::INFINITY, DVec3::ZERO, DVec3::ZERO);
                        };
                        match scene.intersect(&ray, 1e-9, f64::INFINITY) {
                            Some((_, hit)) => ((hit.p - f.origin).dot(f.forward), hit.p, hit.n),
                            None => (f64::INFINITY, DVec3::ZERO, DVec3::ZERO),
                        }
                    })
                    .collect()
            })
            .collect();
        let flat: Vec<(f64, DVec3, DVec3)> = rows.into_iter().flatten().collect();
        let depth: Vec<f64> = flat.iter().map(|t| t.0).collect();
        let coc = coc_pixels(camera, &depth, w, h)?;
        Ok(Passes {
            width: w,
            height: h,
            position: flat.iter().map(|t| t.1).collect(),
            normal: flat.iter().map(|t| t.2).collect(),
            depth,
            coc,
        })
    }

    /// The channels of `which`, named, as 32-bit floats (what an EXR file
    /// holds).
    pub fn channels(&self, which: &[Pass]) -> Vec<(&'static str, Vec<f32>)> {
        let mut out = Vec::new();
        let comp = |v: &[DVec3], k: usize| v.iter().map(|p| p[k] as f32).collect::<Vec<f32>>();
        for p in which {
            match p {
                Pass::Depth => out.push(("Z", self.depth.iter().map(|&z| z as f32).collect())),
                Pass::Position => {
                    for (k, name) in p.channels().iter().enumerate() {
                        out.push((*name, comp(&self.position, k)));
                    }
                }
                Pass::Normal => {
                    for (k, name) in p.channels().iter().enumerate() {
                        out.push((*name, comp(&self.normal, k)));
                    }
                }
                Pass::Coc => out.push(("CoC", self.coc.iter().map(|&c| c as f32).collect())),
            }
        }
        out
    }
}

/// The circle of confusion, pixels, of a point at each depth (m along the
/// axis from the camera position): 0 through a pinhole; through a thin
/// lens of aperture radius R focused at s, the cone's width on the film,
/// 2R |1/Z - 1/s| in units of the tangent of the view angle, turned into
/// pixels (height / (2 tan(fov / 2)) of them per unit; its glass's d-line
/// focus, without the focus-shift trick); through a real lens, the real
/// on-axis bundle's full blur diameter at that distance from the lens
/// crate's circle of confusion (its off-axis aberrations left out),
/// tabulated at [`COC_NODES`] depths evenly spaced in 1 / depth over the
/// image's range (the focus among them, where the blur has its kink) and
/// interpolated linearly in 1 / depth. A pixel that sees the background
/// has the blur of infinity; one with no central ray, 0.
fn coc_pixels(camera: &Camera, depth: &[f64], w: usize, h: usize) -> Result<Vec<f64>, PassError> {
    match camera {
        Camera::Pinhole { .. } => Ok(vec![0.0; depth.len()]),
        Camera::ThinLens { tan_half, radius, focus, .. } => {
            let per_tan = h as f64 / (2.0 * tan_half);
            Ok(depth.iter().map(|&z| 2.0 * radius * (1.0 / z - 1.0 / focus).abs() * per_tan).collect())
        }
        Camera::Real(c) => {
            let per_mm = w as f64 / c.sensor_mm()[0];
            // the image's range in 1 / depth, in front of the lens
            let front = c.front_distance_m();
            let inv: Vec<f64> = depth.iter().filter(|&&z| z > front).map(|&z| 1.0 / z).collect();
            if inv.is_empty() {
                return Ok(vec![0.0; depth.len()]);
            }
            let lo = inv.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = inv.iter().copied().fold(0.0, f64::max);
            let mut nodes: Vec<f64> =
                (0..COC_NODES).map(|k| lo + (hi - lo) * k as f64 / (COC_NODES - 1) as f64).collect();
            let focus = 1.0 / c.focus_distance_m();
            if focus > lo && focus < hi {
                nodes.push(focus);
            }
            nodes.sort_by(f64::total_cmp);
            nodes.dedup();
            let distances: Vec<f64> = nodes.iter().map(|&i| if i > 0.0 { 1.0 / i } else { f64::INFINITY }).collect();
            let blur: Vec<f64> = c.blur_diameters_mm(&distances)?.into_iter().map(|d| d.unwrap_or(0.0)).collect();
            Ok(depth
                .iter()
                .map(|&z| {
                    if z.is_nan() || z <= front {
                        return 0.0;
                    }
                    per_mm * interpolate(&nodes, &blur, 1.0 / z)
                })
                .collect())
        }
    }
}

/// Linear interpolation of `ys` over the increasing `xs` at `x` (clamped
/// to the ends).
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let k = xs.partition_point(|&v| v < x);
    if k == 0 {
        return ys[0];
    }
    if k >= xs.len() {
        return ys[xs.len() - 1];
    }
    let (x0, x1) = (xs[k - 1], xs[k]);
    let t = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[k - 1] + (ys[k] - ys[k - 1]) * t
}
