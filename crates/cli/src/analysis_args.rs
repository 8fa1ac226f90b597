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
