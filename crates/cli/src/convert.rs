//! `lens convert`: write any readable prescription as JSON.

use crate::CmdResult;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription file (.json or pbrt .dat).
    file: PathBuf,
    /// Output JSON file (standard output when omitted).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(a: Args) -> CmdResult {
    let p = lens::Prescription::load(&a.file)?;
    let text = p.to_spec().to_json_string() + "\n";
    match a.output {
        Some(path) => std::fs::write(&path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
        None => print!("{text}"),
    }
    Ok(ExitCode::SUCCESS)
}
