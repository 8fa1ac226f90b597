//! Every flag shared by more than one subcommand, declared once: the
//! prescription and its stop (`FILE`, `--f-number`), the object
//! (`--object-distance`), the field (`--field-deg`), the aiming (`--aim`)
//! and the outputs (`--json`, `--plot`). A subcommand flattens the groups it
//! takes, so a flag is spelled, parsed and documented the same everywhere.

use lens::analysis::fan::ImagePlane;
use lens::analysis::Aim;
use lens::paraxial::ObjectDistance;
use std::path::PathBuf;

/// The prescription and an optional new stop size.
#[derive(clap::Args, Debug, Clone)]
pub struct LensArgs {
    /// Prescription file (.json, pbrt .dat or Zemax .zmx).
    pub file: PathBuf,
    /// Resize the stop so the paraxial f-number (object at infinity) is N;
    /// refused, naming the limiting surface, when the other clear
    /// apertures cannot pass it.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub f_number: Option<f64>,
    #[command(flatten)]
    pub catalogs: GlassArgs,
}

impl LensArgs {
    /// The files this reads: the prescription and any user catalogues.
    pub fn inputs(&self) -> Vec<PathBuf> {
        std::iter::once(self.file.clone()).chain(self.catalogs.glass_catalogs.iter().cloned()).collect()
    }

    /// Checks an output file of this command (`flag` names it) against the
    /// inputs before any work: see [`crate::outputs::check`].
    pub fn check_output(&self, path: Option<&std::path::Path>, flag: &str, extensions: &[&str]) -> Result<(), String> {
        match path {
            Some(path) => crate::outputs::check(&[crate::outputs::Output { path, flag, extensions }], &self.inputs()),
            None => Ok(()),
        }
    }

    /// Checks a `--plot` file: .svg or .png, not an input.
    pub fn check_plot(&self, path: Option<&std::path::Path>) -> Result<(), String> {
        self.check_output(path, "--plot", &["svg", "png"])
    }

    /// Loads the prescription as the file has it (its stop not resized).
    pub fn load_as_written(&self) -> Result<lens::Prescription, Box<dyn std::error::Error>> {
        let extra = self.catalogs.user_catalogs()?;
        let p = lens::Prescription::load_with(&self.file, extra)?;
        for w in p.warnings() {
            crate::warnings::warn("prescription", w);
        }
        Ok(p)
    }

    /// Loads the prescription (at its primary wavelength, its glasses'
    /// range reported there: [`GlassArgs::report`]) and resizes its stop if
    /// asked.
    pub fn load(&self) -> Result<lens::Prescription, Box<dyn std::error::Error>> {
        let p = self.load_as_written()?;
        self.catalogs.report(&p, &[p.primary_wavelength_nm()])?;
        Ok(match self.f_number {
            Some(n) => lens::analysis::aperture::with_f_number(&p, n)?,
            None => p,
        })
    }

    /// The prescription at its primary wavelength, and at `wavelength_nm`
    /// (the primary when not given).
    pub fn load_at(
        &self,
        wavelength_nm: Option<f64>,
    ) -> Result<(lens::Prescription, lens::Prescription), Box<dyn std::error::Error>> {
        let p = self.load()?;
        let at = match wavelength_nm {
            Some(w) if !(w.is_finite() && w > 0.0) => {
                return Err(
                    format!("--wavelength-nm {}: give a positive wavelength in nm", lens::error::exact(w)).into()
                )
            }
            Some(w) => {
                self.catalogs.report(&p, &[w])?;
                p.at_wavelength(w)?
            }
            None => p.clone(),
        };
        Ok((p, at))
    }

    /// The prescription's name, or the file's when it has none.
    pub fn name(&self, p: &lens::Prescription) -> String {
        if p.name().is_empty() {
            self.file.display().to_string()
        } else {
            p.name().to_string()
        }
    }
}

/// Where the object is.
#[derive(clap::Args, Debug, Clone)]
pub struct ObjectArgs {
    /// Object distance in mm in front of the first vertex (`inf` for
    /// infinity; default: the prescription's `object_distance_mm`, or
    /// infinity).
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub object_distance: Option<f64>,
}

