//! Flags shared by the analysis subcommands.

use lens::analysis::fan::ImagePlane;
use lens::analysis::Aim;

/// `--aim paraxial|real`.
#[derive(Clone, Copy, Debug, Default, clap::ValueEnum)]
pub enum AimArg {
    /// Through the paraxial entrance pupil.
    #[default]
    Paraxial,
    /// Real rays aimed at the stop (Newton iteration).
    Real,
}

impl From<AimArg> for Aim {
    fn from(a: AimArg) -> Aim {
        match a {
            AimArg::Paraxial => Aim::Paraxial,
            AimArg::Real => Aim::Real,
        }
    }
}

/// The image plane: paraxial unless a film distance is given.
pub fn plane(film: Option<f64>) -> ImagePlane {
    film.map_or(ImagePlane::Paraxial, ImagePlane::Film)
}

/// Parses "a,b,c" into numbers; `inf` allowed.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("\"{t}\" is not a number")))
        .collect()
}

/// The flags of an analysis at one field (`fan`, `spot`).
#[derive(clap::Args)]
pub struct FieldArgs {
    /// Prescription file (.json or pbrt .dat).
    pub file: std::path::PathBuf,
    /// Field angle in degrees (object at infinity).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    pub field_deg: f64,
    /// How pupil coordinates become rays.
    #[arg(long, value_enum, default_value_t = AimArg::Paraxial)]
    pub aim: AimArg,
    /// Evaluate on a film this many mm behind the last vertex instead of the
    /// paraxial image plane.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub film: Option<f64>,
    /// Resize the stop to this f-number first.
    #[arg(long, value_name = "N")]
    pub f_number: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    pub plot: Option<std::path::PathBuf>,
    /// Plot these field angles (degrees, comma-separated) instead of
    /// --field-deg alone.
    #[arg(long, value_name = "DEG,DEG", value_parser = parse_list)]
    pub plot_fields: Option<std::vec::Vec<f64>>,
}

impl FieldArgs {
    /// The fields to plot.
    pub fn plotted_fields(&self) -> std::vec::Vec<f64> {
        self.plot_fields.clone().unwrap_or_else(|| vec![self.field_deg])
    }
}
