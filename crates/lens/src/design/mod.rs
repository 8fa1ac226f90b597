//! Lens design: a merit function over chosen variables of a prescription
//! and its optimisation by damped least squares (docs/design.md).
//!
//! - [`spec`]: the design file as written ([`DesignSpec`]);
//! - [`variables`]: what may change (radius as curvature, thickness,
//!   conic, aspheric terms, model-glass nd and vd), with bounds;
//! - [`operands`]: what is measured, each through the analysis a command
//!   prints, with its target and weight;
//! - [`merit`]: the merit function of a candidate ([`Design`]);
//! - [`least_squares`]: bounded Levenberg–Marquardt, Jacobian columns in
//!   parallel;
//! - [`optimize`]: the loop, the report of it, and glass substitution
//!   ([`glass_substitution`]).
//!
//! The merit function is Zemax's: sqrt(sum w_i m_i^2 / sum w_i), m_i an
//! operand's miss of its target (0 while an inequality holds).

pub mod glass_substitution;
pub mod least_squares;
pub mod merit;
pub mod operands;
pub mod optimize;
pub mod spec;
pub mod variables;

pub use merit::{Design, Evaluation};
pub use operands::{Measure, Operand};
pub use optimize::{optimize, Optimized};
pub use spec::DesignSpec;
pub use variables::Variable;

use crate::error::LoadError;
use crate::model::Finding;

/// Why a design could not be set up or evaluated. Each message names the
/// variable, operand or surface and what to change.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    /// The design file or its prescription could not be read.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// A variable that does not exist or cannot be varied.
    #[error("{what}: {why}")]
    Variable {
        /// Which variable, in words.
        what: String,
        /// What is wrong and what to change.
        why: String,
    },
    /// An operand that cannot be measured or met.
    #[error("{what}: {why}")]
    Operand {
        /// Which operand, in words.
        what: String,
        /// What is wrong and what to change.
        why: String,
    },
    /// Something else in the design file.
    #[error("design file: {0}")]
    Spec(String),
    /// Something in a tolerance file.
    #[error("tolerance file: {0}")]
    Tolerance(String),
    /// The lens at the given variables is not a valid prescription.
    #[error("{what}: the lens is not valid:\n{}", findings.iter().map(|f| format!("  {f}")).collect::<Vec<_>>().join("\n"))]
    Invalid {
        /// Which lens, in words (the start, say).
        what: String,
        /// Every finding.
        findings: Vec<Finding>,
    },
    /// An operand could not be measured on the lens.
    #[error("{what}: {why}")]
    Measure {
        /// Which operand of which lens, in words.
        what: String,
        /// Why, and what to change.
        why: String,
    },
    /// No variable changes any operand.
    #[error("the merit function does not depend on any variable: {0}")]
    NoDependence(String),
}

/// Reads a JSON file of the design formats (a design or tolerance file) as
/// `T`, the error naming the file, line and column.
pub fn read_json<T: serde::de::DeserializeOwned>(path: &std::path::Path) -> Result<T, DesignError> {
    let origin = path.display().to_string();
    let bytes = crate::io::files::read_bounded(path, crate::io::files::MAX_TEXT_BYTES).map_err(|e| {
        DesignError::Load(LoadError::Io { path: path.to_path_buf(), source: std::io::Error::other(e.reason()) })
    })?;
    let text = String::from_utf8(bytes).map_err(|_| {
        DesignError::Load(LoadError::Json {
            origin: origin.clone(),
            line: 1,
            column: 1,
            message: "the file is not UTF-8 text".into(),
        })
    })?;
    serde_json::from_str(&text).map_err(|e| {
        DesignError::Load(LoadError::Json {
            origin,
            line: e.line(),
            column: e.column(),
            message: crate::io::json::message(&e),
        })
    })
}
