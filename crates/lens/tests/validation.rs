//! Validation finds every problem, names the surface and field, and no input
//! of any shape panics.

mod common;
use lens::model::{validate::validate, Severity};
use lens::{LoadError, Prescription, PrescriptionSpec};
use proptest::prelude::*;

fn findings(json: &str) -> Vec<String> {
    let spec = PrescriptionSpec::from_json_str(json, "<test>").unwrap();
    validate(&spec).iter().map(|f| f.to_string()).collect()
}

#[test]
fn every_error_is_reported_not_just_the_first() {
    let f = findings(
        r#"{"surfaces": [
        {"radius": 0, "thickness": -1, "ior": 0.5, "semi_diameter": -2},
        {"radius": 12, "thickness": 2, "ior": 1.5, "semi_diameter": 14, "stop": true},
        {"radius": -12, "thickness": 0, "semi_diameter": 5, "stop": true}
    ]}"#,
    );
    let all = f.join("\n");
    for needle in [
        "surface 1: radius 0",
        "surface 1: thickness -1 mm is negative",
        "surface 1: ior 0.5",
        "surface 1: semi_diameter -2 mm",
        "surface 2: semi_diameter 14 mm exceeds |radius| 12 mm",
        "2 surfaces are marked as the stop (surfaces 2, 3)",
        "surface 3: the last thickness is the distance to the film and must be > 0 mm",
    ] {
        assert!(all.contains(needle), "missing {needle:?} in\n{all}");
    }
}

#[test]
fn no_stop_units_and_crossing_surfaces() {
    let all = findings(
        r#"{"units": "inch", "surfaces": [
        {"radius": 20, "thickness": 1, "ior": 1.5, "semi_diameter": 10},
        {"radius": -20, "thickness": 50, "semi_diameter": 10}
    ]}"#,
    )
    .join("\n");
    assert!(all.contains("units \"inch\" are not supported"), "{all}");
    assert!(all.contains("no aperture stop"), "{all}");
    assert!(all.contains("surfaces 1 and 2 cross inside their common aperture: the glass"), "{all}");
    // air gaps too: a rear element touching the front one
    let all = findings(
        r#"{"surfaces": [
        {"radius": 20, "thickness": 5, "ior": 1.5, "semi_diameter": 8, "stop": true},
        {"radius": -20, "thickness": 0.1, "semi_diameter": 8},
        {"radius": -15, "thickness": 3, "ior": 1.5, "semi_diameter": 8},
        {"thickness": 30, "semi_diameter": 8}
    ]}"#,
    )
    .join("\n");
    assert!(all.contains("surfaces 2 and 3 cross inside their common aperture: the air"), "{all}");
    assert!(!all.contains("surfaces 1 and 2"), "{all}");
}

#[test]
fn missing_semi_diameter_is_a_warning_and_errors_fail_loading() {
    let spec = PrescriptionSpec::from_json_str(
        r#"{"surfaces": [{"radius": 50, "thickness": 3, "ior": 1.5, "stop": true, "semi_diameter": 5},
                         {"thickness": 90}]}"#,
        "<t>",
    )
    .unwrap();
    let f = validate(&spec);
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].severity, Severity::Warning);
    assert_eq!(f[0].surface, Some(2));
    assert!(Prescription::from_spec(&spec).is_ok());
    let e = Prescription::from_json_str(r#"{"surfaces": [{"thickness": 3, "semi_diameter": 5}]}"#, "x.json");
    let Err(LoadError::Invalid { findings, .. }) = e else { panic!("{e:?}") };
    assert!(findings.iter().any(|f| f.message.contains("no aperture stop")));
}

