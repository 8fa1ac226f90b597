//! Settings that override a scene file's film and camera (the command
//! line's `--width`, `--camera`, `--f-number`, ...), applied to the file as
//! written before it is built, so they are checked exactly as the file's own
//! fields are. Switching the camera's type carries what it can: a real lens
//! becomes the thin lens matched to it (its focal length, f-number, focus
//! and field of view), a thin lens with a focal length becomes a real lens
//! with a sensor of the same field of view.

use super::format::{ApertureSpec, CameraSpec, FocusOn, SceneFile};
use std::path::{Path, PathBuf};

/// A camera type to switch to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraKind {
    /// A pinhole.
    Pinhole,
    /// A thin lens.
    ThinLens,
    /// A real lens (needs a prescription: the scene's or `prescription`).
    Lens,
}

/// What to override; `None` keeps the file's value.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overrides {
    /// Film width, pixels (alone: the height follows the file's aspect).
    pub width: Option<u32>,
    /// Film height, pixels (alone: the width follows the file's aspect).
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// The camera's type.
    pub camera: Option<CameraKind>,
    /// Thin-lens aperture diameter, m.
    pub aperture: Option<f64>,
    /// f-number (thin lens with a focal length, or a real lens).
    pub f_number: Option<f64>,
    /// Thin-lens focal length, mm.
    pub focal_length_mm: Option<f64>,
    /// Distance to the plane in focus, m (replaces the file's autofocus).
    pub focus_distance: Option<f64>,
    /// Autofocus on a pixel or a named shape (replaces the file's focus
    /// distance).
    pub focus_on: Option<FocusOn>,
    /// The thin lens's `focus_shift`.
    pub focus_shift: Option<f64>,
    /// Aperture shape.
    pub aperture_shape: Option<ApertureSpec>,
    /// A real lens's prescription file (relative to the working folder).
    pub prescription: Option<PathBuf>,
    /// Refuse wavelengths outside a glass's data instead of extrapolating
    /// (a spectral render's range narrowed to every glass's data).
    pub strict_glass_range: bool,
    /// Lens flare (`film.flare`).
    pub flare: Option<super::format::FlareSpec>,
    /// Every surface's coating of a real lens (`camera.coating`).
    pub coating: Option<lens::model::CoatingSpec>,
    /// Diffraction at the aperture (`film.diffraction`).
    pub diffraction: Option<super::format::DiffractionSpec>,
}

/// A field name and what is wrong with it.
type Problem = (String, String);

impl Overrides {
    /// Parses an aperture shape written `circle`, `polygon:N[:ROT_DEG]` or
    /// `mask:FILE.png`.
    pub fn parse_shape(s: &str) -> Result<ApertureSpec, String> {
        let parts: Vec<&str> = s.split(':').collect();
        let bad = || format!("{s}: write circle, polygon:BLADES[:ROTATION_DEG] or mask:FILE.png");
        match parts.as_slice() {
            ["circle"] => Ok(ApertureSpec::Circle),
            ["polygon", n] | ["polygon", n, _] => {
                let blades = n.parse().map_err(|_| bad())?;
                let rotation_deg = match parts.get(2) {
                    Some(r) => r.parse().map_err(|_| bad())?,
                    None => 0.0,
                };
                Ok(ApertureSpec::Polygon { blades, rotation_deg })
            }
            ["mask", file] if !file.is_empty() => Ok(ApertureSpec::Mask { image: file.to_string() }),
            _ => Err(bad()),
        }
    }

