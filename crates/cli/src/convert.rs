//! `lens convert`: write any readable prescription as JSON.

use crate::args::LensArgs;
use crate::CmdResult;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Output JSON file (standard output when omitted).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    a.lens.check_output(a.output.as_deref(), "-o", &["json"])?;
    let p = a.lens.load()?;
    let text = p.to_spec().to_json_string() + "\n";
    match a.output {
        Some(path) => lens::io::files::write_bytes_atomic(&path, text.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
        None => out!("{text}"),
    }
    Ok(ExitCode::SUCCESS)
}
