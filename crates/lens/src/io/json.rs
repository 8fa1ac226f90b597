//! The JSON prescription format (docs/prescription-format.md): text to
//! [`PrescriptionSpec`] with serde's line and column on every error, and
//! back.

use crate::error::LoadError;
use crate::model::{Prescription, PrescriptionSpec};

/// Parses one JSON object of type `T` from `text`, as files are written:
/// a leading UTF-8 byte-order mark is skipped, and a file that is not an
/// object (`[...]`, a number) is refused saying what it should hold
/// (`what`). The error's line and column are 1-based and its message does
/// not repeat them.
pub fn parse_object<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> Result<T, (usize, usize, String)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let start = text.trim_start();
    if start.is_empty() {
        let line = 1 + text.matches('\n').count();
        return Err((line, 1, format!("the file is empty: it must hold one JSON object {{...}}: {what}")));
    }
    if !start.is_empty() && !start.starts_with('{') {
        let skipped = &text[..text.len() - start.len()];
        let line = 1 + skipped.matches('\n').count();
        let column = 1 + skipped.rsplit('\n').next().map_or(0, |l| l.chars().count());
        return Err((line, column, format!("the file must hold one JSON object {{...}}: {what}")));
    }
    serde_json::from_str(text).map_err(|e| (e.line(), e.column(), message(&e)))
}

/// serde's message without the " at line L column C" it appends, said in
/// the project's words where serde's own are cryptic (the library's text
/// kept as the detail).
pub fn message(e: &serde_json::Error) -> String {
    let m = e.to_string();
    let tail = format!(" at line {} column {}", e.line(), e.column());
    let m = m.strip_suffix(&tail).map(str::to_string).unwrap_or(m);
    if m.contains("surrogate") || m.contains("escape") {
        format!(
            "a backslash escape here is not a whole character: half of a UTF-16 surrogate pair, cut short, or \
             not one JSON knows ({m}); write the character itself, both halves of a pair (\\ud83d\\ude00), \
             or \\\\ for a backslash"
        )
    } else if e.is_eof() {
        format!("the file ends in the middle of its JSON ({m}): is it cut short? close every {{, [ and \"")
    } else {
        m
    }
}

impl PrescriptionSpec {
    /// Parses JSON text. `origin` names the source in errors (a file name).
    /// Errors carry serde's 1-based line and column.
    pub fn from_json_str(text: &str, origin: &str) -> Result<Self, LoadError> {
        parse_object(text, "a prescription (docs/prescription-format.md)")
            .map_err(|(line, column, message)| LoadError::Json { origin: origin.to_string(), line, column, message })
    }

    /// The JSON text of this prescription (pretty-printed).
    pub fn to_json_string(&self) -> String {
        // Serialising plain structs of f64/String/bool cannot fail except on
        // non-finite floats, which serde_json writes as null.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

impl Prescription {
    /// Parses and validates JSON text; `origin` names it in errors.
    pub fn from_json_str(text: &str, origin: &str) -> Result<Self, LoadError> {
        let spec = PrescriptionSpec::from_json_str(text, origin)?;
        Self::from_spec(&spec).map_err(|findings| LoadError::Invalid { origin: origin.to_string(), findings })
    }
}