    /// Applies the overrides to `file` (whose relative paths resolve
    /// against `dir`). Errors name the flag's field.
    pub fn apply(&self, file: &mut SceneFile, dir: &Path) -> Result<(), Problem> {
        // one side alone keeps the file's aspect (the sensor's is fixed:
        // changing one side only would stretch the picture)
        let (w0, h0) = (file.film.width.max(1) as f64, file.film.height.max(1) as f64);
        let scaled = |side: u32, ratio: f64| ((side as f64 * ratio).round() as u32).max(1);
        match (self.width, self.height) {
            (Some(w), Some(h)) => (file.film.width, file.film.height) = (w, h),
            (Some(w), None) => (file.film.width, file.film.height) = (w, if w == 0 { 0 } else { scaled(w, h0 / w0) }),
            (None, Some(h)) => (file.film.width, file.film.height) = (if h == 0 { 0 } else { scaled(h, w0 / h0) }, h),
            (None, None) => {}
        }
        if let Some(f) = self.flare {
            file.film.flare = f;
        }
        if let Some(d) = self.diffraction {
            file.film.diffraction = d;
        }
        if let Some(s) = self.spp {
            file.film.spp = s;
        }
        let aspect = file.film.width as f64 / file.film.height.max(1) as f64;
        if let Some(kind) = self.camera {
            file.camera = self.switch(&file.camera, kind, aspect, dir)?;
        }
        let field = |f: &str| format!("camera.{f}");
        match &mut file.camera {
            CameraSpec::Pinhole { .. } => {
                let flags = [
                    ("aperture", self.aperture.is_some()),
                    ("f_number", self.f_number.is_some()),
                    ("focal_length_mm", self.focal_length_mm.is_some()),
                    ("focus_distance", self.focus_distance.is_some()),
                    ("focus_on", self.focus_on.is_some()),
                    ("focus_shift", self.focus_shift.is_some()),
                    ("aperture_shape", self.aperture_shape.is_some()),
                    ("prescription", self.prescription.is_some()),
                    ("coating", self.coating.is_some()),
                ];
                if let Some((f, _)) = flags.iter().find(|(_, given)| *given) {
                    return Err((field(f), "a pinhole has no lens: choose --camera thin-lens or lens".into()));
                }
            }
            CameraSpec::ThinLens { aperture, f_number, focal_length_mm, aperture_shape, focus_shift, .. } => {
                if self.prescription.is_some() || self.coating.is_some() {
                    let f = if self.prescription.is_some() { "prescription" } else { "coating" };
                    return Err((field(f), "a thin lens has no prescription: add --camera lens".into()));
                }
                if let Some(a) = self.aperture {
                    *aperture = Some(a);
                    *f_number = None;
                }
                if let Some(n) = self.f_number {
                    *f_number = Some(n);
                    *aperture = None;
                }
                if let Some(f) = self.focal_length_mm {
                    *focal_length_mm = Some(f);
                }
                if let Some(s) = self.focus_shift {
                    *focus_shift = s;
                }
                if let Some(s) = self.shape() {
                    *aperture_shape = s;
                }
            }
            CameraSpec::Lens { prescription, f_number, stop_semi_diameter, aperture_shape, coating, .. } => {
                if let Some(c) = &self.coating {
                    *coating = Some(c.clone());
                }
                if self.aperture.is_some() || self.focal_length_mm.is_some() || self.focus_shift.is_some() {
                    let f = if self.aperture.is_some() {
                        "aperture"
                    } else if self.focal_length_mm.is_some() {
                        "focal_length_mm"
                    } else {
                        "focus_shift"
                    };
                    return Err((
                        field(f),
                        "a real lens takes its focal length and aperture from its prescription: give --f-number, or --camera thin-lens".into(),
                    ));
                }
                if let Some(p) = &self.prescription {
                    *prescription = absolute(p).display().to_string();
                    // the scene's stop setting was for its own lens: the new
                    // one keeps its own unless --f-number is given
                    *f_number = None;
                    *stop_semi_diameter = None;
                }
                if let Some(n) = self.f_number {
                    *f_number = Some(n);
                    *stop_semi_diameter = None;
                }
                if let Some(s) = self.shape() {
                    *aperture_shape = s;
                }
            }
        }
        if let Some(d) = self.focus_distance {
            file.camera.set_focus(Some(d), None);
        } else if let Some(on) = &self.focus_on {
            file.camera.set_focus(None, Some(on.clone()));
        }
        Ok(())
    }

    /// The aperture shape asked for, a mask's file made absolute against
    /// the working folder.
    fn shape(&self) -> Option<ApertureSpec> {
        self.aperture_shape.clone().map(|s| match s {
            ApertureSpec::Mask { image } => {
                ApertureSpec::Mask { image: absolute(Path::new(&image)).display().to_string() }
            }
            other => other,
        })
    }

