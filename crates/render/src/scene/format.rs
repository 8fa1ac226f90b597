//! The scene file format (JSON, lengths in metres), as written by a user.
//! See docs/scene-format.md.

use serde::Deserialize;
use std::collections::BTreeMap;

/// An RGB triple (linear).
pub type Rgb = [f64; 3];
/// A point or vector, metres.
pub type V3 = [f64; 3];

/// A whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The camera.
    pub camera: CameraSpec,
    /// Image size and sampling.
    pub film: FilmSpec,
    /// What rays that leave the scene see.
    #[serde(default)]
    pub background: BackgroundSpec,
    /// Named materials (a name given twice is an error, not the last one
    /// silently kept).
    #[serde(default, deserialize_with = "unique_keys")]
    pub materials: BTreeMap<String, MaterialSpec>,
    /// The shapes.
    #[serde(default)]
    pub shapes: Vec<ShapeSpec>,
    /// Point lights.
    #[serde(default)]
    pub lights: Vec<LightSpec>,
    /// Keyframes of a frame sequence (`lens animate`; a still render
    /// ignores them).
    #[serde(default)]
    pub animation: Option<crate::animation::AnimationSpec>,
}

/// A JSON object into a map, refusing a key given twice.
fn unique_keys<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: serde::Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct Unique<V>(std::marker::PhantomData<V>);
    impl<'de, V: Deserialize<'de>> serde::de::Visitor<'de> for Unique<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an object of named materials")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some((k, v)) = map.next_entry::<String, V>()? {
                if out.contains_key(&k) {
                    return Err(serde::de::Error::custom(format!(
                        "the material \"{k}\" is defined twice: give each material its own name"
                    )));
                }
                out.insert(k, v);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Unique(std::marker::PhantomData))
}

/// Where the camera is and how it looks.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Camera position (the film centre for a real lens), m.
    pub position: V3,
    /// A point the camera looks at, m.
    pub look_at: V3,
    /// Up direction.
    pub up: V3,
}

fn up() -> V3 {
    [0.0, 1.0, 0.0]
}

/// The shape of a thin or real lens's aperture.
#[derive(Debug, Clone, Deserialize, Default, PartialEq)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum ApertureSpec {
    /// A disc.
    #[default]
    Circle,
    /// A regular polygon inscribed in the aperture circle.
    Polygon {
        /// Number of blades (3 or more).
        blades: u32,
        /// Rotation, degrees.
        #[serde(default)]
        rotation_deg: f64,
    },
    /// A grey-scale image (PNG, relative to the scene file) mapped onto the
    /// square around the aperture circle: white transmits, black blocks.
    Mask {
        /// The image file.
        image: String,
    },
}

/// What autofocus focuses on.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum FocusOn {
    /// The shape with this `name`.
    Shape(String),
    /// The pixel (column, row) from the top left of the film as rendered.
    Pixel([f64; 2]),
}

