//! Frame sequences: a scene's `animation` section keyframes the camera's
//! focus distance, f-number, position, look-at point and focal length (a
//! thin lens's, or a zoom lens's between its listed positions), and each
//! frame is the scene with those settings interpolated. Every frame of a
//! sequence is rendered with the same seed, so a pixel draws the same
//! random numbers in every frame, and a real lens's focus pull draws its
//! aperture samples from one set of exit-pupil bounds for all frames
//! ([`SharedPupil`]): noise does not flicker where the picture does not
//! change. Focus breathing is not modelled: it comes out of the real lens,
//! whose film moves as it focuses.

use crate::camera::aperture::Aperture;
use crate::camera::real_lens::SharedPupil;
use crate::scene::format::{CameraSpec, SceneFile, V3};
use crate::scene::{FieldError, Given, Overrides, Scene, SceneError};
use lens::error::{exact, num};
use lens::Prescription;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The `animation` section of a scene file.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AnimationSpec {
    /// Number of frames (frame numbers 0 to frames - 1).
    pub frames: u32,
    /// Keyframes, in increasing frame order.
    #[serde(default)]
    pub keyframes: Vec<Keyframe>,
    /// A zoom lens's prescriptions at its listed positions (the same
    /// surfaces, glasses and radii; the spacings differ), relative to the
    /// scene file: what a real lens's `focal_length_mm` keyframes choose
    /// from.
    #[serde(default)]
    pub zoom: Vec<String>,
}

/// The camera settings at one frame; a setting left out is interpolated
/// from the keyframes that give it.
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// The frame number.
    pub frame: u32,
    /// Distance to the plane in focus, m (as the camera's own field).
    #[serde(default)]
    pub focus_distance: Option<f64>,
    /// f-number.
    #[serde(default)]
    pub f_number: Option<f64>,
    /// Camera position, m.
    #[serde(default)]
    pub position: Option<V3>,
    /// The point looked at, m.
    #[serde(default)]
    pub look_at: Option<V3>,
    /// Focal length, mm: a thin lens's (its field of view follows, as the
    /// film stays), or a zoom's (`zoom` lists its positions).
    #[serde(default)]
    pub focal_length_mm: Option<f64>,
}

/// The most frames a sequence may have.
pub const MAX_FRAMES: u32 = 100_000;

/// A loaded sequence: the scene file (overrides applied) and its
/// keyframes.
#[derive(Debug, Clone)]
pub struct Animation {
    file: SceneFile,
    dir: PathBuf,
    name: String,
    frames: u32,
    keys: Vec<Keyframe>,
    /// The zoom's positions: (focal length, spec), increasing focal length.
    zoom: Vec<(f64, lens::PrescriptionSpec)>,
    strict_glass_range: bool,
    /// A real lens's exit-pupil bounds for every frame's film, made once
    /// (where the lens and its stop stay and the focus is keyframed).
    pupil: Option<SharedPupil>,
}

/// An error about `field` of the scene file.
fn invalid(name: &str, field: String, message: String) -> SceneError {
    SceneError::Invalid { path: name.to_string(), field, source: FieldError::Message(message) }
}