impl ObjectArgs {
    /// The object: the flag's, else the prescription's design distance,
    /// else infinity.
    pub fn object(&self, p: &lens::Prescription) -> Result<ObjectDistance, lens::OpticsError> {
        ObjectDistance::from_mm(self.object_distance.or(p.object_distance_mm()).unwrap_or(f64::INFINITY))
    }
}

/// One field: its angle in y, and in x.
#[derive(clap::Args, Debug, Clone)]
pub struct FieldArgs {
    /// Field angle in degrees: the chief ray's angle in object space (object
    /// at infinity, or at the prescription's design object distance when it
    /// has one), in the y-z plane.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    pub field_deg: f64,
    /// The field's x component, degrees: the chief ray's angle in the x-z
    /// plane (Zemax's and optiland's component angles: the direction is
    /// (tan x, tan y, 1) normalised). For lenses with decentred or tilted
    /// surfaces, which are not symmetric about the y-z plane.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    pub field_x_deg: f64,
}

impl FieldArgs {
    /// Both angles checked (each above -90 and below 90 degrees).
    pub fn check(&self) -> Result<(), String> {
        check_fields("--field-deg", &[self.field_deg])?;
        check_fields("--field-x-deg", &[self.field_x_deg])
    }

    /// The field for `p` ([`lens::analysis::Field::at_angles`]).
    pub fn field(&self, p: &lens::Prescription, first: &lens::paraxial::FirstOrder) -> lens::analysis::Field {
        lens::analysis::Field::at_angles(p, first, self.field_x_deg, self.field_deg)
    }

    /// The field in words for headings: `10 deg`, or `x 2 deg, y 10 deg`.
    pub fn describe(&self) -> String {
        if self.field_x_deg == 0.0 {
            format!("{} deg", lens::error::Fixed(self.field_deg))
        } else {
            format!("x {} deg, y {} deg", lens::error::Fixed(self.field_x_deg), lens::error::Fixed(self.field_deg))
        }
    }

    /// Refuses an x component where `what` takes fields along y only.
    pub fn y_only(&self, what: &str) -> Result<(), String> {
        if self.field_x_deg == 0.0 {
            return Ok(());
        }
        Err(format!(
            "--field-x-deg {}: {what} takes fields along y only; drop --field-x-deg (a lens symmetric about its axis images an x field as the y field of the same angle, turned)",
            lens::error::exact(self.field_x_deg)
        ))
    }

    /// The JSON report `v` with `field_x_deg` added when the field has an
    /// x component ([`lens::report::with_field_x`]).
    pub fn report(&self, v: serde_json::Value) -> serde_json::Value {
        lens::report::with_field_x(v, self.field_x_deg)
    }
}

/// `--aim paraxial|real|auto`.
#[derive(Clone, Copy, Debug, Default, clap::ValueEnum)]
pub enum AimArg {
    /// Paraxial aiming, unless it misses the stop, then real aiming.
    #[default]
    Auto,
    /// Through the paraxial entrance pupil.
    Paraxial,
    /// Real rays aimed at the stop (Newton iteration).
    Real,
}

/// How pupil coordinates become rays.
#[derive(clap::Args, Debug, Clone)]
pub struct AimArgs {
    /// How pupil coordinates become rays: auto (paraxial where the paraxial
    /// chief ray meets the stop near its centre, real otherwise),
    /// paraxial, or real.
    #[arg(long, value_enum, default_value_t = AimArg::Auto)]
    pub aim: AimArg,
}

impl AimArgs {
    /// The aiming for the library.
    pub fn aim(&self) -> Aim {
        match self.aim {
            AimArg::Auto => Aim::Auto,
            AimArg::Paraxial => Aim::Paraxial,
            AimArg::Real => Aim::Real,
        }
    }
}

/// The image plane of an analysis.
#[derive(clap::Args, Debug, Clone)]
pub struct PlaneArgs {
    /// Where to evaluate: `image` (the prescription's image surface, its
    /// last thickness behind the last vertex, as Zemax and optiland do;
    /// the default), `paraxial` (the paraxial image plane of the field's
    /// object), or a film distance in mm behind the last vertex.
    #[arg(long, value_name = "image|paraxial|MM", allow_hyphen_values = true)]
    pub film: Option<String>,
}

