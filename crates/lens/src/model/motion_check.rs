//! Validation of decentred and tilted surfaces and elements: the motions'
//! numbers, the elements' ranges, and that a moved surface does not cross
//! its neighbours (checked in the moved surfaces' own frames).

use super::finding::Severity;
use super::placement::{of_surface, Placement};
use super::spec::PrescriptionSpec;
use super::validate::Findings;
use glam::DVec3;

/// The largest tilt, degrees: a surface tilted 90 degrees or more no
/// longer faces the light coming down the axis.
pub const MAX_TILT_DEG: f64 = 89.0;

/// Azimuths and rings sampled on a moved surface's clear aperture when
/// looking for a crossing with its neighbour.
const AZIMUTHS: usize = 72;
const RINGS: usize = 16;

/// Checks a decentre and tilt as written (`surface`: 1-based, or `None`
/// for an element, named by `what`).
pub(super) fn check_motion(
    out: &mut Findings,
    surface: Option<usize>,
    what: &str,
    decenter: Option<[f64; 2]>,
    tilt: Option<[f64; 2]>,
) {
    if let Some(d) = decenter {
        if !d.iter().all(|x| x.is_finite() && x.abs() <= super::validate::MAX_LENGTH) {
            out.push(
                Severity::Error,
                surface,
                Some("decenter_mm"),
                format!("{what}decenter_mm = {d:?}: give two finite numbers, mm in x and y"),
            );
        }
    }
    if let Some(t) = tilt {
        if !t.iter().all(|x| x.is_finite() && x.abs() <= MAX_TILT_DEG) {
            out.push(
                Severity::Error,
                surface,
                Some("tilt_deg"),
                format!(
                    "{what}tilt_deg = {t:?}: give two angles in degrees, about x then the new y, each within \
                     +-{MAX_TILT_DEG} (a surface turned further no longer faces the light)"
                ),
            );
        }
    }
}

/// Checks the elements' ranges (1-based, first <= last, inside the
/// prescription, not overlapping one another) and motions. Returns whether
/// they are usable for the crossing check.
pub(super) fn check_elements(out: &mut Findings, spec: &PrescriptionSpec) -> bool {
    let n = spec.surfaces.len();
    let mut fine = true;
    let elements = spec.elements.as_deref().unwrap_or(&[]);
    for (k, e) in elements.iter().enumerate() {
        let [first, last] = e.surfaces;
        let what = format!("element {} (surfaces {first}..{last}): ", k + 1);
        if first < 1 || first > last || last > n {
            out.push(
                Severity::Error,
                None,
                Some("elements"),
                format!(
                    "{what}\"surfaces\": [first, last] must number surfaces from 1 to {n}, first <= last \
                     (got [{first}, {last}])"
                ),
            );
            fine = false;
            continue;
        }
        if let Some((j, o)) =
            elements[..k].iter().enumerate().find(|(_, o)| o.surfaces[0] <= last && first <= o.surfaces[1])
        {
            out.push(
                Severity::Error,
                None,
                Some("elements"),
                format!(
                    "{what}overlaps element {} (surfaces {}..{}): a surface belongs to one element at most",
                    j + 1,
                    o.surfaces[0],
                    o.surfaces[1]
                ),
            );
            fine = false;
        }
        check_motion(out, None, &what, e.decenter_mm, e.tilt_deg);
    }
    fine
}

/// Each surface's placement from the spec (`None` on the axis); `None`
/// altogether when a number is unusable (reported elsewhere).
pub(super) fn placements(spec: &PrescriptionSpec) -> Option<Vec<Option<Placement>>> {
    let mut z = Vec::with_capacity(spec.surfaces.len());
    let mut at = 0.0;
    for s in &spec.surfaces {
        z.push(at);
        at += s.thickness;
    }
    let elements = spec.elements.as_deref().unwrap_or(&[]);
    let numbers = |v: &[f64]| v.iter().all(|x| x.is_finite());
    let usable = z.iter().all(|v| v.is_finite())
        && elements
            .iter()
            .all(|e| numbers(&e.decenter_mm.unwrap_or_default()) && numbers(&e.tilt_deg.unwrap_or_default()))
        && spec
            .surfaces
            .iter()
            .all(|s| numbers(&s.decenter_mm.unwrap_or_default()) && numbers(&s.tilt_deg.unwrap_or_default()));
    usable.then(|| {
        (0..spec.surfaces.len())
            .map(|i| {
                let s = &spec.surfaces[i];
                of_surface(i, s.decenter_mm.unwrap_or([0.0; 2]), s.tilt_deg.unwrap_or([0.0; 2]), &z, elements)
            })
            .collect()
    })
}

