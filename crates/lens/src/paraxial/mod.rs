//! Paraxial (first-order) optics by the y-nu trace: focal lengths, cardinal
//! points, pupils, f-numbers, conjugates, and focus. Reads the model; traces no real rays.
//!
//! At surface i of curvature c between indices n and n':
//! power `phi = c (n' - n)`, refraction `n' u' = n u - y phi`, transfer
//! `y_next = y + t u'`. Angles `u` are slopes dy/dz (paraxial: tan = angle).
//! Object space is air (n = 1). docs/architecture.md has the conventions.

pub mod first_order;
pub mod focus;
pub mod imaging;
pub mod seidel;

pub use first_order::{FirstOrder, Pupil};
pub use focus::{
    film_distance, film_for_focus_from_film, focus_group_shift, focus_group_shift_for_focus, object_distance_in_focus,
};
pub use imaging::{imaging, object_in_focus, Imaging, ThickLens};

use crate::error::OpticsError;
use crate::model::Prescription;

/// Relative threshold below which a quantity that should be non-zero is taken
/// as zero (power of an afocal system, image vergence of an object at the
/// front focal plane): 1e-12 of its natural scale.
pub(crate) const ZERO: f64 = 1e-12;

/// Where the object is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjectDistance {
    /// Object at infinity (collimated light).
    Infinity,
    /// Object on the axis this many mm in front of the first vertex
    /// (at z = -distance); must be positive and finite.
    Finite(f64),
}

impl ObjectDistance {
    /// From a distance in mm: `f64::INFINITY` means infinity.
    pub fn from_mm(d: f64) -> Result<Self, OpticsError> {
        if d == f64::INFINITY {
            Ok(Self::Infinity)
        } else if d.is_finite() && d > 0.0 {
            Ok(Self::Finite(d))
        } else {
            Err(OpticsError::BadInput {
                name: "object_distance",
                value: d,
                expected: "a positive distance in mm in front of the first vertex (or infinity)",
            })
        }
    }
}

/// A paraxial ray traced through every surface.
#[derive(Debug, Clone, PartialEq)]
pub struct ParaxialRay {
    /// Height at each surface's vertex plane, mm.
    pub y: Vec<f64>,
    /// Slope after each surface (dy/dz in the medium behind it).
    pub u: Vec<f64>,
}

impl ParaxialRay {
    /// Height at the last surface, mm.
    pub fn last_y(&self) -> f64 {
        *self.y.last().unwrap_or(&0.0)
    }
    /// Slope in image space.
    pub fn last_u(&self) -> f64 {
        *self.u.last().unwrap_or(&0.0)
    }
}

/// Traces a paraxial ray that has height `y1` mm at the first vertex plane
/// and slope `u0` in object space.
pub fn trace(p: &Prescription, y1: f64, u0: f64) -> ParaxialRay {
    let s = p.surfaces();
    let mut y = Vec::with_capacity(s.len());
    let mut u_out = Vec::with_capacity(s.len());
    let (mut h, mut u) = (y1, u0);
    for (i, surf) in s.iter().enumerate() {
        if i > 0 {
            h += s[i - 1].thickness * u;
        }
        let n = p.index_before(i);
        let n2 = surf.ior;
        // an ideal lens (same medium both sides): u' = u - y / f
        let phi = match surf.paraxial {
            Some(f) => n / f,
            None => surf.vertex_curvature() * (n2 - n),
        };
        u = (n * u - h * phi) / n2;
        y.push(h);
        u_out.push(u);
    }
    ParaxialRay { y, u: u_out }
}
