//! Internal focusing: a prescription's `focus_group` moves between its
//! neighbours to focus, the film and the lens's length staying.

use lens::analysis::focus::focus;
use lens::paraxial::{film_distance, focus_group_shift, focus_group_shift_for_focus, ObjectDistance};
use lens::{Prescription, PrescriptionSpec};

fn double_gauss(group: Option<[usize; 2]>) -> Result<Prescription, String> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/double-gauss-50mm.json"))
        .unwrap();
    let mut spec = PrescriptionSpec::from_json_str(&text, "<dg>").unwrap();
    spec.focus_group = group;
    Prescription::from_spec(&spec).map_err(|f| f.iter().map(|x| x.to_string()).collect::<Vec<_>>().join("; "))
}

/// The front cemented doublet (surfaces 3-5) focuses the double Gauss on a
/// plane 2 m from the film: the moved lens images it paraxially on the
/// unmoved film (1e-9 mm), its length and film are unchanged, and only
/// the two gaps beside the group changed, by opposite amounts.
#[test]
fn the_group_moves_and_the_film_stays() {
    let p = double_gauss(Some([3, 5])).unwrap();
    assert_eq!(p.focus_group(), Some((2, 4)));
    let shift = focus_group_shift_for_focus(&p, 2000.0).unwrap();
    let q = p.with_focus_group_shift(shift).unwrap();
    let object = 2000.0 - p.total_track();
    let image = film_distance(&q, ObjectDistance::Finite(object)).unwrap();
    assert!((image - p.film_distance()).abs() < 1e-9, "image {image} mm, film {} mm", p.film_distance());
    assert!((q.total_track() - p.total_track()).abs() < 1e-12 && q.film_distance() == p.film_distance());
    let (a, b) = (p.surfaces(), q.surfaces());
    for i in 0..a.len() {
        let d = b[i].thickness - a[i].thickness;
        match i {
            1 => assert!((d - shift).abs() < 1e-12),
            4 => assert!((d + shift).abs() < 1e-12),
            _ => assert_eq!(d, 0.0, "surface {}", i + 1),
        }
    }
    assert!(shift > 1.0, "near focus moves the doublet back: {shift} mm");
    // the real-ray best focus differs from the paraxial by the lens's
    // spherical aberration, and lands on the film as well
    let best = focus_group_shift(&p, |q| focus(q, ObjectDistance::Finite(object)).map(|f| f.best_focus_film_distance))
        .unwrap();
    let q = p.with_focus_group_shift(best).unwrap();
    let f = focus(&q, ObjectDistance::Finite(object)).unwrap();
    assert!((f.best_focus_film_distance - p.film_distance()).abs() < 1e-9);
    assert!((best - shift).abs() > 1e-4, "{best} {shift}");
}

/// A group without air on both sides, out of range, or moved further than
/// its gaps allow is refused saying what to change; the key survives the
/// JSON round trip.
#[test]
fn bad_focus_groups_are_named() {
    let e = double_gauss(Some([2, 5])).unwrap_err();
    assert!(e.contains("focus_group [2, 5]") && e.contains("must be air"), "{e}");
    let e = double_gauss(Some([1, 5])).unwrap_err();
    assert!(e.contains("focus_group [1, 5]") && e.contains("2 <= first <= last <= 10"), "{e}");
    let e = double_gauss(Some([7, 11])).unwrap_err();
    assert!(e.contains("focus_group [7, 11]"), "{e}");
    let p = double_gauss(Some([3, 5])).unwrap();
    let e = p.with_focus_group_shift(-0.5).unwrap_err().to_string();
    assert!(e.contains("cannot move -0.5 mm: the gaps before and after it are 0.12 and 5.705 mm"), "{e}");
    let q = Prescription::from_spec(&p.to_spec()).unwrap();
    assert_eq!(q.focus_group(), Some((2, 4)));
    let no_group = double_gauss(None).unwrap();
    assert!(no_group.with_focus_group_shift(0.1).is_err());
    assert!(focus_group_shift_for_focus(&no_group, 2000.0).is_err());
}
