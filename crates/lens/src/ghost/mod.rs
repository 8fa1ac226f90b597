//! Ghosts: light reflected at two surfaces of a lens (first at a later
//! surface j, then at an earlier one i < j) and sent on to the film, where
//! it makes a dim, usually defocused copy of a bright source. A lens of n
//! reflecting surfaces has n (n - 1) / 2 of them.
//!
//! - [`paraxial`]: the engineer's ghost list (`lens ghosts`): each ghost's
//!   paraxial focus, its height and blur on the image plane, and its
//!   irradiance relative to the primary image's;
//! - [`image`]: a ghost's (or the primary's) irradiance on a film grid for
//!   a point source, from a grid of rays traced through the ghost's path
//!   ([`crate::Tracer::ghost`], Fresnel-weighted, every clear aperture
//!   clipping) and rasterised triangle by triangle (each pixel's share of
//!   a triangle from `coverage`);
//! - [`reference`]: the brute-force check: rays that reflect or refract at
//!   every surface they meet, at random by their Fresnel probability.
//!
//! Surfaces are numbered from 0 in the code and from 1 in what users read
//! (the JSON's `"surfaces": [i, j]`).

mod coverage;
pub mod image;
pub mod paraxial;
pub mod reference;

use crate::model::Prescription;

pub use image::{rasterise, rasterise_with, FilmGrid, GhostImage, Source, EDGE_STEPS};
pub use paraxial::{ghost_list, GhostFocus};

/// The ghosts of a lens: every pair `[i, j]` (0-based, i < j) of surfaces
/// that reflect (their two sides differ in index, neither is an ideal
/// paraxial surface), in the order (j, i) ascending.
pub fn ghost_pairs(p: &Prescription) -> Vec<[usize; 2]> {
    let s = p.surfaces();
    let reflects: Vec<bool> = (0..s.len()).map(|i| s[i].paraxial.is_none() && p.index_before(i) != s[i].ior).collect();
    let mut out = Vec::new();
    for j in 0..s.len() {
        for i in 0..j {
            if reflects[i] && reflects[j] {
                out.push([i, j]);
            }
        }
    }
    out
}
