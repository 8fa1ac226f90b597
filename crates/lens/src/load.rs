//! Reading prescription files from disk, by format.

use crate::error::LoadError;
use crate::spec::PrescriptionSpec;
use std::path::Path;

/// Reads a prescription file as written, without validating it: pbrt-v4
/// `.dat` when the extension is `dat`, JSON otherwise.
pub fn load_spec(path: &Path) -> Result<PrescriptionSpec, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io { path: path.to_path_buf(), source })?;
    let origin = path.display().to_string();
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = 1 + good.iter().filter(|b| **b == b'\n').count();
        let column = 1 + good.iter().rev().take_while(|b| **b != b'\n').count();
        LoadError::Json { origin: origin.clone(), line, column, message: "the file is not UTF-8 text".into() }
    })?;
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("dat")) {
        crate::dat::parse_dat(&text, &origin)
    } else {
        PrescriptionSpec::from_json_str(&text, &origin)
    }
}
