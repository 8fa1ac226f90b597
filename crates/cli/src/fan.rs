//! `lens fan`: tangential and sagittal ray fans at one field.

use crate::analysis_args::{plane, AimArg};
use crate::{load, print_json, CmdResult};
use lens::analysis::{fan::ray_fan, Field};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Field angle in degrees (object at infinity).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    field_deg: f64,
    /// Points per fan, evenly spaced on [-1, 1] (odd includes 0).
    #[arg(long, default_value_t = 21)]
    points: usize,
    /// How pupil coordinates become rays.
    #[arg(long, value_enum, default_value_t = AimArg::Paraxial)]
    aim: AimArg,
    /// Evaluate on a film this many mm behind the last vertex instead of the
    /// paraxial image plane.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    film: Option<f64>,
    /// Resize the stop to this f-number first.
    #[arg(long, value_name = "N")]
    f_number: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    plot: Option<PathBuf>,
    /// Plot these field angles (degrees, comma-separated) instead of
    /// --field-deg alone.
    #[arg(long, value_name = "DEG,DEG", value_parser = crate::analysis_args::parse_list)]
    plot_fields: Option<std::vec::Vec<f64>>,
}

pub fn run(a: Args) -> CmdResult {
    let p = load(&a.file, a.f_number)?;
    let fan = ray_fan(&p, Field::Angle(a.field_deg), a.points, a.aim.into(), plane(a.film))?;
    if let Some(out) = &a.plot {
        let fans = match &a.plot_fields {
            Some(fields) => fields
                .iter()
                .map(|&d| ray_fan(&p, Field::Angle(d), a.points, a.aim.into(), plane(a.film)))
                .collect::<Result<Vec<_>, _>>()?,
            None => vec![fan.clone()],
        };
        plot::save(&plot::fan::fan_chart(&fans, p.name()), out)?;
    }
    if a.json {
        print_json(&serde_json::to_value(&fan)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "ray fan at {} deg on z = {:.6} mm (chief ray at x {:.6}, y {:.6} mm)",
        a.field_deg, fan.image_z, fan.chief[0], fan.chief[1]
    );
    println!("{:>9} {:>14} {:>9} {:>14}", "py", "ey (mm)", "px", "ex (mm)");
    let f = |v: Option<f64>| v.map_or("vignetted".to_string(), |v| format!("{v:.6e}"));
    for (t, s) in fan.tangential.iter().zip(&fan.sagittal) {
        println!("{:>9.4} {:>14} {:>9.4} {:>14}", t.py, f(t.ey), s.px, f(s.ex));
    }
    Ok(ExitCode::SUCCESS)
}
