//! A finding of validation: what is wrong with a prescription, where, and
//! what to change. A leaf: it imports nothing of the crate.

use std::fmt;

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// The prescription can be used, but something is unusual.
    Warning,
    /// The prescription cannot be used until this is changed.
    Error,
}

/// One problem found in a prescription.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Finding {
    /// Error or warning.
    pub severity: Severity,
    /// Surface number, 1-based as optical designers count; `None` for the
    /// prescription as a whole.
    pub surface: Option<usize>,
    /// The field concerned (`"radius"`, `"thickness"`, ...), if one.
    pub field: Option<&'static str>,
    /// What is wrong and what to change.
    pub message: String,
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let level = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        match self.surface {
            Some(s) => write!(f, "{level}: surface {s}: {}", self.message),
            None => write!(f, "{level}: {}", self.message),
        }
    }
}

/// Whether any finding is an error.
pub fn has_errors(findings: &[Finding]) -> bool {
    findings.iter().any(|f| f.severity == Severity::Error)
}
