//! `lens layout`: the cross-section drawing with ray bundles.

use crate::analysis_args::{parse_list, AimArg};
use crate::{load, CmdResult};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Field angles in degrees, comma-separated.
    #[arg(long, value_name = "DEG,DEG", value_parser = parse_list, default_value = "0")]
    fields: std::vec::Vec<f64>,
    /// Rays per field across the pupil.
    #[arg(long, default_value_t = 7)]
    rays: usize,
    /// How pupil coordinates become rays.
    #[arg(long, value_enum, default_value_t = AimArg::Paraxial)]
    aim: AimArg,
    /// Resize the stop to this f-number first.
    #[arg(long, value_name = "N")]
    f_number: Option<f64>,
    /// Output picture (.svg or .png).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    let p = load(&a.file, a.f_number)?;
    if a.rays > 1000 || a.fields.len() > 100 {
        return Err("--rays is at most 1000 per field and --fields at most 100 angles".into());
    }
    let svg = plot::layout::layout_chart(&p, &a.fields, a.rays, a.aim.into());
    plot::save(&svg, &a.output)?;
    Ok(ExitCode::SUCCESS)
}