    /// The camera `c` as a camera of type `kind`, carrying what it can.
    fn switch(&self, c: &CameraSpec, kind: CameraKind, aspect: f64, dir: &Path) -> Result<CameraSpec, Problem> {
        let pose = c.pose();
        let (position, look_at, up) = (pose.position, pose.look_at, pose.up);
        // what the current camera says: its vertical field of view, focal
        // length, f-number and focus distance (when it has them)
        let (fov, focal, fno, focus) = match c {
            CameraSpec::Pinhole { fov_deg, .. } => (Some(*fov_deg), None, None, None),
            CameraSpec::ThinLens { fov_deg, focal_length_mm, f_number, focus_distance, .. } => {
                (Some(*fov_deg), *focal_length_mm, *f_number, *focus_distance)
            }
            CameraSpec::Lens { prescription, f_number, sensor_mm, focus_distance, .. } => {
                let p = lens::Prescription::load(dir.join(prescription))
                    .map_err(|e| ("camera.prescription".to_string(), e.to_string()))?;
                let first = lens::paraxial::FirstOrder::of(&p)
                    .map_err(|e| ("camera.prescription".to_string(), e.to_string()))?;
                let fov = 2.0 * (sensor_mm[1] / 2.0 / first.efl.abs()).atan().to_degrees();
                (Some(fov), Some(first.efl.abs()), Some(f_number.unwrap_or(first.f_number)), *focus_distance)
            }
        };
        let fov_deg = fov.unwrap_or(40.0);
        // the focus carried over: a distance, or the autofocus target
        let focus_on = c.focus_on().cloned();
        let focus_distance = if focus_on.is_some() { None } else { Some(focus.unwrap_or(3.0)) };
        let shape = match c {
            CameraSpec::ThinLens { aperture_shape, .. } | CameraSpec::Lens { aperture_shape, .. } => {
                aperture_shape.clone()
            }
            CameraSpec::Pinhole { .. } => ApertureSpec::Circle,
        };
        Ok(match kind {
            CameraKind::Pinhole => CameraSpec::Pinhole { position, look_at, up, fov_deg },
            CameraKind::ThinLens => CameraSpec::ThinLens {
                position,
                look_at,
                up,
                fov_deg,
                aperture: None,
                f_number: fno.filter(|_| focal.is_some()),
                focal_length_mm: focal,
                focus_distance,
                focus_on: focus_on.clone(),
                aperture_shape: shape.clone(),
                focus_shift: 0.0,
                glass: None,
            },
            CameraKind::Lens => {
                let prescription = match (&self.prescription, c) {
                    (Some(p), _) => absolute(p).display().to_string(),
                    (None, CameraSpec::Lens { prescription, .. }) => prescription.clone(),
                    (None, _) => {
                        return Err((
                            "camera.prescription".into(),
                            "a real lens needs a prescription: give --prescription FILE".into(),
                        ))
                    }
                };
                let p = lens::Prescription::load(dir.join(&prescription))
                    .map_err(|e| ("camera.prescription".to_string(), e.to_string()))?;
                let efl = lens::paraxial::FirstOrder::of(&p)
                    .map_err(|e| ("camera.prescription".to_string(), e.to_string()))?
                    .efl
                    .abs();
                // a sensor that keeps the field of view
                let h = 2.0 * efl * (fov_deg.to_radians() / 2.0).tan();
                CameraSpec::Lens {
                    position,
                    look_at,
                    up,
                    prescription,
                    f_number: self.f_number.or(fno),
                    stop_semi_diameter: None,
                    focus_distance,
                    focus_on: focus_on.clone(),
                    sensor_mm: [h * aspect, h],
                    aperture_shape: shape.clone(),
                    coating: None,
                }
            }
        })
    }
}

/// `p` made absolute against the working folder (a flag's file is the
/// user's, not relative to the scene).
fn absolute(p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().map(|d| d.join(p)).unwrap_or_else(|_| p.to_path_buf())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aperture_shapes_parse() {
        assert_eq!(Overrides::parse_shape("circle").unwrap(), ApertureSpec::Circle);
        assert_eq!(
            Overrides::parse_shape("polygon:6:15").unwrap(),
            ApertureSpec::Polygon { blades: 6, rotation_deg: 15.0 }
        );
        assert_eq!(
            Overrides::parse_shape("polygon:5").unwrap(),
            ApertureSpec::Polygon { blades: 5, rotation_deg: 0.0 }
        );
        assert_eq!(Overrides::parse_shape("mask:a.png").unwrap(), ApertureSpec::Mask { image: "a.png".into() });
        assert!(Overrides::parse_shape("hexagon").is_err());
        assert!(Overrides::parse_shape("polygon:x").is_err());
    }
}
