//! `lens chromatic`: focal shift against wavelength, lateral colour against
//! field, the polychromatic spot and the fans of each wavelength.

use crate::args::{AimArgs, FieldArgs, JsonArgs, LensArgs, PlotArgs};
use crate::{print_json, CmdResult};
use lens::analysis::chromatic::{chromatic, default_max_field_deg};
use lens::error::Fixed;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Field angle in degrees of the spot and the fans (a chief-ray angle;
    /// for a design at a finite object distance, the object point whose
    /// chief ray makes it).
    #[command(flatten)]
    field: FieldArgs,
    /// Largest field of the lateral-colour curve, degrees (default: the
    /// design's largest field where the file names one, else the half
    /// diagonal of a 36 x 24 mm frame at the focal length, at most 60, and
    /// 2% inside the field where the chief ray stops reaching the image).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    max_field_deg: Option<f64>,
    #[command(flatten)]
    aim: AimArgs,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_plot(a.plot.plot.as_deref())?;
    let p = a.lens.load()?;
    a.lens.catalogs.report(&p, p.wavelengths_nm())?;
    let max_field = match a.max_field_deg {
        Some(m) => m,
        None => default_max_field_deg(&p, a.aim.aim())?,
    };
    if !(max_field.is_finite() && max_field > 0.0 && max_field < 90.0) {
        return Err(
            format!("--max-field-deg {max_field}: give a largest field angle above 0 and below 90 degrees").into()
        );
    }
    a.field.y_only("lens chromatic (lateral colour against field)")?;
    let c = chromatic(&p, a.field.field_deg, max_field, a.aim.aim())?;
    if let Some(out) = &a.plot.plot {
        plot::save(&plot::chromatic::chromatic_chart(&c, &a.lens.name(&p)), out)?;
    }
    if a.out.json {
        print_json(&serde_json::to_value(&c)?)?;
        return Ok(ExitCode::SUCCESS);
    }
    let w = &c.wavelengths_nm;
    outln!("{}: colour at wavelengths {:?} nm (primary {} nm)", a.lens.name(&p), w, c.primary_wavelength_nm);
    if !p.is_dispersive() {
        outln!("  every index is constant: no colour (give surfaces a \"glass\" to see it)");
    }
    outln!(
        "  axial colour         {:+.6} mm  (image distance at {} nm minus at {} nm)",
        Fixed(c.axial_colour),
        w[0],
        w[w.len() - 1]
    );
    outln!("  secondary spectrum   {:+.6} mm  (primary focus minus the mean of the two)", Fixed(c.secondary_spectrum));
    outln!(
        "  focal shift range    {:.6} mm over {} points of 400-700 nm",
        Fixed(c.focal_shift_range),
        c.focal_shift.len()
    );
    outln!("  lateral colour       {:+.6} mm at {:.3} deg", Fixed(c.lateral_colour), Fixed(max_field));
    outln!(
        "  polychromatic spot   RMS {:.6} mm at {} deg ({})",
        Fixed(c.spot.rms_radius),
        a.field.field_deg,
        c.spot
            .wavelengths
            .iter()
            .map(|s| format!("{} nm: {:.6}", s.wavelength_nm, s.rms_radius))
            .collect::<Vec<_>>()
            .join(", ")
    );
    if !c.glasses.is_empty() {
        outln!("  {:<28} {:>10} {:>9} {:>8}  surfaces", "glass", "nd", "vd", "PgF");
        for g in &c.glasses {
            let pgf = g.partial_dispersion_gf.map_or("-".to_string(), |v| format!("{v:.4}"));
            let s: Vec<String> = g.surfaces.iter().map(|s| s.to_string()).collect();
            outln!("  {:<28} {:>10.6} {:>9.4} {:>8}  {}", g.glass, Fixed(g.nd), Fixed(g.vd), pgf, s.join(" "));
        }
    }
    Ok(ExitCode::SUCCESS)
}
