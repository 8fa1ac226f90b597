//! Where a decentred or tilted surface sits: the rigid motion from its own
//! frame (vertex at the origin, axis along z) to the co-axial frame at its
//! unperturbed vertex, composed from the surface's own decentre and tilt
//! and those of the element it belongs to (docs/architecture.md, "Tilted
//! and decentred surfaces").

use super::spec::ElementSpec;
use glam::{DMat3, DVec3};

/// A rigid motion: a point `l` of the surface's own frame is at
/// `rotation * l + offset` in the co-axial frame whose origin is the
/// surface's unperturbed vertex (mm; +z toward the image).
///
/// ```
/// use lens::model::Placement;
/// // a surface tilted 90 deg about x: its axis turns toward -y
/// let p = Placement::of_motion([0.0, 0.0], [90.0, 0.0]);
/// let axis = p.rotation * lens::DVec3::Z;
/// assert!((axis.y + 1.0).abs() < 1e-15 && axis.z.abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The surface frame's axes in the co-axial frame (columns).
    pub rotation: DMat3,
    /// The surface's vertex in the co-axial frame, mm.
    pub offset: DVec3,
}

impl Placement {
    /// No motion.
    pub const IDENTITY: Placement = Placement { rotation: DMat3::IDENTITY, offset: DVec3::ZERO };

    /// A decentre (mm, x and y) then a tilt (degrees) about x and then
    /// about the new y, about the decentred vertex: Zemax's coordinate
    /// break of order 0, right-handed (a positive tilt about x turns the
    /// axis toward -y, one about y toward +x).
    pub fn of_motion(decenter_mm: [f64; 2], tilt_deg: [f64; 2]) -> Placement {
        let rotation =
            DMat3::from_rotation_x(tilt_deg[0].to_radians()) * DMat3::from_rotation_y(tilt_deg[1].to_radians());
        Placement { rotation, offset: DVec3::new(decenter_mm[0], decenter_mm[1], 0.0) }
    }

    /// The motion of a surface `h` mm (along the axis) behind the first
    /// vertex of an element moved by `element` about that vertex: the
    /// element's motion seen from the surface's own unperturbed vertex.
    pub fn within_element(element: Placement, h: f64) -> Placement {
        let along = DVec3::new(0.0, 0.0, h);
        Placement { rotation: element.rotation, offset: element.rotation * along + element.offset - along }
    }

    /// `self` after `inner`: a point of `inner`'s frame carried by `inner`,
    /// then by `self`.
    pub fn then(self, inner: Placement) -> Placement {
        Placement { rotation: self.rotation * inner.rotation, offset: self.rotation * inner.offset + self.offset }
    }

    /// Whether this is no motion at all.
    pub fn is_identity(&self) -> bool {
        *self == Placement::IDENTITY
    }
}

/// Where surface `i` (0-based) sits, given its own decentre (mm) and tilt
/// (degrees), the unperturbed vertices' z (mm, every surface) and the
/// elements (surfaces numbered from 1): its own motion within its
/// element's; `None` on the axis. Ranges outside `vertex_z` count as no
/// element (validation reports them).
pub fn of_surface(
    i: usize,
    decenter_mm: [f64; 2],
    tilt_deg: [f64; 2],
    vertex_z: &[f64],
    elements: &[ElementSpec],
) -> Option<Placement> {
    let own = Placement::of_motion(decenter_mm, tilt_deg);
    let element = elements
        .iter()
        .find(|e| e.surfaces[0] >= 1 && (e.surfaces[0]..=e.surfaces[1]).contains(&(i + 1)))
        .and_then(|e| {
            let first = *vertex_z.get(e.surfaces[0] - 1)?;
            let motion = Placement::of_motion(e.decenter_mm.unwrap_or([0.0; 2]), e.tilt_deg.unwrap_or([0.0; 2]));
            Some(Placement::within_element(motion, vertex_z.get(i)? - first))
        });
    let at = element.map_or(own, |e| e.then(own));
    (!at.is_identity()).then_some(at)
}
