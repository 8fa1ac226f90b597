//! `lens coc`: real circles of confusion beside the thin-lens formula.

use crate::args::{parse_list, JsonArgs, LensArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::coc::circle_of_confusion;
use lens::error::num;
use lens::error::Fixed;
use std::process::ExitCode;

/// Distances drawn for the plot's curves, evenly spaced in 1/distance.
const CURVE_POINTS: usize = 96;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    /// Focus distance S1, mm in front of the first vertex (`inf` allowed).
    #[arg(long, value_name = "S1")]
    focus_mm: f64,
    /// Object distances S2, mm, comma-separated (`inf` allowed).
    #[arg(long, value_name = "S2,S2,...", value_parser = parse_list)]
    distances: std::vec::Vec<f64>,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_plot(a.plot.plot.as_deref())?;
    let (_, p) = a.lens.load_at(a.wavelength.wavelength_nm)?;
    if a.distances.is_empty() {
        return Err("--distances: give at least one object distance in mm (`inf` for infinity)".into());
    }
    let t = circle_of_confusion(&p, a.focus_mm, &a.distances)?;
    if let Some(out) = &a.plot.plot {
        // from infinity to the nearest of the asked distances and the focus
        let nearest = a.distances.iter().chain([a.focus_mm].iter()).copied().fold(f64::INFINITY, f64::min);
        let v_max = 1.0 / (0.8 * nearest);
        let curve: Vec<f64> = (0..=CURVE_POINTS)
            .map(|k| v_max * k as f64 / CURVE_POINTS as f64)
            .map(|v| if v == 0.0 { f64::INFINITY } else { 1.0 / v })
            .collect();
        // distances nearer than the lens can image are left out of the curve
        let dense = circle_of_confusion(&p, a.focus_mm, &curve).or_else(|_| {
            let ok: Vec<f64> =
                curve.iter().copied().filter(|&d| circle_of_confusion(&p, a.focus_mm, &[d]).is_ok()).collect();
            circle_of_confusion(&p, a.focus_mm, &ok)
        })?;
        plot::save(&plot::coc::coc_chart(&dense, &t, p.name()), out)?;
    }
    if a.out.json {
        print_json(&serde_json::to_value(&t)?)?;
        return Ok(ExitCode::SUCCESS);
    }
    let focus = t.focus_distance.map_or("infinity".to_string(), |d| format!("{} mm", num(d)));
    outln!(
        "focused at {focus} (film {:.6} mm behind the last vertex); EFL {:.4} mm, entrance pupil {:.4} mm at z {:.4} mm",
        Fixed(t.film_distance), Fixed(t.efl), Fixed(t.entrance_pupil_diameter), Fixed(t.entrance_pupil_z));
    outln!(
        "{:>14} {:>14} {:>14} {:>14} {:>9}",
        "distance (mm)",
        "geo diam (mm)",
        "rms diam (mm)",
        "thin lens (mm)",
        "real/thin"
    );
    for r in &t.rows {
        let d = r.distance.map_or("infinity".to_string(), num);
        let ratio = if r.thin_lens_diameter > 0.0 { r.geo_diameter / r.thin_lens_diameter } else { f64::NAN };
        let ratio = if ratio.is_finite() { format!("{ratio:.4}") } else { "-".into() };
        outln!(
            "{d:>14} {:>14.6} {:>14.6} {:>14.6} {ratio:>9}",
            Fixed(r.geo_diameter),
            Fixed(r.rms_diameter),
            Fixed(r.thin_lens_diameter)
        );
    }
    Ok(ExitCode::SUCCESS)
}