/// A camera. (Pose fields are repeated in each variant rather than
/// flattened, so that unknown fields are still rejected.)
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum CameraSpec {
    /// An ideal pinhole.
    Pinhole {
        /// Camera position (the film centre for a real lens), m.
        position: V3,
        /// A point the camera looks at, m.
        look_at: V3,
        /// Up direction (default +y).
        #[serde(default = "up")]
        up: V3,
        /// Vertical field of view, degrees.
        fov_deg: f64,
    },
    /// Cook-style thin lens: rays from a point of the aperture toward the
    /// point of the focal plane that the pinhole ray meets.
    ThinLens {
        /// Camera position (the film centre for a real lens), m.
        position: V3,
        /// A point the camera looks at, m.
        look_at: V3,
        /// Up direction (default +y).
        #[serde(default = "up")]
        up: V3,
        /// Vertical field of view, degrees.
        fov_deg: f64,
        /// Aperture diameter, m (0 = pinhole). Or give `f_number` and
        /// `focal_length_mm`.
        #[serde(default)]
        aperture: Option<f64>,
        /// f-number (with `focal_length_mm`).
        #[serde(default)]
        f_number: Option<f64>,
        /// Focal length, mm (with `f_number`).
        #[serde(default)]
        focal_length_mm: Option<f64>,
        /// Distance from the film plane to the plane in focus, m. With
        /// `focal_length_mm` the film sits at the image distance behind the
        /// lens (1/s + 1/s' = 1/f); without it the model has no film
        /// distance and this is measured from the lens. Or give `focus_on`.
        #[serde(default)]
        focus_distance: Option<f64>,
        /// Autofocus: a shape's `name`, or a pixel `[column, row]` from the
        /// top left; the focus distance is found by tracing the scene there.
        #[serde(default)]
        focus_on: Option<FocusOn>,
        /// Aperture shape.
        #[serde(default)]
        aperture_shape: ApertureSpec,
        /// The cheap trick of the original study: shorten the focal distance
        /// linearly with the sample's distance from the lens centre (0 = off;
        /// 0.1 = 10% shorter at the rim), imitating spherical aberration.
        #[serde(default)]
        focus_shift: f64,
        /// A glass for the lens (`"SCHOTT:N-BK7"`, with `focal_length_mm`):
        /// its focal length follows the glass's dispersion, f(λ) = f
        /// (nd - 1) / (n(λ) - 1), the cheap model of axial colour.
        #[serde(default)]
        glass: Option<String>,
    },
    /// A real lens traced surface by surface.
    Lens {
        /// Camera position (the film centre for a real lens), m.
        position: V3,
        /// A point the camera looks at, m.
        look_at: V3,
        /// Up direction (default +y).
        #[serde(default = "up")]
        up: V3,
        /// Prescription file (JSON, pbrt .dat or Zemax .zmx), relative to the scene file.
        prescription: String,
        /// f-number (resizes the stop).
        #[serde(default)]
        f_number: Option<f64>,
        /// Or the stop's clear radius, mm.
        #[serde(default)]
        stop_semi_diameter: Option<f64>,
        /// Distance from the film plane to the plane in focus, m (the film
        /// placed at its exact paraxial focus). Or give `focus_on`.
        #[serde(default)]
        focus_distance: Option<f64>,
        /// Autofocus: a shape's `name`, or a pixel `[column, row]` from the
        /// top left; the film is moved to the real-ray best focus of the
        /// point found there.
        #[serde(default)]
        focus_on: Option<FocusOn>,
        /// Sensor width and height, mm.
        sensor_mm: [f64; 2],
        /// Aperture shape (applied at the stop).
        #[serde(default)]
        aperture_shape: ApertureSpec,
        /// Every surface's coating, overriding the prescription's (its
        /// own, or MgF2 on air-glass surfaces by default): `"none"`,
        /// `"MgF2"`, or thin films `[{"index", "thickness_nm"}, ...]`.
        /// Sets how bright the ghosts of `film.flare` are.
        #[serde(default)]
        coating: Option<lens::model::CoatingSpec>,
    },
}

/// Image size and sampling.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilmSpec {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Samples per pixel.
    #[serde(default = "spp")]
    pub spp: u32,
    /// Exposure multiplier applied before tone mapping (PNG only).
    #[serde(default = "one")]
    pub exposure: f64,
    /// Pixel reconstruction filter.
    #[serde(default)]
    pub filter: FilterSpec,
    /// RGB or spectral transport (default: spectral exactly when the scene
    /// has a dispersive lens or material or a light given as a spectrum).
    #[serde(default)]
    pub spectral: SpectralSpec,
    /// Render one wavelength only, nm (a grey image of the radiance there):
    /// the lens's image at a spectral line.
    #[serde(default)]
    pub wavelength_nm: Option<f64>,
    /// Which spectral samples trace their companion wavelengths through a
    /// real lens with glasses.
    #[serde(default)]
    pub companions: CompanionsSpec,
    /// Lens flare through a real lens: `"off"` (default), `"ghosts"`
    /// (every two-reflection ghost of the bright lamps and sky), or
    /// `"ghosts+glare"` (and the veiling glare of the higher-order
    /// reflections).
    #[serde(default)]
    pub flare: FlareSpec,
    /// Diffraction at a real lens's aperture: `"off"` (default) or `"on"`
    /// (the film convolved with the aperture's diffraction pattern:
    /// starbursts, the Airy blur; docs/rendering.md).
    #[serde(default)]
    pub diffraction: DiffractionSpec,
}

/// Whether a real-lens render adds diffraction at the aperture.
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DiffractionSpec {
    /// Geometric optics alone.
    #[default]
    Off,
    /// The aperture's diffraction pattern applied to the film.
    On,
}

impl std::str::FromStr for DiffractionSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "off" => Ok(DiffractionSpec::Off),
            "on" => Ok(DiffractionSpec::On),
            _ => Err(format!("{s}: write off or on")),
        }
    }
}