impl PlaneArgs {
    /// The image plane: the prescription's image surface unless `--film`
    /// says otherwise; a film that is not behind the last vertex is
    /// refused (as `focus` refuses it).
    pub fn plane(&self) -> Result<ImagePlane, String> {
        let Some(text) = self.film.as_deref().map(str::trim) else {
            return Ok(ImagePlane::ImageSurface);
        };
        match text.to_ascii_lowercase().as_str() {
            "image" | "image-surface" => return Ok(ImagePlane::ImageSurface),
            "paraxial" => return Ok(ImagePlane::Paraxial),
            _ => {}
        }
        let d: f64 = text.parse().map_err(|_| {
            format!("--film {text}: give image (the prescription's image surface), paraxial, or a distance in mm behind the last vertex")
        })?;
        match d {
            d if d.is_finite() && d > 0.0 => Ok(ImagePlane::Film(d)),
            d if d.is_finite() => Err(format!(
                "--film {}: the film would be inside the lens, {} mm in front of the last vertex; give a distance behind it (> 0 mm)",
                lens::error::exact(d),
                lens::error::num(-d)
            )),
            d => Err(format!("--film {d}: give a finite distance in mm behind the last vertex")),
        }
    }
}

/// How an output names `plane`, at `z` mm from the first vertex.
pub fn describe_plane(plane: ImagePlane, z: f64) -> String {
    let what = match plane {
        ImagePlane::ImageSurface => "the prescription's image surface".to_string(),
        ImagePlane::Paraxial => "the paraxial image plane".to_string(),
        ImagePlane::Film(d) => format!("a film {} mm behind the last vertex", lens::error::exact(d)),
    };
    format!("{what}, z = {:.6} mm", lens::error::Fixed(z))
}

/// A list of field angles from the flag `flag`: at least one, each finite
/// and within (-90, 90) degrees.
pub fn check_fields(flag: &str, fields: &[f64]) -> Result<(), String> {
    if fields.is_empty() {
        return Err(format!("{flag}: give at least one field angle in degrees (e.g. 0,10,20)"));
    }
    match fields.iter().find(|f| !(f.is_finite() && f.abs() < 90.0)) {
        Some(f) => Err(format!(
            "{flag}: {} is not a field angle: give angles above -90 and below 90 degrees",
            lens::error::exact(*f)
        )),
        None => Ok(()),
    }
}

/// `--grid N`: the pupil grid of the wave analyses.
#[derive(clap::Args, Debug, Clone)]
pub struct GridArgs {
    /// Pupil samples across the diameter: an N x N grid, each cell weighted
    /// by its area inside the pupil. Default: 64, or finer where the
    /// wavefront needs it (neighbouring samples within half a wave), up to
    /// 1024; a grid given here that is too coarse is refused.
    #[arg(long, value_name = "N")]
    pub grid: Option<usize>,
}

impl GridArgs {
    /// The wavefront of `launcher`'s field through `traced` on `plane`, on
    /// the grid asked for or the one the wavefront needs.
    pub fn wavefront(
        &self,
        p: &lens::Prescription,
        traced: &lens::Prescription,
        launcher: &lens::analysis::Launcher,
        plane: ImagePlane,
    ) -> Result<lens::analysis::wave::Wavefront, lens::OpticsError> {
        match self.grid {
            Some(n) => lens::analysis::wave::wavefront(p, traced, launcher, n, plane),
            None => lens::analysis::wave::wavefront_auto(p, traced, launcher, plane),
        }
    }
}

/// `--json`.
#[derive(clap::Args, Debug, Clone)]
pub struct JsonArgs {
    /// Print JSON (one object on one line) instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// `--plot OUT`.
#[derive(clap::Args, Debug, Clone)]
pub struct PlotArgs {
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    pub plot: Option<PathBuf>,
}

/// `--plot OUT` with `--plot-fields` for the analyses at one field.
#[derive(clap::Args, Debug, Clone)]
pub struct FieldPlotArgs {
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    pub plot: Option<PathBuf>,
    /// Plot these field angles (degrees, comma-separated) instead of
    /// --field-deg alone.
    #[arg(long, value_name = "DEG,DEG", value_parser = parse_list)]
    pub plot_fields: Option<std::vec::Vec<f64>>,
}

impl FieldPlotArgs {
    /// The fields to plot, `(x, y)` degrees: --plot-fields (each checked,
    /// along y), or the analysed field alone.
    pub fn fields(&self, field: &FieldArgs) -> Result<std::vec::Vec<(f64, f64)>, String> {
        match &self.plot_fields {
            Some(f) => {
                field.y_only("--plot-fields")?;
                check_fields("--plot-fields", f).map(|_| f.iter().map(|&y| (0.0, y)).collect())
            }
            None => Ok(vec![(field.field_x_deg, field.field_deg)]),
        }
    }
}

/// Parses "a,b,c" into numbers; `inf` allowed.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("\"{t}\" is not a number")))
        .collect()
}

