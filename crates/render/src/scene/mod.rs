//! A scene ready to render: shapes with materials, lights, background and
//! camera, built from a scene file with every problem reported by field.

mod autofocus;
mod camera;
mod colour;
pub mod format;

use colour::{colour_mode, find_glass, radiance_of};
use lens::error::exact;
pub mod overrides;

pub use overrides::{CameraKind, Overrides};

use crate::bvh::{Bvh, BVH_THRESHOLD};
use crate::camera::{Camera, CameraError};
use crate::geometry::{Hit, Ray, Shape};
use crate::material::Material;
use crate::spectrum::{Colour, Radiance, WavelengthRange};
use crate::transport::{Channels, Medium, Transport};
use format::*;
use glam::DVec3;
use std::path::Path;

/// The most pixels a film may have: 2^25 (8192 x 4096; the image and its
/// rows take about 1.6 GB).
pub const MAX_PIXELS: u64 = 1 << 25;
/// The most samples per pixel.
pub const MAX_SPP: u32 = 1 << 20;
/// The largest coordinate or size in a scene, m (a tenth of a light year:
/// squares of it stay far from overflow).
pub const MAX_COORDINATE: f64 = 1e15;
/// The largest radiance or intensity a light may have (so that no pixel
/// overflows a 32-bit float in an EXR).
pub const MAX_RADIANCE: f64 = 1e20;

/// Why a scene could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A file could not be read.
    #[error("{path}: cannot read: {message}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        message: String,
    },
    /// Malformed JSON, an unknown field or a wrong type.
    #[error("{path}: line {line}, column {column}: {message}")]
    Json {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde's message.
        message: String,
    },
    /// An impossible value; names the field and what to change.
    #[error("{path}: {field}: {source}")]
    Invalid {
        /// The file.
        path: String,
        /// The field, e.g. `shapes[3].radius`.
        field: String,
        /// What is wrong and what to change.
        source: FieldError,
    },
}