impl Animation {
    /// Reads `path` (with `overrides`); `frames` replaces the file's frame
    /// count (a file without an `animation` section is one still repeated).
    /// Keyframes are checked here: numbering, order, values in their
    /// domain, the zoom's positions.
    pub fn load(path: &Path, overrides: &Overrides, frames: Option<u32>) -> Result<Animation, SceneError> {
        let name = path.display().to_string();
        let mut file = Scene::read_with(path, overrides)?;
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let spec = file.animation.take();
        let own = spec.as_ref().map_or(1, |s| s.frames);
        let frames = frames.unwrap_or(own);
        if frames == 0 || frames > MAX_FRAMES {
            return Err(invalid(&name, "animation.frames".into(), format!("{frames}: give 1 to {MAX_FRAMES} frames")));
        }
        let (mut keys, zoom_files) = spec.map(|s| (s.keyframes, s.zoom)).unwrap_or_default();
        // another frame count stretches the keyframes over it (a preview
        // of a long sequence in a few frames)
        if frames != own && own > 1 && keys.iter().all(|k| k.frame < own) {
            let scale = (frames - 1) as f64 / (own - 1) as f64;
            for k in &mut keys {
                k.frame = (k.frame as f64 * scale).round() as u32;
            }
            if keys.windows(2).any(|w| w[1].frame <= w[0].frame) {
                return Err(invalid(
                    &name,
                    "animation.frames".into(),
                    format!("{frames} frames: too few for the {} keyframes of the {own}-frame sequence to keep their own frames", keys.len()),
                ));
            }
        }
        for (i, k) in keys.iter().enumerate() {
            let field = |f: &str| format!("animation.keyframes[{i}].{f}");
            if k.frame >= frames {
                return Err(invalid(
                    &name,
                    field("frame"),
                    format!("frame {} of a {frames}-frame sequence: number frames 0 to {}", k.frame, frames - 1),
                ));
            }
            if i > 0 && k.frame <= keys[i - 1].frame {
                return Err(invalid(
                    &name,
                    field("frame"),
                    format!(
                        "frame {} comes after frame {}: list keyframes in increasing frame order, each frame once",
                        k.frame,
                        keys[i - 1].frame
                    ),
                ));
            }
            if let Some(d) = k.focus_distance {
                if !(d.is_finite() && d > 0.0) {
                    return Err(invalid(
                        &name,
                        field("focus_distance"),
                        format!("{}: the plane in focus must be in front of the camera (a distance > 0 m)", exact(d)),
                    ));
                }
            }
            for (what, v) in [("f_number", k.f_number), ("focal_length_mm", k.focal_length_mm)] {
                if let Some(v) = v {
                    if !(v.is_finite() && v > 0.0) {
                        return Err(invalid(&name, field(what), format!("{}: give a positive number", exact(v))));
                    }
                }
            }
            for (what, v) in [("position", k.position), ("look_at", k.look_at)] {
                if let Some(v) = v {
                    if !v.iter().all(|x| x.is_finite()) {
                        return Err(invalid(&name, field(what), "give three finite coordinates, m".into()));
                    }
                }
            }
        }
        let zoom = zoom_positions(&zoom_files, &dir, &name)?;
        let wants_zoom = keys.iter().any(|k| k.focal_length_mm.is_some());
        if wants_zoom {
            match &file.camera {
                CameraSpec::Lens { .. } if zoom.is_empty() => {
                    return Err(invalid(
                        &name,
                        "animation.zoom".into(),
                        "a real lens's focal_length_mm keyframes need the zoom's positions: list its prescriptions \
                         (one per listed focal length) in animation.zoom"
                            .into(),
                    ))
                }
                CameraSpec::Pinhole { .. } => {
                    return Err(invalid(
                        &name,
                        "animation.keyframes".into(),
                        "a pinhole has no focal length: keyframe fov by a thin_lens camera".into(),
                    ))
                }
                _ => {}
            }
        }
        let mut anim = Animation {
            file,
            dir,
            name,
            frames,
            keys,
            zoom,
            strict_glass_range: overrides.strict_glass_range,
            pupil: None,
        };
        anim.pupil = anim.shared_pupil()?;
        Ok(anim)
    }

    /// One set of exit-pupil bounds for all frames of a real lens whose
    /// prescription and stop stay (no f-number or zoom keyframes) and
    /// whose focus is a distance: they hold the films of every frame's
    /// focus, so each frame draws its samples from the same regions (the
    /// same aim for the same random numbers: the noise stays put), and
    /// they are made once instead of per frame. `None` otherwise.
    fn shared_pupil(&self) -> Result<Option<SharedPupil>, SceneError> {
        let CameraSpec::Lens { sensor_mm, aperture_shape, .. } = &self.file.camera else { return Ok(None) };
        if self.keys.iter().any(|k| k.f_number.is_some() || k.focal_length_mm.is_some()) {
            return Ok(None);
        }
        let focus_keyed = self.keys.iter().any(|k| k.focus_distance.is_some());
        if !focus_keyed && self.file.camera.focus_distance().is_none() {
            return Ok(None);
        }
        let p = Scene::camera_lens(&self.file.camera, &self.dir, &self.name)?;
        if p.focus_group().is_some() {
            // the group moves from frame to frame: another lens each time
            return Ok(None);
        }
        let Ok(aperture) = Aperture::from_spec(aperture_shape, &self.dir) else { return Ok(None) };
        let mut films = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..self.frames {
            let focus = interpolate_mapped(&self.keys, k, &|kf: &Keyframe| kf.focus_distance, |d| 1.0 / d, |x| 1.0 / x)
                .or(self.file.camera.focus_distance());
            // a frame that cannot be focused is named when it is built
            let Some(Ok(f)) = focus.map(|d| lens::paraxial::film_for_focus_from_film(&p, d * 1e3)) else {
                return Ok(None);
            };
            films = (films.0.min(f), films.1.max(f));
        }
        Ok(Some(SharedPupil::new(&p, &aperture, *sensor_mm, films)))
    }

