//! `lens coc`: real circles of confusion beside the thin-lens formula.

use crate::analysis_args::parse_list;
use crate::{load, print_json, CmdResult};
use lens::analysis::coc::circle_of_confusion;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Focus distance S1, mm in front of the first vertex.
    #[arg(long, value_name = "S1")]
    focus_mm: f64,
    /// Object distances S2, mm, comma-separated (`inf` allowed).
    #[arg(long, value_name = "S2,S2,...", value_parser = parse_list)]
    distances: std::vec::Vec<f64>,
    /// Resize the stop to this f-number first.
    #[arg(long, value_name = "N")]
    f_number: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write a plot (.svg or .png).
    #[arg(long, value_name = "OUT")]
    plot: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let p = load(&a.file, a.f_number)?;
    let t = circle_of_confusion(&p, a.focus_mm, &a.distances)?;
    if let Some(out) = &a.plot {
        plot::save(&plot::coc::coc_chart(&t, p.name()), out)?;
    }
    if a.json {
        print_json(&serde_json::to_value(&t)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "focused at {} mm (film {:.6} mm behind the last vertex); EFL {:.4} mm, entrance pupil {:.4} mm at z {:.4} mm",
        t.focus_distance, t.film_distance, t.efl, t.entrance_pupil_diameter, t.entrance_pupil_z
    );
    println!(
        "{:>14} {:>14} {:>14} {:>14} {:>9}",
        "distance (mm)", "geo diam (mm)", "rms diam (mm)", "thin lens (mm)", "real/thin"
    );
    for r in &t.rows {
        let d = r.distance.map_or("inf".to_string(), |d| format!("{d}"));
        let ratio = if r.thin_lens_diameter > 0.0 { r.geo_diameter / r.thin_lens_diameter } else { f64::NAN };
        let ratio = if ratio.is_finite() { format!("{ratio:.4}") } else { "-".into() };
        println!("{d:>14} {:>14.6} {:>14.6} {:>14.6} {ratio:>9}", r.geo_diameter, r.rms_diameter, r.thin_lens_diameter);
    }
    Ok(ExitCode::SUCCESS)
}
