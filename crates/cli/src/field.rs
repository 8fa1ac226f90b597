//! `lens field`: distortion, field curvature, spherical aberration and
//! vignetting against field.

use crate::args::{AimArgs, JsonArgs, LensArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::curves::field_curves;
use lens::error::Fixed;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    /// Largest field angle, degrees (default: where the chief ray is lost).
    #[arg(long, value_name = "DEG")]
    max_field_deg: Option<f64>,
    /// Number of fields from 0 to the largest.
    #[arg(long, default_value_t = 11)]
    fields: usize,
    #[command(flatten)]
    aim: AimArgs,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_plot(a.plot.plot.as_deref())?;
    let (_, p) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    let c = field_curves(&p, a.max_field_deg, a.fields, a.aim.aim())?;
    if let Some(out) = &a.plot.plot {
        plot::save(&plot::field::field_chart(&c, p.name()), out)?;
    }
    if a.out.json {
        print_json(&serde_json::to_value(&c)?)?;
        return Ok(ExitCode::SUCCESS);
    }
    let object = match p.object_distance_mm() {
        Some(d) if d.is_finite() => format!(" of the object {d} mm in front of the lens"),
        _ => String::new(),
    };
    outln!(
        "field curves to {:.3} deg on the paraxial image plane{object} z = {:.6} mm",
        Fixed(c.max_field_deg),
        Fixed(c.image_z)
    );
    outln!(
        "{:>8} {:>12} {:>12} {:>11} {:>12} {:>12} {:>9} {:>9}",
        "deg",
        "height",
        "paraxial",
        "dist (%)",
        "tan (mm)",
        "sag (mm)",
        "unvign.",
        "rel.ill."
    );
    for f in &c.fields {
        outln!(
            "{:>8.3} {:>12.6} {:>12.6} {:>11.5} {:>12.6} {:>12.6} {:>9.4} {:>9.4}",
            Fixed(f.field_deg),
            Fixed(f.chief_height),
            Fixed(f.paraxial_height),
            Fixed(f.distortion_percent),
            Fixed(f.tangential_focus),
            Fixed(f.sagittal_focus),
            Fixed(f.unvignetted_fraction),
            Fixed(f.relative_illumination)
        );
    }
    outln!("longitudinal spherical aberration:");
    for z in &c.spherical {
        outln!("  pupil {:.2}: {:+.6} mm", Fixed(z.pupil), Fixed(z.longitudinal));
    }
    Ok(ExitCode::SUCCESS)
}