#[test]
fn malformed_json_gets_line_and_column_and_unknown_fields_are_named() {
    let e = PrescriptionSpec::from_json_str("{\n  \"surfaces\": [\n    {\"radius\": 1.0,, }\n  ]\n}", "bad.json");
    let Err(LoadError::Json { line, column, .. }) = e else { panic!("{e:?}") };
    assert_eq!((line, column), (3, 20));
    let e = PrescriptionSpec::from_json_str(r#"{"surfaces": [{"thickness": 1, "radious": 5}]}"#, "typo.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("unknown field `radious`"), "{e}");
    let e = PrescriptionSpec::from_json_str(r#"{"surfaces": [{"thickness": "thick"}]}"#, "t.json").unwrap_err();
    assert!(e.to_string().contains("line 1"), "{e}");
    let e = PrescriptionSpec::from_json_str(r#"{"surfaces": [{"thickness": 1e999}]}"#, "t.json").unwrap_err();
    assert!(matches!(e, LoadError::Json { .. }), "{e}");
}

#[test]
fn pbrt_dat_import_of_the_reference_lenses() {
    let dir = common::data_dir().join("pbrt");
    for (dat, json) in [
        ("dgauss.50mm.dat", "double-gauss-50mm.json"),
        ("wide.22mm.dat", "wide-angle-22mm.json"),
        ("fisheye.10mm.dat", "fisheye-10mm.json"),
        ("telephoto.250mm.dat", "telephoto-250mm.json"),
    ] {
        let from_dat = Prescription::load(dir.join(dat)).unwrap();
        let shipped = Prescription::load(common::data_dir().join(json)).unwrap();
        assert_eq!(from_dat.surfaces().len(), shipped.surfaces().len(), "{dat}");
        for (a, b) in from_dat.surfaces().iter().zip(shipped.surfaces()) {
            assert!((a.curvature - b.curvature).abs() <= 1e-15 * a.curvature.abs(), "{dat}");
            assert_eq!(a.ior, b.ior, "{dat}");
            assert_eq!(a.semi_diameter, b.semi_diameter, "{dat}");
            assert_eq!(a.stop, b.stop, "{dat}");
            assert!((a.thickness - b.thickness).abs() < 1e-9, "{dat}");
        }
        // last thickness 0 in the .dat: the film sits at the paraxial focus
        let f = lens::paraxial::FirstOrder::of(&from_dat).unwrap();
        assert!((from_dat.film_distance() - f.bfl).abs() < 1e-12, "{dat}");
    }
}

#[test]
fn malformed_dat_lines_are_errors_with_line_numbers() {
    let e = lens::io::dat::parse_dat("# x\n1 2 3\n", "a.dat").unwrap_err().to_string();
    assert!(e.contains("a.dat: line 2: expected 4 numbers"), "{e}");
    let e = lens::io::dat::parse_dat("1 2 x 4\n", "a.dat").unwrap_err().to_string();
    assert!(e.contains("ior \"x\" is not a number"), "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Arbitrary numbers in every field: validation never panics, and
    /// whatever loads gives finite first-order numbers or a typed error.
    #[test]
    fn no_input_panics(rows in prop::collection::vec(
        (prop::option::of(prop_oneof![Just(0.0), Just(f64::NAN), Just(1e308), -1e3f64..1e3]),
         prop_oneof![Just(0.0), Just(-1.0), Just(f64::INFINITY), 0.0f64..100.0],
         prop::option::of(prop_oneof![Just(0.5), Just(f64::NAN), 1.0f64..4.0]),
         prop::option::of(prop_oneof![Just(0.0), Just(-1.0), 0.0f64..50.0]),
         any::<bool>()), 0..8)) {
        let spec = PrescriptionSpec {
            surfaces: rows.iter().map(|&(radius, thickness, ior, semi_diameter, stop)| lens::SurfaceSpec {
                ior, semi_diameter, stop, ..lens::SurfaceSpec::new(radius, thickness) }).collect(),
            ..PrescriptionSpec::default()
        };
        let _ = validate(&spec);
        if let Ok(p) = Prescription::from_spec(&spec) {
            if let Ok(f) = lens::paraxial::FirstOrder::of(&p) {
                prop_assert!(f.efl.is_finite() && f.bfl.is_finite() && f.entrance_pupil.diameter.is_finite());
                prop_assert!(f.f_number.is_finite());
            }
            let _ = lens::analysis::focus::focus(&p, lens::paraxial::ObjectDistance::Finite(1000.0));
        }
    }

    /// Arbitrary text as a .dat or JSON file never panics.
    #[test]
    fn arbitrary_text_never_panics(text in "[ -~\\n\\t]{0,200}") {
        let _ = lens::io::dat::parse_dat(&text, "fuzz.dat");
        let _ = PrescriptionSpec::from_json_str(&text, "fuzz.json");
    }
}
