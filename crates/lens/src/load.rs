//! Reading prescription files from disk, by format.

use crate::error::LoadError;
use crate::spec::PrescriptionSpec;
use std::path::Path;

/// Reads a prescription file as written, without validating it: pbrt-v4
/// `.dat` when the extension is `dat`, JSON otherwise.
pub fn load_spec(path: &Path) -> Result<PrescriptionSpec, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io { path: path.to_path_buf(), source })?;
    let origin = path.display().to_string();
    let text = String::from_utf8(bytes).map_err(|e| LoadError::Json {
        origin: origin.clone(),
        line: 1,
        column: e.utf8_error().valid_up_to() + 1,
        message: "the file is not UTF-8 text".into(),
    })?;
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("dat")) {
        crate::dat::parse_dat(&text, &origin)
    } else {
        PrescriptionSpec::from_json_str(&text, &origin)
    }
}
