//! The JSON prescription format (docs/prescription-format.md): text to
//! [`PrescriptionSpec`] with serde's line and column on every error, and
//! back.

use crate::error::LoadError;
use crate::model::{Prescription, PrescriptionSpec};

impl PrescriptionSpec {
    /// Parses JSON text. `origin` names the source in errors (a file name).
    /// Errors carry serde's 1-based line and column.
    pub fn from_json_str(text: &str, origin: &str) -> Result<Self, LoadError> {
        serde_json::from_str(text).map_err(|e| LoadError::Json {
            origin: origin.to_string(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })
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