    /// Sets the film's colour transport for every frame (`lens animate
    /// --spectral`).
    pub fn set_spectral(&mut self, s: crate::scene::format::SpectralSpec) {
        self.file.film.spectral = s;
    }

    /// The film every frame has (keyframes move the camera only).
    pub fn film(&self) -> &crate::scene::format::FilmSpec {
        &self.file.film
    }

    /// Number of frames.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The scene at frame `k` (0-based): the keyframed settings
    /// interpolated (focus linearly in 1 / distance, as a focus ring turns;
    /// f-number and focal length linearly in their logarithms, so a ramp
    /// goes by equal stops and equal zoom ratios; position and look-at
    /// linearly), held before the first and after the last keyframe that
    /// gives them. Errors name the frame.
    pub fn scene(&self, k: u32) -> Result<Scene, SceneError> {
        let mut file = self.file.clone();
        let at = |get: &dyn Fn(&Keyframe) -> Option<f64>, map: fn(f64) -> f64, unmap: fn(f64) -> f64| {
            interpolate_mapped(&self.keys, k, get, map, unmap)
        };
        let focus = at(&|kf: &Keyframe| kf.focus_distance, |d| 1.0 / d, |x| 1.0 / x);
        let f_number = at(&|kf: &Keyframe| kf.f_number, f64::ln, f64::exp);
        let focal = at(&|kf: &Keyframe| kf.focal_length_mm, f64::ln, f64::exp);
        let comp = |c: usize, pos: bool| {
            interpolate(&self.keys, k, &|kf: &Keyframe| if pos { kf.position } else { kf.look_at }.map(|v| v[c]))
        };
        let position = (0..3).map(|c| comp(c, true)).collect::<Option<Vec<f64>>>();
        let look_at = (0..3).map(|c| comp(c, false)).collect::<Option<Vec<f64>>>();
        let frame_err = |e: SceneError| match e {
            SceneError::Invalid { path, field, source } => {
                SceneError::Invalid { path, field: format!("animation frame {k}: {field}"), source }
            }
            other => other,
        };
        let mut lens: Option<Prescription> = None;
        match &mut file.camera {
            CameraSpec::Pinhole { position: p, look_at: l, .. } => {
                set_pose(p, l, &position, &look_at);
                if focus.is_some() || f_number.is_some() {
                    return Err(invalid(
                        &self.name,
                        "animation.keyframes".into(),
                        "a pinhole has no focus or f-number: use a thin_lens or lens camera".into(),
                    ));
                }
            }
            CameraSpec::ThinLens {
                position: p, look_at: l, f_number: n, aperture, focal_length_mm, fov_deg, ..
            } => {
                set_pose(p, l, &position, &look_at);
                if let Some(f) = focal {
                    let Some(f0) = *focal_length_mm else {
                        return Err(invalid(
                            &self.name,
                            "animation.keyframes".into(),
                            "focal_length_mm keyframes need the thin lens's own focal_length_mm (the film it keeps)"
                                .into(),
                        ));
                    };
                    // the film stays: the field of view narrows as f grows
                    let t = (fov_deg.to_radians() / 2.0).tan() * f0 / f;
                    *fov_deg = 2.0 * t.atan().to_degrees();
                    *focal_length_mm = Some(f);
                }
                if let Some(v) = f_number {
                    *n = Some(v);
                    *aperture = None;
                }
            }
            CameraSpec::Lens { position: p, look_at: l, f_number: n, stop_semi_diameter, .. } => {
                set_pose(p, l, &position, &look_at);
                if let Some(v) = f_number {
                    *n = Some(v);
                    *stop_semi_diameter = None;
                }
                if let Some(f) = focal {
                    lens = Some(
                        self.zoom_at(f)
                            .map_err(|m| invalid(&self.name, format!("animation frame {k}: focal_length_mm"), m))?,
                    );
                }
            }
        }
        if let Some(d) = focus {
            file.camera.set_focus(Some(d), None);
        }
        let mut scene =
            Scene::build_given(file, &self.dir, &self.name, &Given { lens: lens.as_ref(), pupil: self.pupil.as_ref() })
                .map_err(frame_err)?;
        if self.strict_glass_range {
            scene.set_glass_range(lens::glass::GlassRange::Strict).map_err(frame_err)?;
        }
        Ok(scene)
    }

