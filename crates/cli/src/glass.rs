//! `lens glass`: a glass's index at a wavelength, its nd, vd and range, a
//! plot of its dispersion; or the glass map of the loaded catalogues.

use crate::args::{GlassArgs, JsonArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::glass::LINE_D_NM;
use serde_json::json;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Glass names, `VENDOR:NAME` (vendor in any case) or `NAME` where one
    /// catalogue has it.
    #[arg(required_unless_present = "map")]
    names: Vec<String>,
    /// Draw the glass map (nd against vd) of the loaded catalogues with
    /// --plot.
    #[arg(long)]
    map: bool,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    #[command(flatten)]
    catalogs: GlassArgs,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(a: Args) -> CmdResult {
    if let Some(path) = &a.plot.plot {
        let out = crate::outputs::Output { path, flag: "--plot", extensions: &["svg", "png"] };
        crate::outputs::check(&[out], &a.catalogs.glass_catalogs)?;
    }
    let cats = a.catalogs.load()?;
    if a.map {
        let Some(out) = &a.plot.plot else {
            return Err("--map draws a picture: give --plot OUT.svg or OUT.png".into());
        };
        plot::save(&plot::glass::glass_map(&cats), out)?;
        if a.names.is_empty() {
            return Ok(ExitCode::SUCCESS);
        }
    }
    let mut glasses = Vec::with_capacity(a.names.len());
    for n in &a.names {
        let (g, note) = cats.resolve(n)?;
        if let Some(note) = note {
            crate::warnings::warn("glass_name", note);
        }
        glasses.push(g);
    }
    let nm = a.wavelength.wavelength_nm.unwrap_or(LINE_D_NM);
    if let (Some(out), false) = (&a.plot.plot, a.map) {
        plot::save(&plot::glass::dispersion_chart(&glasses), out)?;
    }
    for g in glasses {
        let n = g.index_with(nm, a.catalogs.range())?;
        if let Some(w) = g.range_warning(nm) {
            crate::warnings::glass_range(&w);
        }
        let (nd, vd) = (g.nd()?, g.vd()?);
        if a.out.json {
            print_json(&json!({
                "catalog": g.catalog,
                "name": g.name,
                "formula": g.dispersion.name(),
                "nd": nd,
                "vd": vd,
                "range_nm": g.range_nm,
                "wavelength_nm": nm,
                "n": n,
                "partial_dispersion_gf": g.partial_dispersion_gf().ok(),
            }))?;
            continue;
        }
        outln!(
            "{} ({}, formula {})",
            g.full_name(),
            g.range_nm.map(|v| format!("{v} nm")).join(" to "),
            g.dispersion.name()
        );
        let row = format!("n at {nm} nm");
        outln!("  {row:<22} {n:.6}");
        outln!("  {:<22} {nd:.6}", "nd");
        outln!("  {:<22} {vd:.3}", "vd");
        if let Ok(p) = g.partial_dispersion_gf() {
            outln!("  {:<22} {p:.4}", "PgF (g to F)");
        }
    }
    Ok(ExitCode::SUCCESS)
}
