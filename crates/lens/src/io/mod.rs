//! Prescription files in and out: JSON (our format), pbrt-v4 `.dat`,
//! Zemax `.zmx` and CODE V `.seq`, chosen by the file's extension. Nothing here computes optics; the model
//! is in [`crate::model`].

pub mod codev;
pub mod dat;
pub mod files;
pub mod json;
pub mod zemax;

use crate::error::LoadError;
use crate::glass::{Catalog, Catalogs};
use crate::model::{Prescription, PrescriptionSpec};
use std::path::Path;

/// Reads a prescription file as written, without validating it: pbrt-v4
/// `.dat` when the extension is `dat`, Zemax when it is `zmx`, CODE V when
/// it is `seq` (glasses looked up in the shipped catalogues), JSON
/// otherwise.
pub fn load_spec(path: &Path) -> Result<PrescriptionSpec, LoadError> {
    load_spec_with(path, Catalogs::shipped())
}

/// A prescription file as written and the catalogues its glasses are
/// looked up in: `extra` (a user's, from the command line) first, then a
/// JSON file's `glass_catalogs` (relative to it), then the shipped ones; a
/// Zemax file's `GCAT` vendors are searched first among those.
pub fn load_spec_and_catalogs(path: &Path, extra: Vec<Catalog>) -> Result<(PrescriptionSpec, Catalogs), LoadError> {
    let origin = path.display().to_string();
    if is_zemax(path) || is_codev(path) {
        let catalogs = Catalogs::with(extra);
        let spec = load_spec_with(path, &catalogs)?;
        return Ok((spec, catalogs));
    }
    let spec = load_spec(path)?;
    let mut catalogs = extra;
    let dir = path.parent().unwrap_or(Path::new("."));
    for name in spec.glass_catalogs.iter().flatten() {
        let c = crate::glass::agf::load(&dir.join(name))
            .map_err(|e| LoadError::Glass { origin: origin.clone(), source: e })?;
        catalogs.push(c);
    }
    Ok((spec, Catalogs::with(catalogs)))
}

/// Whether `path` names a Zemax lens file (extension `zmx`).
pub fn is_zemax(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("zmx"))
}

/// Whether `path` names a pbrt-v4 realistic-camera lens file (extension
/// `dat`).
pub fn is_dat(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("dat"))
}

/// Whether `path` names a CODE V sequence file (extension `seq`).
pub fn is_codev(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("seq"))
}

/// [`load_spec`] with a Zemax or CODE V file's glasses looked up in
/// `catalogs` (a Zemax file's `GCAT` vendors first); JSON and `.dat` do not
/// use them.
pub fn load_spec_with(path: &Path, catalogs: &Catalogs) -> Result<PrescriptionSpec, LoadError> {
    let bytes = files::read_bounded(path, files::MAX_TEXT_BYTES).map_err(|e| match e {
        files::ReadError::Io { path, source } => LoadError::Io { path, source },
        e @ files::ReadError::TooLarge { .. } => {
            LoadError::Io { path: path.to_path_buf(), source: std::io::Error::other(e.reason()) }
        }
    })?;
    let origin = path.display().to_string();
    if is_zemax(path) {
        let (text, _) = zemax::text::decode(&bytes).map_err(|message| LoadError::Zemax {
            origin: origin.clone(),
            line: 0,
            message,
        })?;
        let mut spec =
            zemax::read(&text, catalogs).map_err(|e| LoadError::Zemax { origin, line: e.line, message: e.message })?;
        let file = path.file_name().map_or_else(|| path.display().to_string(), |f| f.to_string_lossy().into_owned());
        spec.source = Some(match spec.source.take() {
            Some(notes) => format!("imported from the Zemax file {file}; {notes}"),
            None => format!("imported from the Zemax file {file}"),
        });
        return Ok(spec);
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = 1 + good.iter().filter(|b| **b == b'\n').count();
        let column = 1 + good.iter().rev().take_while(|b| **b != b'\n').count();
        LoadError::Json { origin: origin.clone(), line, column, message: "the file is not UTF-8 text".into() }
    })?;
    if is_codev(path) {
        let mut spec =
            codev::read(&text, catalogs).map_err(|e| LoadError::CodeV { origin, line: e.line, message: e.message })?;
        let file = path.file_name().map_or_else(|| path.display().to_string(), |f| f.to_string_lossy().into_owned());
        spec.source = Some(format!("imported from the CODE V file {file}"));
        return Ok(spec);
    }
    if is_dat(path) {
        dat::parse_dat(&text, &origin)
    } else {
        PrescriptionSpec::from_json_str(&text, &origin)
    }
}

impl Prescription {
    /// Loads a prescription file: pbrt-v4 `.dat` by its extension, JSON
    /// otherwise. Errors name the file, and for JSON the line and column.
    /// Glasses are looked up in the AGF catalogues the file names
    /// (`glass_catalogs`, relative to it), then in the shipped ones.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        Self::load_with(path, Vec::new())
    }

    /// [`Self::load`] with `extra` catalogues searched first (a user's, from
    /// the command line).
    pub fn load_with(path: impl AsRef<Path>, extra: Vec<Catalog>) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let (spec, catalogs) = load_spec_and_catalogs(path, extra)?;
        Self::from_spec_with(&spec, &catalogs).map_err(|findings| LoadError::Invalid { origin, findings })
    }
}
