//! # lens — real camera lenses as data, traced exactly
//!
//! The crate is laid out by concept (docs/architecture.md):
//!
//! - [`model`]: the prescription as written ([`PrescriptionSpec`]), its
//!   validation with every finding, and the validated [`Prescription`];
//! - [`io`]: files in and out (JSON, pbrt-v4 `.dat`);
//! - [`trace`]: exact real-ray tracing, one ray ([`Tracer::trace`]) or a
//!   batch ([`Tracer::trace_soa`], [`Tracer::trace_batch`]), each ray ending
//!   in a classified [`Outcome`]; the surface step is written once;
//! - [`ghost`]: ghost reflections between surfaces: the paraxial ghost
//!   list, ghost images rasterised from ray grids, and their brute-force
//!   reference;
//! - [`glass`]: glass catalogues and dispersion formulas (shipped and
//!   Zemax AGF), indices at any wavelength;
//! - [`paraxial`]: first-order optics (focal lengths, cardinal points,
//!   pupils, f-numbers, conjugates, focus);
//! - [`analysis`]: what an optical engineer asks of a lens (fans, spots,
//!   circles of confusion, field curves, best focus), all on one ray-bundle
//!   primitive traced by the batch tracer;
//! - [`design`]: merit functions over a prescription's variables and their
//!   optimisation by damped least squares;
//! - [`tolerance`]: sensitivity and Monte Carlo tolerancing with
//!   compensators, reproducible trial by trial.
//!
//! Conventions (docs/architecture.md): +z is the optical axis, light travels
//! toward +z, lengths are millimetres, positions are z from the first
//! vertex, a radius is positive when its centre lies toward the image. f64
//! throughout. The library never panics on user input and never returns
//! NaN: degenerate cases are error values.
//!
//! ```
//! use lens::{Prescription, paraxial::FirstOrder};
//! let p = Prescription::from_json_str(r#"{"surfaces": [
//!   {"radius": 51.5, "thickness": 3.6, "ior": 1.5168, "semi_diameter": 12.7, "stop": true},
//!   {"thickness": 97.2, "semi_diameter": 12.7}]}"#, "<doc>").unwrap();
//! let f = FirstOrder::of(&p).unwrap();
//! assert!((f.efl - 51.5 / 0.5168).abs() < 1e-9); // plano-convex: f = R / (n - 1)
//! ```

pub mod analysis;
pub mod coating;
pub mod design;
pub mod error;
pub mod ghost;
pub mod glass;
pub mod io;
pub mod model;
pub mod paraxial;
pub mod report;
mod simd;
pub mod tolerance;
pub mod trace;

pub use error::{LoadError, OpticsError};
pub use glam::DVec3;
pub use io::load_spec;
pub use model::{Prescription, PrescriptionSpec, Surface, SurfaceSpec};
pub use trace::{Outcome, Ray, RayBatch, Tracer};
