//! # lens — real camera lenses as data, traced exactly
//!
//! Prescriptions (radius, thickness, index, clear aperture) are read from
//! JSON or pbrt-v4 `.dat` files ([`Prescription::load`]), checked with every
//! finding reported ([`validate::validate`]), and traced:
//!
//! - exactly, ray by ray ([`Tracer::trace`]) or in vectorised batches
//!   ([`Tracer::trace_soa`], [`Tracer::trace_batch`]), each ray ending in a
//!   classified [`Outcome`];
//! - paraxially ([`paraxial`]): focal lengths, cardinal points, pupils,
//!   f-numbers, conjugates, a thick-lens model;
//! - for focus ([`focus`]): the film distance that images an object,
//!   paraxially and by real rays.
//!
//! Conventions (see DESIGN.md): +z is the optical axis, light travels toward
//! +z, lengths are millimetres, positions are z from the first vertex, a
//! radius is positive when its centre lies toward the image. f64 throughout.
//! The library never panics on user input and never returns NaN: degenerate
//! cases are error values.
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
#[cfg(target_arch = "x86_64")]
mod avx2;
pub mod batch;
pub mod bench;
pub mod dat;
pub mod error;
pub mod focus;
pub mod intersect;
mod lanes;
mod load;
pub mod paraxial;
pub mod prescription;
pub mod quadrature;
pub mod ray;
pub mod refract;
pub mod spec;
pub mod surface;
pub mod trace;
pub mod validate;

pub use batch::RayBatch;
pub use error::{LoadError, OpticsError};
pub use glam::DVec3;
pub use load::load_spec;
pub use prescription::Prescription;
pub use ray::{Outcome, Ray};
pub use spec::{PrescriptionSpec, SurfaceSpec};
pub use surface::Surface;
pub use trace::{Direction, Tracer};