/// Which lens flare a real-lens render adds (docs/rendering.md).
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub enum FlareSpec {
    /// None: the lens passes all its light to the primary image.
    #[default]
    #[serde(rename = "off")]
    Off,
    /// The ghosts of two reflections, of the scene's bright sources; the
    /// primary image loses what the surfaces reflect.
    #[serde(rename = "ghosts")]
    Ghosts,
    /// The ghosts and a veil of the light reflected four or more times.
    #[serde(rename = "ghosts+glare")]
    GhostsAndGlare,
}

impl std::str::FromStr for FlareSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "off" => Ok(FlareSpec::Off),
            "ghosts" => Ok(FlareSpec::Ghosts),
            "ghosts+glare" => Ok(FlareSpec::GhostsAndGlare),
            _ => Err(format!("{s}: write off, ghosts or ghosts+glare")),
        }
    }
}

/// Which spectral samples trace their companion wavelengths through a real
/// lens with glasses (each costs a lens trace; docs/rendering.md).
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum CompanionsSpec {
    /// Those bright enough for their colour to matter (a pilot sets the
    /// threshold); the others keep their hero alone: faster where bright
    /// highlights dominate, with more colour noise in dim regions.
    #[default]
    Auto,
    /// Every sample: the least colour noise, the most lens traces.
    All,
}

/// When a render carries wavelengths.
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SpectralSpec {
    /// Spectral when something in the scene depends on wavelength.
    #[default]
    Auto,
    /// Always spectral.
    On,
    /// Always RGB: glasses at the d line (587.56 nm), a real lens at its
    /// primary wavelength, spectral lights by their sRGB colour.
    Off,
}

/// Emitted radiance: linear sRGB `[r, g, b]`, or a spectrum scaled to a
/// luminance.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum RadianceSpec {
    /// Linear sRGB.
    Rgb(Rgb),
    /// A spectrum.
    Spectrum(SpectrumSpec),
}

/// A light's spectrum: `{"blackbody_k": 3200}` or `{"illuminant": "D65"}`
/// (or `"A"`), with its luminance Y (default 1: as bright as RGB
/// [1, 1, 1]).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpectrumSpec {
    /// A black body at this temperature, K.
    #[serde(default)]
    pub blackbody_k: Option<f64>,
    /// A CIE illuminant: "D65" or "A".
    #[serde(default)]
    pub illuminant: Option<String>,
    /// Luminance Y (W / (m^2 sr) weighted by the CIE luminosity curve,
    /// on the scale where RGB white [1, 1, 1] has Y = 1).
    #[serde(default = "one")]
    pub luminance: f64,
}

fn spp() -> u32 {
    16
}
fn one() -> f64 {
    1.0
}

/// Pixel filters.
#[derive(Debug, Clone, Copy, Deserialize, Default, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum FilterSpec {
    /// Samples uniform over the pixel, equal weights.
    #[default]
    Box,
    /// Samples over two pixels' width with tent-distributed offsets.
    Tent,
}

/// The background.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum BackgroundSpec {
    /// Uniform radiance.
    Constant {
        /// Radiance.
        radiance: Rgb,
    },
    /// An equirectangular (latitude-longitude) OpenEXR environment:
    /// +y up, the image centre toward +z.
    Environment {
        /// The EXR file, relative to the scene file.
        exr: String,
        /// Radiance multiplier.
        #[serde(default = "one")]
        intensity: f64,
    },
    /// A gradient from the horizon to the zenith (below the horizon:
    /// `ground`).
    Sky {
        /// At the horizon.
        horizon: Rgb,
        /// Straight up.
        zenith: Rgb,
        /// Below the horizon.
        #[serde(default)]
        ground: Rgb,
    },
}

impl Default for BackgroundSpec {
    fn default() -> Self {
        BackgroundSpec::Constant { radiance: [0.0; 3] }
    }
}

/// A material.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialSpec {
    /// Lambertian.
    Diffuse {
        /// Albedo in [0, 1].
        color: Rgb,
    },
    /// Lambertian checkerboard.
    Checker {
        /// First colour.
        a: Rgb,
        /// Second colour.
        b: Rgb,
        /// Square size (m on planes, 0..1 on quads and spheres).
        scale: f64,
    },
    /// Light emitter.
    Emissive {
        /// Radiance: linear sRGB, or a spectrum.
        radiance: RadianceSpec,
    },
    /// Mirror.
    Mirror {
        /// Reflectance.
        #[serde(default = "white")]
        tint: Rgb,
    },
    /// Glass of a constant index.
    Glass {
        /// Refractive index.
        ior: f64,
    },
    /// A smooth dielectric: a constant `ior`, or a catalogue `glass`
    /// (`"SCHOTT:N-BK7"`) whose index follows the wavelength (a prism
    /// splits white light).
    Dielectric {
        /// Refractive index.
        #[serde(default)]
        ior: Option<f64>,
        /// Catalogue glass, `VENDOR:NAME`.
        #[serde(default)]
        glass: Option<String>,
    },
}

