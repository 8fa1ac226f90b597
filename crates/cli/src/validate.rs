//! `lens validate`: every finding in every file; exit 1 on any error.

use crate::CmdResult;
use lens::model::{has_errors, validate::validate};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Prescription files (.json, pbrt .dat or Zemax .zmx).
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print one JSON object per file: {"file", "valid", "findings": [...]}.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> CmdResult {
    let mut failed = false;
    for path in &a.files {
        let (valid, findings, load_error) = match lens::load_spec(path) {
            Ok(spec) => {
                let f = validate(&spec);
                (!has_errors(&f), f, None)
            }
            Err(e) => (false, Vec::new(), Some(e.to_string())),
        };
        failed |= !valid;
        if a.json {
            let v = lens::report::validation(&path.display().to_string(), valid, load_error, &findings);
            outln!("{v}");
            continue;
        }
        if let Some(e) = load_error {
            outln!("{}: error: {e}", path.display());
            continue;
        }
        let errors = findings.iter().filter(|f| f.severity == lens::model::Severity::Error).count();
        outln!(
            "{}: {} ({} error{}, {} warning{})",
            path.display(),
            if valid { "valid" } else { "INVALID" },
            errors,
            if errors == 1 { "" } else { "s" },
            findings.len() - errors,
            if findings.len() - errors == 1 { "" } else { "s" },
        );
        for f in &findings {
            outln!("  {f}");
        }
    }
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}
