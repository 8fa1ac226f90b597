//! Workspace-level checks of the shipped data: every prescription in
//! lens-data/ loads, validates clean and has sane first-order numbers.

use lens::model::{validate::validate, Severity};
use lens::paraxial::FirstOrder;

#[test]
fn every_shipped_prescription_validates_and_cites_its_source() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("lens-data");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        count += 1;
        let spec = lens::load_spec(&path).unwrap();
        let findings = validate(&spec);
        assert!(findings.iter().all(|f| f.severity != Severity::Error), "{}: {findings:?}", path.display());
        assert!(spec.source.as_deref().is_some_and(|s| s.len() > 10), "{}: no source", path.display());
        let p = lens::Prescription::from_spec(&spec).unwrap();
        let f = FirstOrder::of(&p).unwrap();
        assert!(f.efl > 0.0 && f.f_number > 1.0 && f.f_number < 20.0, "{}: {f:?}", path.display());
        let focus = lens::analysis::focus::focus(&p, lens::paraxial::ObjectDistance::Infinity).unwrap();
        assert!(focus.best_focus_film_distance.is_finite());
    }
    assert_eq!(count, 12, "expected the twelve shipped prescriptions");
}
