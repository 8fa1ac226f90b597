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
    let p = a.lens.load()?;
    let text = p.to_spec().to_json_string() + "\n";
    match a.output {
        Some(path) => std::fs::write(&path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
        None => out!("{text}"),
    }
    Ok(ExitCode::SUCCESS)
}
