//! The optical model as data: the prescription file as written
//! ([`spec`]), its validation with every finding ([`validate`],
//! [`finding`]), and the validated prescription ([`Prescription`]) of
//! [`Surface`]s that every computation reads. Nothing here traces rays or
//! computes first-order optics; see docs/architecture.md for the layout.

pub mod finding;
mod motion_check;
pub mod placement;
pub mod prescription;
pub mod spec;
pub mod surface;
pub mod validate;

pub use finding::{has_errors, Finding, Severity};
pub use placement::Placement;
pub use prescription::Prescription;
pub use spec::{CoatingSpec, ElementSpec, GlassSpec, LayerSpec, PrescriptionSpec, SurfaceSpec, VignettingFactors};
pub use surface::Surface;
