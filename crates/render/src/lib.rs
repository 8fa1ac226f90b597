//! # render — scenes seen through pinholes, thin lenses and real lenses
//!
//! A scene file (JSON, metres; see docs/scene-format.md) is built into a
//! [`scene::Scene`] whose camera is a pinhole, a Cook-style thin lens, or a
//! real lens prescription traced surface by surface by the `lens` crate
//! (film to scene). A path tracer with direct light sampling and Russian
//! roulette renders it on all cores, deterministically for a seed.
//!
//! `render` knows nothing of prescription file formats: the `lens` crate
//! loads them. Scenes are in metres; the real-lens camera converts to
//! millimetres at its boundary.

pub mod animation;
pub mod bvh;
pub mod camera;
mod companions;
pub mod envmap;
pub mod geometry;
pub mod image;
pub mod integrator;
pub mod light;
pub mod material;
pub mod mesh;
pub mod passes;
pub mod renderer;
pub mod report;
pub mod rng;
pub mod scene;
pub mod spectrum;
mod splat;
pub mod study;
pub mod transport;

pub use image::Image;
pub use renderer::{render, render_with, Companions, Options, Stats};
pub use scene::Scene;