    /// Builds the scene of every keyframe and of the first and last frames
    /// (and drops them): the sequence's problems found before any frame
    /// is rendered, named by keyframe. Frames between two keyframes
    /// interpolate settings both of them take (a focus between two reachable
    /// ones, an f-number between two the lens reaches), so they are not
    /// built twice; one can still fail on its own (autofocus on a pixel
    /// that a moving camera turns to the background), and is named when it
    /// is reached.
    pub fn check(&self) -> Result<(), SceneError> {
        for (i, kf) in self.keys.iter().enumerate() {
            self.scene(kf.frame).map_err(|e| match e {
                SceneError::Invalid { path, field, source } => {
                    SceneError::Invalid { path, field: format!("animation.keyframes[{i}] ({field})"), source }
                }
                other => other,
            })?;
        }
        for k in [0, self.frames - 1] {
            if !self.keys.iter().any(|kf| kf.frame == k) {
                self.scene(k)?;
            }
        }
        Ok(())
    }

    /// The zoom lens at focal length `f` mm: a listed position's own
    /// prescription where `f` is its focal length; between two positions,
    /// their spacings and clear apertures interpolated linearly by one
    /// parameter t, solved (bisection) so that the focal length is `f`.
    /// The patent gives the spacings only at its positions: between them
    /// the focal length is exact and the aberrations are those of the
    /// interpolated spacings, not the maker's cam.
    fn zoom_at(&self, f: f64) -> Result<Prescription, String> {
        let efls: Vec<f64> = self.zoom.iter().map(|z| z.0).collect();
        let (lo, hi) = (efls[0], efls[efls.len() - 1]);
        // a listed position (to a millionth: the files' rounding)
        if let Some((_, spec)) = self.zoom.iter().find(|z| (z.0 - f).abs() <= 1e-6 * f) {
            return Prescription::from_spec(spec)
                .map_err(|e| e.iter().map(|x| x.to_string()).collect::<Vec<_>>().join("; "));
        }
        if !(f >= lo && f <= hi) {
            return Err(format!(
                "{} mm is outside the zoom's range, {} to {} mm: keyframe a focal length inside it",
                num(f),
                num(lo),
                num(hi)
            ));
        }
        let i = efls.partition_point(|&e| e < f).clamp(1, efls.len() - 1) - 1;
        let (a, b) = (&self.zoom[i].1, &self.zoom[i + 1].1);
        let make = |t: f64| -> Result<(Prescription, f64), String> {
            let mut s = a.clone();
            for (sa, sb) in s.surfaces.iter_mut().zip(&b.surfaces) {
                sa.thickness += t * (sb.thickness - sa.thickness);
                if let (Some(x), Some(y)) = (sa.semi_diameter, sb.semi_diameter) {
                    sa.semi_diameter = Some(x + t * (y - x));
                }
            }
            let p = Prescription::from_spec(&s).map_err(|e| {
                format!(
                    "the zoom interpolated at t = {t}: {}",
                    e.iter().map(|x| x.to_string()).collect::<Vec<_>>().join("; ")
                )
            })?;
            let efl = lens::paraxial::FirstOrder::of(&p).map_err(|e| e.to_string())?.efl.abs();
            Ok((p, efl))
        };
        let (mut t0, mut t1) = (0.0, 1.0);
        let e0 = self.zoom[i].0;
        let rising = self.zoom[i + 1].0 > e0;
        for _ in 0..80 {
            let t = 0.5 * (t0 + t1);
            let (_, e) = make(t)?;
            if (e < f) == rising {
                t0 = t;
            } else {
                t1 = t;
            }
        }
        Ok(make(0.5 * (t0 + t1))?.0)
    }
}

