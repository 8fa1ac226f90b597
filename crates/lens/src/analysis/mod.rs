//! Analyses an optical engineer expects: ray fans, spot diagrams, circles of
//! confusion and field curves, all from exact ray traces.
//!
//! Rays enter through [`launch::Launcher`]: a field (an angle for an object at
//! infinity, or an object height at a finite distance) and normalised pupil
//! coordinates (px, py) on the entrance pupil, aimed paraxially or by real
//! rays onto the stop. Vignetted rays are counted and left out of statistics.

pub mod aperture;
pub mod bundle;
pub mod chromatic;
pub mod coc;
pub mod convergence;
pub mod curves;
pub mod fan;
pub mod field;
pub mod focus;
pub mod launch;
pub mod pattern;
pub mod quadrature;
mod refine;
pub mod spot;
pub mod wave;

pub use launch::{Aim, Field, Launcher, AUTO_TOLERANCE};
