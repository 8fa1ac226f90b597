//! `lens spot`: spot diagram statistics at one field.

use crate::analysis_args::{plane, AimArg};
use crate::{load, print_json, CmdResult};
use lens::analysis::pattern::Pattern;
use lens::analysis::{spot::spot_diagram, Field};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum PatternArg {
    /// n x n grid, points inside the unit circle.
    Square,
    /// n rings of 6k points.
    Hexapolar,
    /// n uniform random points (fixed seed).
    Random,
}

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Field angle in degrees (object at infinity).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    field_deg: f64,
    /// Pupil pattern.
    #[arg(long, value_enum, default_value_t = PatternArg::Hexapolar)]
    pattern: PatternArg,
    /// Grid width (square), ring count (hexapolar) or ray count (random).
    #[arg(long, default_value_t = 12)]
    n: usize,
    /// How pupil coordinates become rays.
    #[arg(long, value_enum, default_value_t = AimArg::Paraxial)]
    aim: AimArg,
    /// Evaluate on a film this many mm behind the last vertex.
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
    let pattern = match a.pattern {
        PatternArg::Square => Pattern::Square,
        PatternArg::Hexapolar => Pattern::Hexapolar,
        PatternArg::Random => Pattern::Random,
    };
    let s = spot_diagram(&p, Field::Angle(a.field_deg), pattern, a.n, a.aim.into(), plane(a.film))?;
    if let Some(out) = &a.plot {
        let spots = match &a.plot_fields {
            Some(fields) => fields
                .iter()
                .map(|&d| spot_diagram(&p, Field::Angle(d), pattern, a.n, a.aim.into(), plane(a.film)))
                .collect::<Result<Vec<_>, _>>()?,
            None => vec![s.clone()],
        };
        plot::save(&plot::spot::spot_chart(&spots, p.name()), out)?;
    }
    if a.json {
        print_json(&json!({
            "field_deg": a.field_deg,
            "image_z": s.image_z,
            "rays": s.rays,
            "vignetted": s.vignetted,
            "aim_failures": s.aim_failures,
            "centroid": s.centroid,
            "rms_radius": s.rms_radius,
            "rms_radius_chief": s.rms_radius_chief,
            "geo_radius": s.geo_radius,
            "geo_radius_chief": s.geo_radius_chief,
            "chief": s.chief,
            "airy_radius": s.airy_radius,
            "best_focus_shift": s.best_focus_shift,
            "rms_radius_best_focus": s.rms_radius_best_focus,
        }));
        return Ok(ExitCode::SUCCESS);
    }
    println!("spot at {} deg on z = {:.6} mm: {} rays, {} vignetted", a.field_deg, s.image_z, s.rays, s.vignetted);
    println!("  centroid            x {:.6e}, y {:.6e} mm", s.centroid[0], s.centroid[1]);
    println!(
        "  RMS radius          {:.6e} mm (about the centroid), {:.6e} mm (about the chief ray)",
        s.rms_radius, s.rms_radius_chief
    );
    println!(
        "  geometric radius    {:.6e} mm (about the centroid), {:.6e} mm (about the chief ray)",
        s.geo_radius, s.geo_radius_chief
    );
    println!("  Airy radius         {:.6e} mm (587.56 nm)", s.airy_radius);
    println!(
        "  best focus          {:+.6e} mm from this plane, RMS radius {:.6e} mm",
        s.best_focus_shift, s.rms_radius_best_focus
    );
    Ok(ExitCode::SUCCESS)
}