/// The zoom's positions, loaded and checked: the same surfaces but for
/// their spacings and clear apertures, sorted by focal length.
fn zoom_positions(files: &[String], dir: &Path, name: &str) -> Result<Vec<(f64, lens::PrescriptionSpec)>, SceneError> {
    if files.len() == 1 {
        return Err(invalid(name, "animation.zoom".into(), "list at least two positions of the zoom".into()));
    }
    let mut out = Vec::new();
    for (i, f) in files.iter().enumerate() {
        let field = format!("animation.zoom[{i}]");
        let spec = lens::load_spec(&dir.join(f)).map_err(|e| invalid(name, field.clone(), e.to_string()))?;
        let p = Prescription::from_spec(&spec).map_err(|e| {
            invalid(name, field.clone(), e.iter().map(|x| x.to_string()).collect::<Vec<_>>().join("; "))
        })?;
        let efl =
            lens::paraxial::FirstOrder::of(&p).map_err(|e| invalid(name, field.clone(), e.to_string()))?.efl.abs();
        if let Some((_, first)) = out.first() {
            let first: &lens::PrescriptionSpec = first;
            if first.surfaces.len() != spec.surfaces.len() {
                return Err(invalid(
                    name,
                    field,
                    format!(
                        "{} surfaces, the first position {}: a zoom's positions are one lens with other spacings",
                        spec.surfaces.len(),
                        first.surfaces.len()
                    ),
                ));
            }
            for (k, (a, b)) in first.surfaces.iter().zip(&spec.surfaces).enumerate() {
                if a.radius != b.radius || a.glass != b.glass || a.ior != b.ior || a.stop != b.stop {
                    return Err(invalid(
                        name,
                        field,
                        format!(
                            "surface {} differs from the first position's in radius, glass or stop: a zoom's positions \
                             differ only in their spacings",
                            k + 1
                        ),
                    ));
                }
            }
        }
        out.push((efl, spec));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(out)
}

/// Sets the pose fields that are animated.
fn set_pose(p: &mut V3, l: &mut V3, position: &Option<Vec<f64>>, look_at: &Option<Vec<f64>>) {
    if let Some(v) = position {
        *p = [v[0], v[1], v[2]];
    }
    if let Some(v) = look_at {
        *l = [v[0], v[1], v[2]];
    }
}

/// The value at frame `k` of the setting `get`, linear between the
/// keyframes that give it, held outside them; `None` when none does.
fn interpolate(keys: &[Keyframe], k: u32, get: &dyn Fn(&Keyframe) -> Option<f64>) -> Option<f64> {
    interpolate_mapped(keys, k, get, |x| x, |x| x)
}

/// [`interpolate`] in the variable `map(value)`.
fn interpolate_mapped(
    keys: &[Keyframe],
    k: u32,
    get: &dyn Fn(&Keyframe) -> Option<f64>,
    map: fn(f64) -> f64,
    unmap: fn(f64) -> f64,
) -> Option<f64> {
    let given: Vec<(u32, f64)> = keys.iter().filter_map(|kf| get(kf).map(|v| (kf.frame, v))).collect();
    let (first, last) = (given.first()?, given.last()?);
    if k <= first.0 {
        return Some(first.1);
    }
    if k >= last.0 {
        return Some(last.1);
    }
    let j = given.partition_point(|g| g.0 <= k);
    let ((f0, v0), (f1, v1)) = (given[j - 1], given[j]);
    if f0 == k {
        return Some(v0);
    }
    let t = (k - f0) as f64 / (f1 - f0) as f64;
    Some(unmap(map(v0) + t * (map(v1) - map(v0))))
}

/// A frame file name from a pattern with one `%d` or `%0Nd` (the frame
/// number, zero-padded to N digits).
pub fn frame_path(pattern: &str, k: u32) -> Result<PathBuf, String> {
    let bad = || format!("{pattern}: give a file name with one frame number, %d or %04d (frames/f%04d.exr)");
    let start = pattern.find('%').ok_or_else(bad)?;
    let rest = &pattern[start + 1..];
    let end = rest.find('d').ok_or_else(bad)?;
    let width = &rest[..end];
    if !(width.is_empty()
        || (width.starts_with('0') && width.len() <= 3 && width[1..].chars().all(|c| c.is_ascii_digit())))
    {
        return Err(bad());
    }
    let after = &rest[end + 1..];
    if after.contains('%') {
        return Err(bad());
    }
    let n: usize = if width.is_empty() { 0 } else { width[1..].parse().map_err(|_| bad())? };
    Ok(PathBuf::from(format!("{}{:0n$}{}", &pattern[..start], k, after)))
}