fn white() -> Rgb {
    [1.0; 3]
}

/// A shape with its material name.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A sphere.
    Sphere {
        /// Centre, m.
        center: V3,
        /// Radius, m.
        radius: f64,
        /// Material name.
        material: String,
        /// A name (for `focus_on`), unique in the scene.
        #[serde(default)]
        name: Option<String>,
    },
    /// An infinite plane.
    Plane {
        /// A point on it.
        point: V3,
        /// Its normal.
        normal: V3,
        /// Material name.
        material: String,
        /// A name (for `focus_on`), unique in the scene.
        #[serde(default)]
        name: Option<String>,
    },
    /// A parallelogram corner + s u + t v.
    Quad {
        /// Corner.
        corner: V3,
        /// First edge.
        u: V3,
        /// Second edge.
        v: V3,
        /// Material name.
        material: String,
        /// A name (for `focus_on`), unique in the scene.
        #[serde(default)]
        name: Option<String>,
    },
    /// An axis-aligned box.
    Box {
        /// Minimum corner.
        min: V3,
        /// Maximum corner.
        max: V3,
        /// Material name.
        material: String,
        /// A name (for `focus_on`), unique in the scene.
        #[serde(default)]
        name: Option<String>,
    },
    /// A Wavefront OBJ triangle mesh.
    Mesh {
        /// OBJ file, relative to the scene file.
        obj: String,
        /// Uniform scale.
        #[serde(default = "unit")]
        scale: f64,
        /// Translation, m.
        #[serde(default)]
        translate: V3,
        /// Material name.
        material: String,
        /// A name (for `focus_on`), unique in the scene.
        #[serde(default)]
        name: Option<String>,
    },
}

fn unit() -> f64 {
    1.0
}

/// A light that is not a shape.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightSpec {
    /// An isotropic point light.
    Point {
        /// Position, m.
        position: V3,
        /// Intensity, W / sr per channel, or a spectrum.
        intensity: RadianceSpec,
    },
}

impl ShapeSpec {
    /// The shape's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        match self {
            ShapeSpec::Sphere { name, .. }
            | ShapeSpec::Plane { name, .. }
            | ShapeSpec::Quad { name, .. }
            | ShapeSpec::Box { name, .. }
            | ShapeSpec::Mesh { name, .. } => name.as_deref(),
        }
    }
}

impl CameraSpec {
    /// The focus distance given (m), `None` for a pinhole or autofocus.
    pub fn focus_distance(&self) -> Option<f64> {
        match self {
            CameraSpec::Pinhole { .. } => None,
            CameraSpec::ThinLens { focus_distance, .. } | CameraSpec::Lens { focus_distance, .. } => *focus_distance,
        }
    }

    /// What autofocus focuses on, if it is asked for.
    pub fn focus_on(&self) -> Option<&FocusOn> {
        match self {
            CameraSpec::Pinhole { .. } => None,
            CameraSpec::ThinLens { focus_on, .. } | CameraSpec::Lens { focus_on, .. } => focus_on.as_ref(),
        }
    }

    /// Sets the focus distance and the autofocus target (a pinhole has
    /// neither: unchanged).
    pub fn set_focus(&mut self, distance: Option<f64>, on: Option<FocusOn>) {
        match self {
            CameraSpec::Pinhole { .. } => {}
            CameraSpec::ThinLens { focus_distance, focus_on, .. }
            | CameraSpec::Lens { focus_distance, focus_on, .. } => {
                *focus_distance = distance;
                *focus_on = on;
            }
        }
    }

    /// The camera's pose.
    pub fn pose(&self) -> Pose {
        match self {
            CameraSpec::Pinhole { position, look_at, up, .. }
            | CameraSpec::ThinLens { position, look_at, up, .. }
            | CameraSpec::Lens { position, look_at, up, .. } => {
                Pose { position: *position, look_at: *look_at, up: *up }
            }
        }
    }
}
