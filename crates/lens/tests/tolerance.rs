//! Tolerancing: trials reproducible bit for bit whatever the shares and
//! threads; the closed-form back focus is the refocus least squares
//! finds; distributions as documented; invalid lenses counted, never
//! judged; bad files refused by name.

use lens::glass::Catalogs;
use lens::io::load_spec;
use lens::tolerance::{merge, ToleranceSpec, Tolerancing};
use lens::PrescriptionSpec;
use std::path::Path;

fn triplet() -> PrescriptionSpec {
    load_spec(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/cooke-triplet.json")).unwrap()
}

fn shipped() -> ToleranceSpec {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/design/cooke-triplet.tolerance.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn analysis(t: &ToleranceSpec) -> Tolerancing {
    Tolerancing::new(t, triplet(), Catalogs::shipped()).unwrap()
}

/// The same trials from one run, from three shares merged in any order,
/// and on one thread: equal to the bit.
#[test]
fn trials_are_reproducible_across_shares_and_threads() {
    let tol = analysis(&shipped());
    let whole = tol.run(11, 60, [1, 1]).unwrap();
    let shares: Vec<_> = [3, 1, 2].iter().map(|&i| tol.run(11, 60, [i, 3]).unwrap()).collect();
    let merged = merge(&shares).unwrap();
    assert_eq!(merged.results, whole.results);
    // through JSON (as shares travel between machines), still to the bit
    let travelled: Vec<lens::tolerance::Share> =
        shares.iter().map(|s| serde_json::from_str(&serde_json::to_string(s).unwrap()).unwrap()).collect();
    assert_eq!(merge(&travelled).unwrap().results, whole.results);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let single = one.install(|| tol.run(11, 60, [1, 1]).unwrap());
    assert_eq!(single.results, whole.results);
    assert_eq!(tol.statistics(&shares).unwrap(), tol.statistics(std::slice::from_ref(&whole)).unwrap());
    // another seed draws other lenses
    assert_ne!(tol.run(12, 60, [1, 1]).unwrap().results, whole.results);
    // a share missing, a share twice, another analysis: refused
    assert!(merge(&shares[..2]).unwrap_err().contains("in no share"));
    let twice = vec![shares[0].clone(), shares[0].clone(), shares[1].clone(), shares[2].clone()];
    assert!(merge(&twice).unwrap_err().contains("in two shares"));
    let mut other = shipped();
    other.tolerances[0].plus_minus = 0.2;
    let foreign = analysis(&other).run(11, 60, [1, 3]).unwrap();
    assert!(merge(&[foreign, shares[1].clone(), shares[2].clone()]).unwrap_err().contains("another analysis"));
}

/// The back focus found in closed form is the film least squares finds
/// for the same criterion, and moving the film either way from it makes
/// the criterion worse.
#[test]
fn closed_form_back_focus_is_the_refocus_optimum() {
    let fast = analysis(&shipped());
    let mut general = shipped();
    general.compensators = vec![serde_json::from_str(r#"{"surface": 7, "param": "thickness"}"#).unwrap()];
    let slow = analysis(&general);
    let values = fast.draw(3, 5);
    let lens = fast.perturbed(&values);
    let (v_fast, film) = fast.criterion.judge(&lens).unwrap();
    let (v_slow, film_slow) = slow.criterion.judge(&lens).unwrap();
    assert!((v_fast - v_slow).abs() < 1e-9 * v_fast, "{v_fast} vs {v_slow}");
    assert!((film[0] - film_slow[0]).abs() < 1e-4, "{film:?} vs {film_slow:?}");
    let mut none = shipped();
    none.compensators.clear();
    let fixed = analysis(&none);
    for dz in [0.0, 0.02, -0.02] {
        let mut at = lens.clone();
        at.surfaces.last_mut().unwrap().thickness = film[0] + dz;
        let (v, _) = fixed.criterion.judge(&at).unwrap();
        if dz == 0.0 {
            assert!((v - v_fast).abs() < 1e-12 * v, "{v} vs {v_fast}");
        } else {
            assert!(v > v_fast, "dz {dz}: {v} <= {v_fast}");
        }
    }
}

/// Normal draws stay within +-plus_minus with the truncated normal's
/// spread (0.880 sigma, sigma = plus_minus / 2); uniform ones have
/// plus_minus / sqrt(3).
#[test]
fn distributions_are_as_documented() {
    let mut t = shipped();
    t.tolerances.truncate(2);
    t.tolerances[1].distribution = Some("uniform".into());
    let tol = analysis(&t);
    let draws: Vec<Vec<f64>> = (0..20_000).map(|k| tol.draw(5, k)).collect();
    let sd = |i: usize| {
        let m = draws.iter().map(|d| d[i]).sum::<f64>() / draws.len() as f64;
        (draws.iter().map(|d| (d[i] - m).powi(2)).sum::<f64>() / draws.len() as f64).sqrt()
    };
    assert!(draws.iter().all(|d| d[0].abs() <= 0.1 && d[1].abs() <= 1.0));
    assert!((sd(0) / (0.05 * 0.8796) - 1.0).abs() < 0.02, "{}", sd(0));
    assert!((sd(1) / (1.0 / 3f64.sqrt()) - 1.0).abs() < 0.02, "{}", sd(1));
}

/// Tolerances large enough to make surfaces cross give invalid trials,
/// counted and never judged.
#[test]
fn crossing_trials_are_counted() {
    let mut t = shipped();
    t.tolerances = vec![serde_json::from_str(
        r#"{"type": "thickness", "surface": 4, "plus_minus": 4.0, "distribution": "uniform"}"#,
    )
    .unwrap()];
    let tol = analysis(&t);
    let share = tol.run(1, 200, [1, 1]).unwrap();
    let s = tol.statistics(&[share]).unwrap();
    assert!(s.invalid > 20, "{s:?}");
    assert_eq!(s.judged + s.invalid + s.unmeasured, 200);
    assert!(s.failures[0].contains("invalid"), "{:?}", s.failures);
    assert!(s.yield_fraction.unwrap() <= s.judged as f64 / 200.0);
}

/// Fringes change the sag at the semi-diameter by fringes x lambda / 2.
#[test]
fn fringes_change_the_sag_at_the_rim() {
    let mut t = shipped();
    t.tolerances = vec![serde_json::from_str(r#"{"type": "fringes", "surface": 1, "plus_minus": 3}"#).unwrap()];
    let tol = analysis(&t);
    let before = tol.nominal.surfaces[0].sag(14.7).unwrap();
    let after = tol.perturbed(&[3.0]).surfaces[0].sag(14.7).unwrap();
    assert!((after - before - 3.0 * 546.074e-6 / 2.0).abs() < 1e-12, "{}", after - before);
}

/// Bad tolerance files are refused, each naming the tolerance.
#[test]
fn bad_tolerances_are_refused() {
    let refused = |json: &str| {
        let mut t = shipped();
        t.tolerances = vec![serde_json::from_str(json).unwrap()];
        Tolerancing::new(&t, triplet(), Catalogs::shipped()).unwrap_err().to_string()
    };
    let e = refused(r#"{"type": "wedge", "surface": 1, "plus_minus": 1}"#);
    assert!(e.contains("tolerance 1 (wedge): unknown type"), "{e}");
    let e = refused(r#"{"type": "radius", "surface": 9, "plus_minus": 1}"#);
    assert!(e.contains("surfaces 1 to 7"), "{e}");
    let e = refused(r#"{"type": "abbe", "surface": 2, "plus_minus": 1}"#);
    assert!(e.contains("air follows surface 2"), "{e}");
    let e = refused(r#"{"type": "element_tilt", "surfaces": [4, 3], "axis": "x", "plus_minus": 1}"#);
    assert!(e.contains("first <= last"), "{e}");
    let e = refused(r#"{"type": "surface_tilt", "surface": 3, "plus_minus": 1}"#);
    assert!(e.contains("axis"), "{e}");
    let e = refused(r#"{"type": "radius", "surface": 1, "plus_minus": -1}"#);
    assert!(e.contains("plus_minus -1"), "{e}");
    let mut t = shipped();
    t.criterion.kind = "strehl".into();
    let e = Tolerancing::new(&t, triplet(), Catalogs::shipped()).unwrap_err().to_string();
    assert!(e.contains("criterion: type \"strehl\""), "{e}");
}

/// An MTF criterion with the back focus compensated ends at an MTF at
/// least that of the lens at its own film, and of the film of least RMS
/// spot where least squares starts (through-focus MTF has side lobes).
#[test]
fn mtf_refocus_is_no_worse_than_its_starts() {
    let mut t = shipped();
    t.tolerances.truncate(1);
    t.criterion = serde_json::from_str(r#"{"type": "mtf", "fields_deg": [0, 10], "frequency_per_mm": 20}"#).unwrap();
    let comp = analysis(&t);
    t.compensators.clear();
    let fixed = analysis(&t);
    let lens = comp.perturbed(&[0.08]);
    let (v, film) = comp.criterion.judge(&lens).unwrap();
    let (at_own, _) = fixed.criterion.judge(&lens).unwrap();
    assert!(v >= at_own, "{v} < {at_own}");
    let mut at = lens.clone();
    at.surfaces.last_mut().unwrap().thickness = film[0];
    let (again, _) = fixed.criterion.judge(&at).unwrap();
    assert!((again - v).abs() < 1e-12, "{again} vs {v}");
}

/// When no trial can be judged the statistics are refused, not NaN.
#[test]
fn no_judged_trial_is_an_error_not_nan() {
    let tol = analysis(&shipped());
    let mut share = tol.run(1, 3, [1, 1]).unwrap();
    for r in &mut share.results {
        r.value = None;
        r.failure = Some("invalid: surfaces cross".into());
    }
    let e = tol.statistics(&[share]).unwrap_err();
    assert!(e.contains("none of the 3 trials could be judged"), "{e}");
}

/// A criterion's fields may have x components (`fields_x_deg`, in the
/// order of `fields_deg`): on the symmetric nominal an x field judges as
/// the y field of the same angle; a decentre in x then tells them apart;
/// lists of different lengths are refused.
#[test]
fn criterion_fields_take_x_components() {
    let judge = |json: &str, lens: &PrescriptionSpec| {
        let mut t = shipped();
        t.criterion = serde_json::from_str(json).unwrap();
        analysis(&t).criterion.judge(lens).unwrap().0
    };
    let y = r#"{"type": "rms_spot", "fields_deg": [10]}"#;
    let x = r#"{"type": "rms_spot", "fields_deg": [0], "fields_x_deg": [10]}"#;
    let (vy, vx) = (judge(y, &triplet()), judge(x, &triplet()));
    assert!((vy - vx).abs() <= 1e-12 * vy, "{vy} vs {vx}");
    let mut moved = triplet();
    moved.elements =
        Some(vec![lens::model::ElementSpec { surfaces: [3, 4], decenter_mm: Some([0.2, 0.0]), tilt_deg: None }]);
    let (vy, vx) = (judge(y, &moved), judge(x, &moved));
    assert!((vy - vx).abs() > 1e-3 * vy, "{vy} vs {vx}");
    let mut t = shipped();
    t.criterion = serde_json::from_str(r#"{"type": "rms_spot", "fields_deg": [0, 10], "fields_x_deg": [5]}"#).unwrap();
    let e = Tolerancing::new(&t, triplet(), Catalogs::shipped()).unwrap_err().to_string();
    assert!(e.contains("fields_x_deg has 1 angles and fields_deg 2"), "{e}");
}
