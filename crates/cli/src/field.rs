//! `lens field`: distortion, field curvature, spherical aberration and
//! vignetting against field.

use crate::analysis_args::AimArg;
use crate::{load, print_json, CmdResult};
use lens::analysis::curves::field_curves;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Largest field angle, degrees (default: where the chief ray is lost).
    #[arg(long, value_name = "DEG")]
    max_field_deg: Option<f64>,
    /// Number of fields from 0 to the largest.
    #[arg(long, default_value_t = 11)]
    fields: usize,
    /// How pupil coordinates become rays.
    #[arg(long, value_enum, default_value_t = AimArg::Paraxial)]
    aim: AimArg,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    plot: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let p = load(&a.file, None)?;
    let c = field_curves(&p, a.max_field_deg, a.fields, a.aim.into())?;
    if let Some(out) = &a.plot {
        plot::save(&plot::field::field_chart(&c, p.name()), out)?;
    }
    if a.json {
        print_json(&serde_json::to_value(&c)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!("field curves to {:.3} deg on the paraxial image plane z = {:.6} mm", c.max_field_deg, c.image_z);
    println!(
        "{:>8} {:>12} {:>12} {:>11} {:>12} {:>12} {:>9} {:>9}",
        "deg", "height", "paraxial", "dist (%)", "tan (mm)", "sag (mm)", "unvign.", "rel.ill."
    );
    for f in &c.fields {
        println!(
            "{:>8.3} {:>12.6} {:>12.6} {:>11.5} {:>12.6} {:>12.6} {:>9.4} {:>9.4}",
            f.field_deg,
            f.chief_height,
            f.paraxial_height,
            f.distortion_percent,
            f.tangential_focus,
            f.sagittal_focus,
            f.unvignetted_fraction,
            f.relative_illumination
        );
    }
    println!("longitudinal spherical aberration:");
    for z in &c.spherical {
        println!("  pupil {:.2}: {:+.6} mm", z.pupil, z.longitudinal);
    }
    Ok(ExitCode::SUCCESS)
}
