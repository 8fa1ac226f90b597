//! `lens layout`: the cross-section drawing with ray bundles.

use crate::args::{parse_list, AimArgs, LensArgs, WavelengthArgs};
use crate::CmdResult;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    /// Field angles in degrees, comma-separated.
    #[arg(long, value_name = "DEG,DEG", value_parser = parse_list, default_value = "0")]
    fields: std::vec::Vec<f64>,
    /// Rays per field across the pupil.
    #[arg(long, default_value_t = 7)]
    rays: usize,
    #[command(flatten)]
    aim: AimArgs,
    /// Output picture (.svg or .png).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(Some(&a.output), "-o", &["svg", "png"])?;
    let (_, p) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    crate::args::check_fields("--fields", &a.fields)?;
    if a.rays > 1000 || a.fields.len() > 100 {
        return Err("--rays is at most 1000 per field and --fields at most 100 angles".into());
    }
    let svg = plot::layout::layout_chart(&p, &a.fields, a.rays, a.aim.aim());
    plot::save(&svg, &a.output)?;
    Ok(ExitCode::SUCCESS)
}