/// `--wavelength-nm W`.
#[derive(clap::Args, Debug, Clone)]
pub struct WavelengthArgs {
    /// Wavelength in nm (default: the d line, 587.5618 nm, or the
    /// prescription's primary wavelength).
    #[arg(long, value_name = "NM")]
    pub wavelength_nm: Option<f64>,
}

/// `--width`, `--height`, `--spp`: the film of a study's every cell or a
/// sequence's every frame.
#[derive(clap::Args, Debug, Clone)]
pub struct FilmArgs {
    /// Film width, pixels (overrides the scene's; alone, the height
    /// follows the scene's aspect).
    #[arg(long)]
    pub width: Option<u32>,
    /// Film height, pixels (alone, the width follows the scene's aspect).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel (overrides the scene's).
    #[arg(long)]
    pub spp: Option<u32>,
}

impl FilmArgs {
    /// As scene overrides, with the glass range asked for.
    pub fn overrides(&self, glass: &GlassRangeArgs) -> ::render::scene::Overrides {
        ::render::scene::Overrides {
            width: self.width,
            height: self.height,
            spp: self.spp,
            strict_glass_range: glass.strict_glass_range,
            ..Default::default()
        }
    }
}

/// `--strict-glass-range`, for the analyses and the renders alike.
#[derive(clap::Args, Debug, Clone)]
pub struct GlassRangeArgs {
    /// Refuse a wavelength outside a glass's stated data range instead of
    /// extrapolating its formula there with a warning (a render's spectral
    /// range is then narrowed to every glass's data).
    #[arg(long)]
    pub strict_glass_range: bool,
}

impl GlassRangeArgs {
    /// What to do outside a glass's data.
    pub fn range(&self) -> lens::glass::GlassRange {
        if self.strict_glass_range {
            lens::glass::GlassRange::Strict
        } else {
            lens::glass::GlassRange::Extrapolate
        }
    }
}

/// `--glass-catalog FILE`, repeatable, and `--strict-glass-range`.
#[derive(clap::Args, Debug, Clone)]
pub struct GlassArgs {
    /// A Zemax AGF glass catalogue to search before the shipped ones
    /// (repeatable; UTF-16, UTF-8 or Latin-1).
    #[arg(long = "glass-catalog", value_name = "FILE")]
    pub glass_catalogs: Vec<PathBuf>,
    #[command(flatten)]
    pub range: GlassRangeArgs,
}

impl GlassArgs {
    /// What to do outside a glass's data.
    pub fn range(&self) -> lens::glass::GlassRange {
        self.range.range()
    }

    /// Checks `p`'s glasses at `wavelengths_nm`: a warning for each glass
    /// used outside its data, or the error that refuses it
    /// (`--strict-glass-range`, or no index there).
    pub fn report(&self, p: &lens::Prescription, wavelengths_nm: &[f64]) -> Result<(), lens::glass::GlassError> {
        for w in p.glass_range(wavelengths_nm, self.range())? {
            crate::warnings::glass_range(&w);
        }
        Ok(())
    }

    /// The user's catalogues.
    pub fn user_catalogs(&self) -> Result<Vec<lens::glass::Catalog>, lens::glass::GlassError> {
        self.glass_catalogs.iter().map(|p| lens::glass::agf::load(p)).collect()
    }

    /// The user's catalogues and the shipped ones.
    pub fn load(&self) -> Result<lens::glass::Catalogs, lens::glass::GlassError> {
        Ok(lens::glass::Catalogs::with(self.user_catalogs()?))
    }
}
