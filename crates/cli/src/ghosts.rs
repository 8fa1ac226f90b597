//! `lens ghosts`: the paraxial ghost list at one field.

use crate::args::{JsonArgs, LensArgs, PlotArgs};
use crate::{print_json, CmdResult};
use lens::ghost::ghost_list;
use lens::paraxial::FirstOrder;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Field angle in degrees (object at infinity), in the y-z plane.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, default_value_t = 0.0)]
    field_deg: f64,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_plot(a.plot.plot.as_deref())?;
    crate::args::check_fields("--field-deg", &[a.field_deg])?;
    let p = a.lens.load()?;
    let ghosts = ghost_list(&p, a.field_deg)?;
    let first = FirstOrder::of(&p)?;
    let primary = lens::ghost::paraxial::image_height_mm(&p, &first, a.field_deg);
    if let Some(out) = &a.plot.plot {
        let reach = 3.0 * primary.abs().max(first.efl.abs() * 0.5);
        plot::save(&plot::ghost::ghost_chart(&ghosts, primary, reach, a.field_deg, p.name()), out)?;
    }
    if a.out.json {
        print_json(&serde_json::json!({
            "lens": p.name(),
            "field_deg": a.field_deg,
            "wavelength_nm": p.primary_wavelength_nm(),
            "image_height_mm": primary,
            "ghosts": ghosts,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "{} ghosts of {} at {} deg ({} nm; primary image at {:.4} mm)",
        ghosts.len(),
        p.name(),
        lens::error::Fixed(a.field_deg),
        p.primary_wavelength_nm(),
        primary
    );
    outln!("  surfaces   focus z mm   height mm   radius mm   R_i R_j     intensity");
    let mut order: Vec<_> = ghosts.iter().collect();
    order.sort_by(|x, y| y.intensity.unwrap_or(f64::INFINITY).total_cmp(&x.intensity.unwrap_or(f64::INFINITY)));
    for g in order {
        let focus = g.focus_z_mm.map_or("afocal".to_string(), |z| format!("{z:.3}"));
        let intensity = g.intensity.map_or("-".to_string(), |i| format!("{i:.3e}"));
        outln!(
            "  {:>3}-{:<3}  {:>11}  {:>10.4}  {:>10.4}  {:.3e}  {}",
            g.surfaces[0],
            g.surfaces[1],
            focus,
            g.image_height_mm,
            g.radius_mm,
            g.reflectance,
            intensity
        );
    }
    Ok(ExitCode::SUCCESS)
}
