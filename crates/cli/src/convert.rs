//! `lens convert`: write any readable prescription as JSON or as a Zemax
//! `.zmx` file.

use crate::args::LensArgs;
use crate::CmdResult;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Set every clear aperture but the stop's to pass the full stop on the
    /// axis and at these field angles (degrees, comma-separated), as
    /// Zemax's automatic semi-diameters: for designs whose source gives no
    /// clear apertures. With `--f-number`, the stop is sized first.
    #[arg(long, value_name = "DEG,DEG", value_delimiter = ',', allow_hyphen_values = true)]
    clear_apertures: Option<Vec<f64>>,
    /// Output file: `.json` (our format) or `.zmx` (Zemax, UTF-16 LE as
    /// OpticStudio writes it); JSON on standard output when omitted.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(a.output.as_deref(), "-o", &["json", "zmx"])?;
    let p = match &a.clear_apertures {
        None => a.lens.load()?,
        Some(fields) => {
            if let Some(bad) = fields.iter().find(|f| !(f.is_finite() && f.abs() < 90.0)) {
                return Err(format!("--clear-apertures {bad}: give field angles in degrees, |angle| < 90").into());
            }
            let raw = a.lens.load_as_written()?;
            let n = raw.surfaces().len();
            let mut p = raw.with_clear_apertures(&vec![None; n])?;
            if let Some(f) = a.lens.f_number {
                p = lens::analysis::aperture::with_f_number(&p, f)?;
            }
            lens::analysis::aperture::automatic_semi_diameters(&p, fields)?
        }
    };
    match a.output {
        Some(path) => {
            let bytes = if lens::io::is_zemax(&path) {
                lens::io::zemax::text::encode_utf16le(&lens::io::zemax::write(&p)?)
            } else {
                (p.to_spec().to_json_string() + "\n").into_bytes()
            };
            lens::io::files::write_bytes_atomic(&path, &bytes)
                .map_err(|e| format!("{}: cannot write: {e}", path.display()))?
        }
        None => out!("{}", p.to_spec().to_json_string() + "\n"),
    }
    Ok(ExitCode::SUCCESS)
}
