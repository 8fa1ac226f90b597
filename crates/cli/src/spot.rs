//! `lens spot`: spot diagram statistics at one field.

use crate::analysis_args::{plane, FieldArgs};
use crate::{load, print_json, CmdResult};
use lens::analysis::pattern::Pattern;
use lens::analysis::{spot::spot_diagram, Field};
use serde_json::json;
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
    #[command(flatten)]
    f: FieldArgs,
    /// Pupil pattern.
    #[arg(long, value_enum, default_value_t = PatternArg::Hexapolar)]
    pattern: PatternArg,
    /// Grid width (square), ring count (hexapolar) or ray count (random).
    #[arg(long, default_value_t = 12)]
    n: usize,
}

pub fn run(args: Args) -> CmdResult {
    let a = &args.f;
    let p = load(&a.file, a.f_number)?;
    let pattern = match args.pattern {
        PatternArg::Square => Pattern::Square,
        PatternArg::Hexapolar => Pattern::Hexapolar,
        PatternArg::Random => Pattern::Random,
    };
    let spot_at = |deg: f64| spot_diagram(&p, Field::Angle(deg), pattern, args.n, a.aim.into(), plane(a.film));
    let s = spot_at(a.field_deg)?;
    if let Some(out) = &a.plot {
        let spots = a.plotted_fields().into_iter().map(spot_at).collect::<Result<Vec<_>, _>>()?;
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
