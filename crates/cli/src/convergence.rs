//! `lens convergence`: error against run time of the pupil-sampled
//! statistics, as a markdown report.

use crate::args::LensArgs;
use crate::CmdResult;
use lens::analysis::convergence::{coc_rms, spot_rms, wave_statistics, Convergence};
use lens::analysis::Field;
use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Field angle of the spot statistic, degrees.
    #[arg(long, default_value_t = 10.0)]
    field_deg: f64,
    /// Focus distance S1 of the circle-of-confusion statistic, mm.
    #[arg(long, default_value_t = 2000.0)]
    focus_mm: f64,
    /// Object distance S2 of the circle-of-confusion statistic, mm.
    #[arg(long, default_value_t = 1000.0)]
    object_mm: f64,
    /// Field angle of the wave statistics (RMS wavefront error, Strehl,
    /// Zernike defocus), degrees.
    #[arg(long, default_value_t = 0.0)]
    wave_field_deg: f64,
    /// Write the report here (markdown) instead of standard output.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

fn table(out: &mut String, c: &Convergence) {
    let _ = writeln!(out, "### {}\n", c.statistic);
    let unit = if c.unit.is_empty() { String::new() } else { format!(" {}", c.unit) };
    let paren = if c.unit.is_empty() { String::new() } else { format!(" ({})", c.unit) };
    let _ = writeln!(out, "Reference: {:.9e}{unit} ({}).\n", c.reference, c.reference_method);
    let _ = writeln!(out, "| method | rays | time (ms) | estimate{paren} | error{paren} | relative error |");
    let _ = writeln!(out, "|---|---:|---:|---:|---:|---:|");
    for r in &c.rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.3} | {:.9e} | {:.2e} | {:.2e} |",
            r.method,
            r.rays,
            r.seconds * 1e3,
            r.estimate,
            r.error,
            r.error / c.reference.abs().max(f64::MIN_POSITIVE)
        );
    }
    out.push('\n');
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(a.output.as_deref(), "-o", &["md"])?;
    let p = a.lens.load()?;
    let spot = spot_rms(&p, Field::Angle(a.field_deg))?;
    let coc = coc_rms(&p, a.focus_mm, a.object_mm)?;
    let mut out = String::new();
    let _ = writeln!(out, "## {}\n", a.lens.name(&p));
    table(&mut out, &spot);
    table(&mut out, &coc);
    for c in wave_statistics(&p, Field::Angle(a.wave_field_deg))? {
        table(&mut out, &c);
    }
    match a.output {
        Some(path) => lens::io::files::write_bytes_atomic(&path, out.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
        None => out!("{out}"),
    }
    Ok(ExitCode::SUCCESS)
}