/// Whether surfaces `i` and `i + 1` (0-based) move as one rigid body (both
/// on the axis, or in the same element with no motion of their own): the
/// co-axial edge check then holds in their frame.
pub(super) fn rigid_pair(spec: &PrescriptionSpec, placements: &[Option<Placement>], i: usize) -> bool {
    let own = |s: &super::spec::SurfaceSpec| {
        s.decenter_mm.is_some_and(|d| d != [0.0; 2]) || s.tilt_deg.is_some_and(|t| t != [0.0; 2])
    };
    let element_of = |k: usize| {
        spec.elements.as_deref().unwrap_or(&[]).iter().position(|e| (e.surfaces[0]..=e.surfaces[1]).contains(&(k + 1)))
    };
    let (a, b) = (&spec.surfaces[i], &spec.surfaces[i + 1]);
    if own(a) || own(b) {
        return false;
    }
    (placements[i].is_none() && placements[i + 1].is_none())
        || (element_of(i).is_some() && element_of(i) == element_of(i + 1))
}

/// Checks that moved surfaces `i` and `i + 1` (0-based) do not cross: each
/// one's clear aperture, sampled on rings, must lie on its own side of the
/// other (the first in front of the second), each point compared with the
/// other surface's sag in that surface's own frame.
pub(super) fn check_moved_edge(
    out: &mut Findings,
    spec: &PrescriptionSpec,
    placements: &[Option<Placement>],
    i: usize,
) {
    let (a, b) = (&spec.surfaces[i], &spec.surfaces[i + 1]);
    let positive = |v: Option<f64>| v.filter(|x| x.is_finite() && *x > 0.0);
    let h_max = match (positive(a.semi_diameter), positive(b.semi_diameter)) {
        (Some(x), Some(y)) => x.min(y),
        (Some(x), None) | (None, Some(x)) => x,
        (None, None) => return,
    };
    if !a.thickness.is_finite() || a.thickness < 0.0 {
        return;
    }
    let pa = placements[i].unwrap_or(Placement::IDENTITY);
    // b's placement seen from a's vertex frame
    let shift = DVec3::new(0.0, 0.0, a.thickness);
    let pb = placements[i + 1].unwrap_or(Placement::IDENTITY);
    let pb = Placement { rotation: pb.rotation, offset: pb.offset + shift };
    // the point of `from`'s surface at local (x, y), in `to`'s frame: its
    // depth below `to`'s surface there (positive: behind it)
    let depth = |from: &super::spec::SurfaceSpec,
                 pf: &Placement,
                 to: &super::spec::SurfaceSpec,
                 pt: &Placement,
                 x: f64,
                 y: f64| {
        let r = x.hypot(y);
        let local = DVec3::new(x, y, from.sag(r)?);
        let q = pt.rotation.transpose() * (pf.rotation * local + pf.offset - pt.offset);
        Some(q.z - to.sag(q.x.hypot(q.y))?)
    };
    let tol = 1e-9 * (1.0 + a.thickness.abs() + h_max);
    let mut worst: Option<(f64, f64, f64, usize)> = None;
    for ring in 1..=RINGS {
        let h = h_max * ring as f64 / RINGS as f64;
        for k in 0..AZIMUTHS {
            let phi = std::f64::consts::TAU * k as f64 / AZIMUTHS as f64;
            let (x, y) = (h * phi.cos(), h * phi.sin());
            // a's points must lie in front of b (depth <= 0), b's behind a
            let found =
                [depth(a, &pa, b, &pb, x, y).map(|d| (d, i + 1)), depth(b, &pb, a, &pa, x, y).map(|d| (-d, i + 2))];
            for (d, which) in found.into_iter().flatten() {
                if d > tol && worst.is_none_or(|w| d > w.0) {
                    worst = Some((d, x, y, which));
                }
            }
        }
    }
    if let Some((d, x, y, which)) = worst {
        out.error(
            i + 1,
            "thickness",
            format!(
                "surfaces {} and {} cross where they are decentred or tilted: surface {which} at ({x:.4}, {y:.4}) mm \
                 of its clear aperture lies {d:.6} mm beyond the other; reduce the tilt or decentre, increase \
                 thickness of surface {} by at least {d:.6} mm, or reduce the semi_diameters",
                i + 1,
                i + 2,
                i + 1
            ),
        );
    }
}