/// What is wrong with one field of a scene. Errors of the lens crate and of
/// the camera are kept as they are, as the source.
#[derive(Debug, thiserror::Error)]
pub enum FieldError {
    /// A value out of its domain, in words.
    #[error("{0}")]
    Message(String),
    /// The camera could not be built.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The prescription could not be loaded.
    #[error(transparent)]
    Lens(Box<lens::LoadError>),
    /// The prescription could not be set up as asked.
    #[error(transparent)]
    Optics(Box<lens::OpticsError>),
    /// The aperture shape could not be made.
    #[error(transparent)]
    Aperture(#[from] crate::camera::aperture::ApertureError),
    /// A mesh file could not be read.
    #[error("{}: {source}", path.display())]
    Mesh {
        /// The OBJ file.
        path: std::path::PathBuf,
        /// The line that could not be read.
        source: crate::mesh::MeshError,
    },
    /// An environment image could not be read.
    #[error(transparent)]
    Image(#[from] crate::image::ImageError),
}

impl From<lens::OpticsError> for FieldError {
    fn from(e: lens::OpticsError) -> Self {
        FieldError::Optics(Box::new(e))
    }
}

impl From<lens::LoadError> for FieldError {
    fn from(e: lens::LoadError) -> Self {
        FieldError::Lens(Box::new(e))
    }
}

impl From<String> for FieldError {
    fn from(m: String) -> Self {
        FieldError::Message(m)
    }
}

impl From<&str> for FieldError {
    fn from(m: &str) -> Self {
        FieldError::Message(m.to_string())
    }
}

/// What a frame sequence gives each frame's scene beyond its file.
#[derive(Debug, Clone, Copy, Default)]
pub struct Given<'a> {
    /// A real lens camera's prescription in place of its file (a zoom
    /// between its listed positions); its `f_number` and
    /// `stop_semi_diameter` still apply.
    pub lens: Option<&'a lens::Prescription>,
    /// Exit-pupil bounds shared by the frames (used where they were made
    /// for the camera's lens, stop, sensor and film).
    pub pupil: Option<&'a crate::camera::real_lens::SharedPupil>,
}

/// What rays that leave the scene see.
#[derive(Debug, Clone, PartialEq)]
pub enum Background {
    /// Uniform.
    Constant(Radiance),
    /// Equirectangular environment image (already scaled by its intensity).
    Environment(Box<crate::image::Image>),
    /// Gradient.
    Sky {
        /// Horizon.
        horizon: Radiance,
        /// Zenith.
        zenith: Radiance,
        /// Below the horizon.
        ground: Radiance,
    },
}

/// How a render carries colour.
#[derive(Debug, Clone, PartialEq)]
pub enum ColourMode {
    /// Three linear sRGB channels.
    Rgb,
    /// Hero-wavelength spectral transport over a range of wavelengths, the
    /// film in CIE XYZ.
    Spectral(WavelengthRange),
    /// One wavelength, nm: each pixel is the radiance there (grey).
    Monochromatic(f64),
}

impl Background {
    /// Radiance seen along `d`, in the channels of `t`.
    pub fn radiance<T: Transport>(&self, t: &T, d: DVec3) -> T::Value {
        match self {
            Background::Constant(c) => t.radiance(c),
            Background::Environment(img) => {
                let (x, y) = crate::camera::sky_patches::texel_of(d, img.width, img.height);
                t.rgb_radiance(img.pixels[y * img.width + x])
            }
            Background::Sky { horizon, zenith, ground } => {
                if d.y < 0.0 {
                    t.radiance(ground)
                } else {
                    t.radiance(horizon).mix(t.radiance(zenith), d.y.clamp(0.0, 1.0))
                }
            }
        }
    }
}

/// A built scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Primitives.
    pub shapes: Vec<Shape>,
    /// Material index of each primitive.
    pub material_of: Vec<usize>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Primitives with an emissive material (area lights), bounded ones.
    pub emitters: Vec<usize>,
    /// Cumulative probabilities of choosing each emitter for light
    /// sampling, in proportion to its power (luminance of its radiance
    /// times its area), the last 1.
    pub emitter_cdf: Vec<f64>,
    /// Point lights: position, intensity.
    pub point_lights: Vec<(DVec3, Radiance)>,
    /// Background.
    pub background: Background,
    /// Importance sampling of an environment background (`None` for the
    /// others, or a black image).
    pub env_sampler: Option<crate::envmap::EnvSampler>,
    /// Camera.
    pub camera: Camera,
    /// Film settings.
    pub film: FilmSpec,
    /// RGB, spectral or one wavelength.
    pub colour: ColourMode,
    /// What a spectral render does outside a glass's data.
    pub glass_range: lens::glass::GlassRange,
    /// The glasses a spectral or one-wavelength render uses past their
    /// data (extrapolated).
    pub glass_warnings: Vec<lens::glass::RangeWarning>,
    /// Anything else the user should know about the scene as built, one
    /// sentence each: a focus beyond every object, a real lens whose image
    /// circle leaves the film's corners dark.
    pub warnings: Vec<String>,
    /// The camera's settings in words, with units (`Double Gauss 50mm f/2:
    /// f = 50.3582 mm, f/2, focus 5 m, sensor 36 x 24 mm`).
    pub camera_summary: String,
    /// Every file the scene was built from: the scene file (when loaded
    /// from one), the prescription, aperture masks, the environment image,
    /// meshes. A command must not write over any of them.
    pub inputs: Vec<std::path::PathBuf>,
    /// Whether a real lens's lamps (emissive spheres) seen through it are
    /// rendered by tracing light from them into the lens
    /// (`camera::lamp_light`; on unless turned off here, as tests do to
    /// compare with camera paths alone). Either way the picture is the same
    /// in expectation.
    pub lamp_tracing: bool,
    bvh: Option<Bvh>,
    /// Primitives tested one by one (planes, or all when there is no BVH).
    linear: Vec<usize>,
}

fn v3(a: V3) -> DVec3 {
    DVec3::from_array(a)
}

