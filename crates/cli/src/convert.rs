//! `lens convert`: write any readable prescription as JSON, a Zemax `.zmx`
//! file, a CODE V `.seq` file or a pbrt-v4 realistic-camera lens file
//! (`.dat`).

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
    /// Output file: `.json` (our format), `.zmx` (Zemax, UTF-16 LE as
    /// OpticStudio writes it), `.seq` (CODE V) or `.dat` (pbrt-v4's
    /// realistic camera); JSON on standard output when omitted.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// For `.dat`: the wavelength (nm) whose indices are written (pbrt-v4's
    /// lens file has no dispersion; a lens with glasses needs it).
    #[arg(long, value_name = "NM")]
    wavelength_nm: Option<f64>,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(a.output.as_deref(), "-o", &["json", "zmx", "seq", "dat"])?;
    let to_dat = a.output.as_deref().is_some_and(lens::io::is_dat);
    if a.wavelength_nm.is_some() && !to_dat {
        return Err("--wavelength-nm: only a pbrt-v4 .dat output holds one wavelength's indices; leave it out".into());
    }
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
            } else if lens::io::is_codev(&path) {
                lens::io::codev::write(&p)?.into_bytes()
            } else if to_dat {
                lens::io::dat::write_dat(&p, a.wavelength_nm)?.into_bytes()
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
