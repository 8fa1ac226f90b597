//! The frame change of a decentred or tilted surface's step: a ray carried
//! from the co-axial frame of the step before into the surface's own frame
//! (its vertex at the origin, its axis along z), met and refracted there
//! by the ordinary step, and carried back to the co-axial frame at the
//! surface's unperturbed vertex (docs/architecture.md, "Tilted and
//! decentred surfaces"). Written once over the lane type, so the one-ray
//! path and the batch agree bit for bit; a co-axial step has no frame and
//! pays nothing.

use super::step::Lane;
use crate::model::Placement;
use crate::simd::lanes::Real;

/// A step's frame change: `local = R^T (p - into)` on the way in,
/// `p = R local + out` on the way out (directions rotate alone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    /// The rotation R, `r[i][j]` its row i, column j.
    r: [[f64; 3]; 3],
    /// The surface's vertex in the frame of the step before (its shift
    /// included), mm.
    into: [f64; 3],
    /// The surface's vertex in the co-axial frame at its unperturbed
    /// vertex, mm.
    out: [f64; 3],
}

impl Frame {
    /// The frame change of a surface at `placement`, `shift` mm along z
    /// from the frame of the step before.
    pub(crate) fn of(placement: Placement, shift: f64) -> Frame {
        let m = placement.rotation;
        let r = [0, 1, 2].map(|i| [m.x_axis[i], m.y_axis[i], m.z_axis[i]]);
        let o = placement.offset;
        Frame { r, into: [o.x, o.y, o.z + shift], out: o.to_array() }
    }

    /// The ray `l` (frame of the step before) in the surface's own frame.
    #[inline(always)]
    pub(crate) fn enter<L: Real>(&self, l: Lane<L>) -> Lane<L> {
        let s = L::splat;
        let q = [l.px - s(self.into[0]), l.py - s(self.into[1]), l.pz - s(self.into[2])];
        let d = [l.dx, l.dy, l.dz];
        // component i of R^T v: column i of R against v
        let rt = |i: usize, v: [L; 3]| s(self.r[2][i]).fma(v[2], s(self.r[1][i]).fma(v[1], s(self.r[0][i]) * v[0]));
        Lane { px: rt(0, q), py: rt(1, q), pz: rt(2, q), dx: rt(0, d), dy: rt(1, d), dz: rt(2, d), opl: l.opl }
    }

    /// The ray `l` (the surface's own frame) in the co-axial frame at the
    /// surface's unperturbed vertex.
    #[inline(always)]
    pub(crate) fn leave<L: Real>(&self, l: Lane<L>) -> Lane<L> {
        let s = L::splat;
        let p = [l.px, l.py, l.pz];
        let d = [l.dx, l.dy, l.dz];
        let r = |i: usize, v: [L; 3]| s(self.r[i][2]).fma(v[2], s(self.r[i][1]).fma(v[1], s(self.r[i][0]) * v[0]));
        Lane {
            px: r(0, p) + s(self.out[0]),
            py: r(1, p) + s(self.out[1]),
            pz: r(2, p) + s(self.out[2]),
            dx: r(0, d),
            dy: r(1, d),
            dz: r(2, d),
            opl: l.opl,
        }
    }
}
