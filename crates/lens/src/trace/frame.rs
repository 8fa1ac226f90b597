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

    /// The frame change's numbers in lanes of `L`, made once per chunk
    /// (broadcast out of the loop over its vectors).
    #[inline(always)]
    pub(crate) fn lanes<L: Real>(&self) -> FrameLanes<L> {
        let s = L::splat;
        FrameLanes { r: self.r.map(|row| row.map(s)), into: self.into.map(s), out: self.out.map(s) }
    }

    /// The ray `l` (frame of the step before) in the surface's own frame.
    #[inline(always)]
    pub(crate) fn enter(&self, l: Lane<f64>) -> Lane<f64> {
        self.lanes().enter(l)
    }

    /// The ray `l` (the surface's own frame) in the co-axial frame at the
    /// surface's unperturbed vertex.
    #[inline(always)]
    pub(crate) fn leave(&self, l: Lane<f64>) -> Lane<f64> {
        self.lanes().leave(l)
    }
}

/// A [`Frame`] in lanes of `L`.
#[derive(Clone, Copy)]
pub(crate) struct FrameLanes<L> {
    r: [[L; 3]; 3],
    into: [L; 3],
    out: [L; 3],
}

impl<L: Real> FrameLanes<L> {
    /// The rays `l` (frame of the step before) in the surface's own frame;
    /// their path lengths as they are.
    #[inline(always)]
    pub(crate) fn enter(&self, l: Lane<L>) -> Lane<L> {
        let r = &self.r;
        let q = [l.px - self.into[0], l.py - self.into[1], l.pz - self.into[2]];
        let d = [l.dx, l.dy, l.dz];
        // component i of R^T v: column i of R against v
        let rt = |i: usize, v: [L; 3]| r[2][i].fma(v[2], r[1][i].fma(v[1], r[0][i] * v[0]));
        Lane { px: rt(0, q), py: rt(1, q), pz: rt(2, q), dx: rt(0, d), dy: rt(1, d), dz: rt(2, d), opl: l.opl }
    }

    /// The rays `l` (the surface's own frame) in the co-axial frame at the
    /// surface's unperturbed vertex.
    #[inline(always)]
    pub(crate) fn leave(&self, l: Lane<L>) -> Lane<L> {
        let r = &self.r;
        let p = [l.px, l.py, l.pz];
        let d = [l.dx, l.dy, l.dz];
        let m = |i: usize, v: [L; 3]| r[i][2].fma(v[2], r[i][1].fma(v[1], r[i][0] * v[0]));
        Lane {
            px: m(0, p) + self.out[0],
            py: m(1, p) + self.out[1],
            pz: m(2, p) + self.out[2],
            dx: m(0, d),
            dy: m(1, d),
            dz: m(2, d),
            opl: l.opl,
        }
    }
}
