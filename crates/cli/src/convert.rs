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
    /// Output file: `.json` (our format) or `.zmx` (Zemax, UTF-16 LE as
    /// OpticStudio writes it); JSON on standard output when omitted.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(a.output.as_deref(), "-o", &["json", "zmx"])?;
    let p = a.lens.load()?;
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