impl Scene {
    /// Loads and builds a scene file. Paths inside it are relative to it.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        Scene::load_with(path, &Overrides::default())
    }

    /// [`Self::load`] with settings of the film and camera overridden (the
    /// command line's flags), applied to the file as read, before the scene
    /// is built.
    pub fn load_with(path: &Path, overrides: &Overrides) -> Result<Scene, SceneError> {
        let name = path.display().to_string();
        let file = Scene::read_with(path, overrides)?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut scene = Scene::build(file, dir, &name)?;
        scene.inputs.insert(0, path.to_path_buf());
        if overrides.strict_glass_range {
            scene.set_glass_range(lens::glass::GlassRange::Strict)?;
        }
        Ok(scene)
    }

    /// Reads a scene file and applies `overrides` to it, without building
    /// it (what a frame sequence builds once per frame).
    pub fn read_with(path: &Path, overrides: &Overrides) -> Result<SceneFile, SceneError> {
        let name = path.display().to_string();
        let text = lens::io::files::read_bounded(path, lens::io::files::MAX_TEXT_BYTES)
            .map_err(|e| SceneError::Io { path: name.clone(), message: e.reason() })
            .and_then(|b| {
                String::from_utf8(b).map_err(|_| SceneError::Io {
                    path: name.clone(),
                    message: "not UTF-8 text: is it a scene file?".into(),
                })
            })?;
        let file: SceneFile = lens::io::json::parse_object(&text, "a scene (docs/scene-format.md)")
            .map_err(|(line, column, message)| SceneError::Json { path: name.clone(), line, column, message })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut file = file;
        overrides.apply(&mut file, dir).map_err(|(field, message)| SceneError::Invalid {
            path: name.clone(),
            field,
            source: message.into(),
        })?;
        Ok(file)
    }

    /// Builds a scene from its parsed file; `dir` resolves relative paths.
    pub fn build(file: SceneFile, dir: &Path, name: &str) -> Result<Scene, SceneError> {
        Scene::build_given(file, dir, name, &Given::default())
    }

    /// A real lens camera's prescription as the scene file asks for it
    /// (loaded, its stop resized), before it is focused; errors name the
    /// field.
    pub fn camera_lens(spec: &CameraSpec, dir: &Path, name: &str) -> Result<lens::Prescription, SceneError> {
        camera::load_lens(spec, dir, &Given::default()).map_err(|(field, source)| SceneError::Invalid {
            path: name.to_string(),
            field,
            source,
        })
    }

    /// [`Self::build`] with what a frame sequence prepared once for all its
    /// frames ([`Given`]).
    pub fn build_given(file: SceneFile, dir: &Path, name: &str, given: &Given) -> Result<Scene, SceneError> {
        let inputs = referenced_files(&file, dir);
        let bad = |field: String, message: String| SceneError::Invalid {
            path: name.to_string(),
            field,
            source: message.into(),
        };
        let finite = |field: &str, v: &[f64]| -> Result<(), SceneError> {
            if v.iter().all(|x| x.is_finite() && x.abs() <= MAX_COORDINATE) {
                Ok(())
            } else {
                Err(bad(field.into(), format!("must be finite numbers of at most {MAX_COORDINATE:e} m")))
            }
        };
        // film
        let f = &file.film;
        if f.width == 0 || f.height == 0 || f.width > 16384 || f.height > 16384 {
            return Err(bad(
                "film".into(),
                format!("{} x {} pixels: width and height must be 1..=16384", f.width, f.height),
            ));
        }
        if (f.width as u64) * (f.height as u64) > MAX_PIXELS {
            return Err(bad(
                "film".into(),
                format!(
                    "{} x {} pixels: at most {MAX_PIXELS} pixels (8192 x 4096) are rendered, so the image fits in memory",
                    f.width, f.height
                ),
            ));
        }
        if f.spp == 0 || f.spp > MAX_SPP {
            return Err(bad("film.spp".into(), format!("{}: samples per pixel must be 1..={MAX_SPP}", f.spp)));
        }
        if !(f.exposure.is_finite() && f.exposure > 0.0) {
            return Err(bad("film.exposure".into(), "must be a positive number".into()));
        }
        // materials
        let mut names = Vec::new();
        let mut materials = Vec::new();
        for (key, m) in &file.materials {
            let field = format!("materials.{key}");
            let rgb = |c: Rgb, what: &str| -> Result<DVec3, SceneError> {
                if c.iter().all(|x| x.is_finite() && *x >= 0.0) {
                    Ok(v3(c))
                } else {
                    Err(bad(format!("{field}.{what}"), "colours must be finite and >= 0".into()))
                }
            };
            let colour = |c: Rgb, what: &str| rgb(c, what).map(Colour::new);
            let constant = |ior: f64| -> Result<Material, SceneError> {
                if !(ior.is_finite() && ior >= 1.0) {
                    return Err(bad(format!("{field}.ior"), format!("{}: a refractive index >= 1", exact(ior))));
                }
                Ok(Material::Dielectric { medium: Medium { ior, glass: None } })
            };
            materials.push(match m {
                MaterialSpec::Diffuse { color } => Material::Diffuse { albedo: colour(*color, "color")? },
                MaterialSpec::Checker { a, b, scale } => {
                    if !(scale.is_finite() && *scale > 0.0) {
                        return Err(bad(format!("{field}.scale"), "must be a positive size".into()));
                    }
                    Material::Checker { a: colour(*a, "a")?, b: colour(*b, "b")?, scale: *scale }
                }
                MaterialSpec::Emissive { radiance } => Material::Emissive {
                    radiance: radiance_of(radiance).map_err(|e| bad(format!("{field}.radiance"), e))?,
                },
                MaterialSpec::Mirror { tint } => Material::Mirror { tint: colour(*tint, "tint")? },
                MaterialSpec::Glass { ior } => constant(*ior)?,
                MaterialSpec::Dielectric { ior: Some(ior), glass: None } => constant(*ior)?,
                MaterialSpec::Dielectric { ior: None, glass: Some(name) } => {
                    let glass = find_glass(name).map_err(|e| bad(format!("{field}.glass"), e))?;
                    Material::Dielectric { medium: Medium { ior: glass.1, glass: Some(glass.0) } }
                }
                MaterialSpec::Dielectric { .. } => {
                    return Err(bad(
                        field.clone(),
                        "a dielectric needs either \"ior\" (a constant index) or \"glass\" (\"VENDOR:NAME\"), not both"
                            .into(),
                    ))
                }
            });
            names.push(key.clone());
        }
        let material = |i: usize, m: &str| -> Result<usize, SceneError> {
            names.iter().position(|n| n == m).ok_or_else(|| {
                bad(
                    format!("shapes[{i}].material"),
                    format!("no material named \"{m}\" (defined: {})", names.join(", ")),
                )
            })
        };
        // shapes
        let mut shapes = Vec::new();
        let mut material_of = Vec::new();
        // the primitives of each named shape
        let mut named: Vec<(String, std::ops::Range<usize>)> = Vec::new();
        for (i, s) in file.shapes.iter().enumerate() {
            let field = |f: &str| format!("shapes[{i}].{f}");
            let first = shapes.len();
            if let Some(n) = s.name() {
                if n.is_empty() || named.iter().any(|(m, _)| m == n) {
                    return Err(bad(field("name"), format!("\"{n}\": give each named shape its own, non-empty name")));
                }
                named.push((n.to_string(), first..first));
            }
            match s {
                ShapeSpec::Sphere { center, radius, material: m, .. } => {
                    finite(&field("center"), center)?;
                    if !(radius.is_finite() && *radius > 0.0 && *radius <= MAX_COORDINATE) {
                        return Err(bad(
                            field("radius"),
                            format!(
                                "{}: a sphere needs a positive radius of at most {MAX_COORDINATE:e} m",
                                exact(*radius)
                            ),
                        ));
                    }
                    shapes.push(Shape::Sphere { center: v3(*center), radius: *radius });
                    material_of.push(material(i, m)?);
                }
                ShapeSpec::Plane { point, normal, material: m, .. } => {
                    finite(&field("point"), point)?;
                    finite(&field("normal"), normal)?;
                    let n = v3(*normal)
                        .try_normalize()
                        .ok_or_else(|| bad(field("normal"), "must be a non-zero vector".into()))?;
                    shapes.push(Shape::Plane { point: v3(*point), normal: n });
                    material_of.push(material(i, m)?);
                }
                ShapeSpec::Quad { corner, u, v, material: m, .. } => {
                    finite(&field("corner"), corner)?;
                    finite(&field("u"), u)?;
                    finite(&field("v"), v)?;
                    if v3(*u).cross(v3(*v)).length() == 0.0 || !v3(*u).is_finite() || !v3(*v).is_finite() {
                        return Err(bad(field("u"), "u and v must be finite, non-parallel edges".into()));
                    }
                    shapes.push(Shape::Quad { corner: v3(*corner), u: v3(*u), v: v3(*v) });
                    material_of.push(material(i, m)?);
                }
                ShapeSpec::Box { min, max, material: m, .. } => {
                    finite(&field("min"), min)?;
                    finite(&field("max"), max)?;
                    let (lo, hi) = (v3(*min), v3(*max));
                    if !(lo.is_finite() && hi.is_finite() && lo.cmplt(hi).all()) {
                        return Err(bad(field("max"), "each coordinate of max must exceed min".into()));
                    }
                    let mi = material(i, m)?;
                    let d = hi - lo;
                    let (x, y, z) = (DVec3::X * d.x, DVec3::Y * d.y, DVec3::Z * d.z);
                    // six faces, normals outward (u x v)
                    for (c, u, v) in [(lo, y, x), (lo, x, z), (lo, z, y), (hi, -x, -y), (hi, -z, -x), (hi, -y, -z)] {
                        shapes.push(Shape::Quad { corner: c, u, v });
                        material_of.push(mi);
                    }
                }
                ShapeSpec::Mesh { obj, scale, translate, material: m, .. } => {
                    let mi = material(i, m)?;
                    let p = dir.join(obj);
                    let text = lens::io::files::read_bounded(&p, lens::io::files::MAX_TEXT_BYTES)
                        .map_err(|e| e.reason())
                        .and_then(|b| String::from_utf8(b).map_err(|_| "not UTF-8 text".to_string()))
                        .map_err(|e| bad(field("obj"), format!("{}: cannot read: {e}", p.display())))?;
                    let tris = crate::mesh::parse_obj(&text).map_err(|source| SceneError::Invalid {
                        path: name.to_string(),
                        field: field("obj"),
                        source: FieldError::Mesh { path: p.clone(), source },
                    })?;
                    if !(scale.is_finite() && *scale > 0.0 && *scale <= MAX_COORDINATE) {
                        return Err(bad(
                            field("scale"),
                            format!("{}: give a positive scale of at most {MAX_COORDINATE:e}", exact(*scale)),
                        ));
                    }
                    finite(&field("translate"), translate)?;
                    let far = tris
                        .iter()
                        .flatten()
                        .map(|p| (*p * *scale + v3(*translate)).abs().max_element())
                        .fold(0.0, f64::max);
                    if far.is_nan() || far > MAX_COORDINATE {
                        return Err(bad(
                            field("scale"),
                            format!("the mesh reaches {far:e} m: scenes end at {MAX_COORDINATE:e} m"),
                        ));
                    }
                    for t in tris {
                        shapes.push(Shape::Triangle { v: t.map(|p| p * *scale + v3(*translate)) });
                        material_of.push(mi);
                    }
                }
            }
            if s.name().is_some() {
                if let Some((_, r)) = named.last_mut() {
                    r.end = shapes.len();
                }
            }
        }
        let emitters: Vec<usize> = (0..shapes.len())
            .filter(|&i| matches!(materials[material_of[i]], Material::Emissive { .. }) && shapes[i].area().is_finite())
            .collect();
        let emitter_cdf = emitter_cdf(&emitters, &shapes, &materials, &material_of);
        let mut point_lights = Vec::new();
        for (i, l) in file.lights.iter().enumerate() {
            let LightSpec::Point { position, intensity } = l;
            finite(&format!("lights[{i}].position"), position)?;
            let intensity = radiance_of(intensity).map_err(|e| bad(format!("lights[{i}].intensity"), e))?;
            point_lights.push((v3(*position), intensity));
        }
        let radiance =
            |c: &Rgb, what: &str| radiance_of(&RadianceSpec::Rgb(*c)).map_err(|e| bad(format!("background.{what}"), e));
        let background = match &file.background {
            BackgroundSpec::Constant { radiance: c } => Background::Constant(radiance(c, "radiance")?),
            BackgroundSpec::Environment { exr, intensity } => {
                if !(intensity.is_finite() && *intensity >= 0.0 && *intensity <= MAX_RADIANCE) {
                    return Err(bad(
                        "background.intensity".into(),
                        format!("must be a number from 0 to {MAX_RADIANCE:e}"),
                    ));
                }
                let mut img = load_environment(&dir.join(exr)).map_err(|source| SceneError::Invalid {
                    path: name.to_string(),
                    field: "background.exr".into(),
                    source,
                })?;
                for p in &mut img.pixels {
                    *p *= *intensity;
                }
                Background::Environment(Box::new(img))
            }
            BackgroundSpec::Sky { horizon, zenith, ground } => Background::Sky {
                horizon: radiance(horizon, "horizon")?,
                zenith: radiance(zenith, "zenith")?,
                ground: radiance(ground, "ground")?,
            },
        };
        let invalid =
            |(field, source): (String, FieldError)| SceneError::Invalid { path: name.to_string(), field, source };
        // autofocus: the distance found, written into the camera as if given
        let mut file = file;
        let mut focus_note = None;
        let mut real = None;
        if let Some(on) = file.camera.focus_on().cloned() {
            if file.camera.focus_distance().is_some() {
                return Err(invalid((
                    "camera.focus_on".into(),
                    "give focus_distance or focus_on, not both (autofocus finds the distance)".into(),
                )));
            }
            let a =
                autofocus::autofocus(&file.camera, &file.film, dir, given, &on, &shapes, &named).map_err(invalid)?;
            file.camera.set_focus(Some(a.distance_m), None);
            real = a.real;
            focus_note = Some(a.note);
        }
        let f = &file.film;
        let mut camera = camera::build_camera(&file.camera, f, dir, given, real).map_err(invalid)?;
        let spheres: Vec<(DVec3, f64)> = (0..shapes.len())
            .filter(|&i| matches!(materials[material_of[i]], Material::Emissive { .. }))
            .filter_map(|i| match shapes[i] {
                Shape::Sphere { center, radius } => Some((center, radius)),
                _ => None,
            })
            .collect();
        match &mut camera {
            Camera::ThinLens { aperture, focus_shift, lamps, .. } => {
                *lamps = crate::camera::LampAim::new(spheres, aperture, *focus_shift);
            }
            // the real lens's lamps are traced from the lamps at render time
            Camera::Real(_) | Camera::Pinhole { .. } => {}
        }
        let warnings = camera::settings_warnings(&file.camera, &camera, &shapes);
        let mut camera_summary = camera::summary(&file.camera, &camera);
        if let Some(n) = focus_note {
            camera_summary = format!("{camera_summary} ({n})");
        }
        let range = lens::glass::GlassRange::Extrapolate;
        let (colour, range_warnings) =
            colour_mode(&file.film, &camera, &materials, &point_lights, range).map_err(|(field, e)| bad(field, e))?;
        // acceleration only when there are enough bounded primitives
        let bounded: Vec<usize> = (0..shapes.len()).filter(|&i| !matches!(shapes[i], Shape::Plane { .. })).collect();
        let (bvh, linear) = if bounded.len() >= BVH_THRESHOLD {
            let planes = (0..shapes.len()).filter(|&i| matches!(shapes[i], Shape::Plane { .. })).collect();
            (Some(Bvh::build(&shapes, bounded)), planes)
        } else {
            (None, (0..shapes.len()).collect())
        };
        Ok(Scene {
            shapes,
            material_of,
            materials,
            emitter_cdf,
            emitters,
            env_sampler: match &background {
                Background::Environment(img) => crate::envmap::EnvSampler::new(img),
                _ => None,
            },
            point_lights,
            background,
            camera,
            film: file.film,
            colour,
            glass_range: range,
            glass_warnings: range_warnings,
            warnings,
            camera_summary,
            inputs,
            lamp_tracing: true,
            bvh,
            linear,
        })
    }

    /// What a render does outside a glass's data (extrapolate, the default,
    /// or strict: a spectral range narrowed to every glass's data, one
    /// wavelength outside one refused); errors name the film's field.
    pub fn set_glass_range(&mut self, range: lens::glass::GlassRange) -> Result<(), SceneError> {
        let old = self.glass_range;
        self.glass_range = range;
        let film = self.film.clone();
        self.set_colour(film.spectral, film.wavelength_nm).inspect_err(|_| self.glass_range = old)
    }

    /// Overrides the film's `spectral` and `wavelength_nm` settings (as
    /// the command line's `--spectral` and `--wavelength-nm` do); errors
    /// name the flag's field.
    pub fn set_colour(&mut self, spectral: SpectralSpec, wavelength_nm: Option<f64>) -> Result<(), SceneError> {
        let mut film = self.film.clone();
        film.spectral = spectral;
        film.wavelength_nm = wavelength_nm;
        let (colour, warnings) =
            colour_mode(&film, &self.camera, &self.materials, &self.point_lights, self.glass_range)
                .map_err(|(field, e)| SceneError::Invalid { path: "command line".into(), field, source: e.into() })?;
        self.colour = colour;
        self.glass_warnings = warnings;
        self.film = film;
        Ok(())
    }

    /// Nearest hit: (primitive, hit).
    pub fn intersect(&self, r: &Ray, t_min: f64, t_max: f64) -> Option<(usize, Hit)> {
        let mut best = self.bvh.as_ref().and_then(|b| b.intersect(&self.shapes, r, t_min, t_max));
        let mut t_max = best.map_or(t_max, |b| b.1.t);
        for &i in &self.linear {
            if let Some(h) = self.shapes[i].intersect(r, t_min, t_max) {
                t_max = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    /// The probability that light sampling picks emitter `prim` (0 when it
    /// is not one).
    pub fn emitter_probability(&self, prim: usize) -> f64 {
        match self.emitters.binary_search(&prim) {
            Ok(k) => self.emitter_cdf[k] - if k == 0 { 0.0 } else { self.emitter_cdf[k - 1] },
            Err(_) => 0.0,
        }
    }

    /// An emitter chosen in proportion to its power from the uniform `u`,
    /// and the probability of that choice.
    pub fn choose_emitter(&self, u: f64) -> Option<(usize, f64)> {
        let k = self.emitter_cdf.partition_point(|c| *c <= u).min(self.emitters.len().checked_sub(1)?);
        let p = self.emitter_cdf[k] - if k == 0 { 0.0 } else { self.emitter_cdf[k - 1] };
        Some((self.emitters[k], p))
    }

    /// Whether primitive `i` is an area light that direct light sampling
    /// picks (bounded and emissive).
    pub fn light_sampled(&self, i: usize) -> bool {
        self.emitters.binary_search(&i).is_ok()
    }

    /// Whether the segment from `a` to `b` is unobstructed.
    pub fn visible(&self, a: DVec3, b: DVec3) -> bool {
        let d = b - a;
        let len = d.length();
        let r = Ray { origin: a, dir: d / len };
        self.intersect(&r, crate::geometry::EPS * (1.0 + a.abs().max_element()), len * (1.0 - 1e-7)).is_none()
    }
}

/// Light sampling's choice of emitter: in proportion to power (the
/// luminance of its radiance times its area), so a sun is picked far more
/// often than a candle; every emitter keeps at least a 1% share of a uniform
/// choice so none is starved.
fn emitter_cdf(emitters: &[usize], shapes: &[Shape], materials: &[Material], material_of: &[usize]) -> Vec<f64> {
    let power: Vec<f64> = emitters
        .iter()
        .map(|&i| match &materials[material_of[i]] {
            Material::Emissive { radiance } => {
                let rgb = radiance.to_rgb();
                (0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z).max(0.0) * shapes[i].area()
            }
            _ => 0.0,
        })
        .collect();
    let total: f64 = power.iter().sum();
    let n = emitters.len() as f64;
    let mut acc = 0.0;
    let mut cdf: Vec<f64> = power
        .iter()
        .map(|p| {
            let share = if total > 0.0 && total.is_finite() { 0.99 * p / total + 0.01 / n } else { 1.0 / n };
            acc += share;
            acc
        })
        .collect();
    if let Some(last) = cdf.last_mut() {
        *last = 1.0;
    }
    cdf
}

/// The files a scene file names, resolved against `dir`.
fn referenced_files(file: &SceneFile, dir: &Path) -> Vec<std::path::PathBuf> {
    let mut v = Vec::new();
    let shape = match &file.camera {
        CameraSpec::Lens { prescription, aperture_shape, .. } => {
            v.push(dir.join(prescription));
            Some(aperture_shape)
        }
        CameraSpec::ThinLens { aperture_shape, .. } => Some(aperture_shape),
        CameraSpec::Pinhole { .. } => None,
    };
    if let Some(ApertureSpec::Mask { image }) = shape {
        v.push(dir.join(image));
    }
    if let BackgroundSpec::Environment { exr, .. } = &file.background {
        v.push(dir.join(exr));
    }
    for s in &file.shapes {
        if let ShapeSpec::Mesh { obj, .. } = s {
            v.push(dir.join(obj));
        }
    }
    v
}

#[cfg(feature = "exr")]
fn load_environment(path: &Path) -> Result<crate::image::Image, FieldError> {
    let img = crate::image::Image::load_exr(path)?;
    if img.pixels.iter().any(|p| !p.is_finite() || p.min_element() < 0.0) {
        return Err(format!("{}: the environment has negative or non-finite pixels", path.display()).into());
    }
    Ok(img)
}

#[cfg(not(feature = "exr"))]
fn load_environment(path: &Path) -> Result<crate::image::Image, FieldError> {
    Err(format!("{}: environment maps need the render crate's `exr` feature", path.display()).into())
}
