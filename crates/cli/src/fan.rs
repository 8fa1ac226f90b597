//! `lens fan`: tangential and sagittal ray fans at one field.

use crate::args::{AimArgs, FieldArgs, FieldPlotArgs, JsonArgs, LensArgs, PlaneArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::fan::fan_traced;
use lens::analysis::{Field, Launcher};
use lens::error::Fixed;
use lens::paraxial::FirstOrder;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    field: FieldArgs,
    #[command(flatten)]
    aim: AimArgs,
    #[command(flatten)]
    plane: PlaneArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    /// Points per fan, evenly spaced on [-1, 1] (odd includes 0; at least 2).
    #[arg(long, default_value_t = 21)]
    points: usize,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: FieldPlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_plot(a.plot.plot.as_deref())?;
    let plane = a.plane.plane()?;
    let (p, traced) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    if a.points < 2 {
        return Err(format!("--points {}: a fan needs at least 2 points", a.points).into());
    }
    let first = FirstOrder::of(&p)?;
    a.field.check()?;
    let fan_at = |(x, y): (f64, f64)| -> Result<_, lens::OpticsError> {
        let launcher = Launcher::with_first(&p, &first, Field::at_angles(&p, &first, x, y), a.aim.aim())?;
        fan_traced(&p, &traced, &launcher, a.points, plane)
    };
    let fan = fan_at((a.field.field_x_deg, a.field.field_deg))?;
    if let Some(out) = &a.plot.plot {
        let fields = a.plot.fields(&a.field)?;
        let fans = fields.into_iter().map(fan_at).collect::<Result<Vec<_>, _>>()?;
        plot::save(&plot::fan::fan_chart(&fans, p.name()), out)?;
    }
    if a.out.json {
        print_json(&serde_json::to_value(&fan)?)?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "ray fan at {} on {} (chief ray at x {:.6}, y {:.6} mm)",
        a.field.describe(),
        crate::args::describe_plane(plane, fan.image_z),
        Fixed(fan.chief[0]),
        Fixed(fan.chief[1])
    );
    outln!("{:>9} {:>14} {:>9} {:>14}", "py", "ey (mm)", "px", "ex (mm)");
    let f = |v: Option<f64>| v.map_or("vignetted".to_string(), |v| format!("{v:.6e}"));
    for (t, s) in fan.tangential.iter().zip(&fan.sagittal) {
        outln!("{:>9.4} {:>14} {:>9.4} {:>14}", Fixed(t.py), f(t.ey), Fixed(s.px), f(s.ex));
    }
    Ok(ExitCode::SUCCESS)
}
