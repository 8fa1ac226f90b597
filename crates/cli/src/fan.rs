//! `lens fan`: tangential and sagittal ray fans at one field.

use crate::analysis_args::{plane, FieldArgs};
use crate::{load, print_json, CmdResult};
use lens::analysis::{fan::ray_fan, Field};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    f: FieldArgs,
    /// Points per fan, evenly spaced on [-1, 1] (odd includes 0).
    #[arg(long, default_value_t = 21)]
    points: usize,
}

pub fn run(args: Args) -> CmdResult {
    let a = &args.f;
    let p = load(&a.file, a.f_number)?;
    let fan_at = |deg: f64| ray_fan(&p, Field::Angle(deg), args.points, a.aim.into(), plane(a.film));
    let fan = fan_at(a.field_deg)?;
    if let Some(out) = &a.plot {
        let fans = a.plotted_fields().into_iter().map(fan_at).collect::<Result<Vec<_>, _>>()?;
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
