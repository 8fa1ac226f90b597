//! Paraxial results against closed forms: lensmaker, Gullstrand, Gauss.

mod common;
use common::*;
use lens::paraxial::{imaging, FirstOrder, ObjectDistance};
use proptest::prelude::*;

fn radius() -> impl Strategy<Value = f64> {
    prop_oneof![(20.0f64..500.0), (-500.0f64..-20.0)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Gullstrand's equation is exact for a thick singlet in air:
    /// phi = phi1 + phi2 - t/n phi1 phi2, with BFL = f (1 - t phi1 / n).
    #[test]
    fn gullstrand_thick_lens(r1 in radius(), r2 in radius(), t in 0.5f64..15.0, n in 1.3f64..2.0) {
        let sd = 0.4 * r1.abs().min(r2.abs());
        let p = singlet(Some(r1), Some(r2), t, n, sd, 100.0);
        let phi1 = (n - 1.0) / r1;
        let phi2 = (1.0 - n) / r2;
        let phi = phi1 + phi2 - t / n * phi1 * phi2;
        prop_assume!(phi.abs() > 1e-6);
        let f = FirstOrder::of(&p).unwrap();
        prop_assert!(rel(f.efl, 1.0 / phi) < 1e-12, "efl {} vs {}", f.efl, 1.0 / phi);
        let bfl = (1.0 - t * phi1 / n) / phi;
        prop_assert!((f.bfl - bfl).abs() < 1e-9 * bfl.abs().max(1.0));
        let ffd = -(1.0 - t * phi2 / n) / phi;
        prop_assert!((f.ffd - ffd).abs() < 1e-9 * ffd.abs().max(1.0));
        // principal planes: rear at z = t + bfl - f, front at ffd + f
        prop_assert!((f.back_principal_plane - (t + bfl - 1.0 / phi)).abs() < 1e-9 * (1.0 + 1.0 / phi.abs()));
        prop_assert!((f.front_principal_plane - (ffd + 1.0 / phi)).abs() < 1e-9 * (1.0 + 1.0 / phi.abs()));
    }

    /// The thin-lens limit: as t -> 0 the EFL converges to the lensmaker's
    /// 1/f = (n - 1)(1/R1 - 1/R2), the error shrinking in proportion to t.
    #[test]
    fn lensmaker_thin_limit(r1 in radius(), r2 in radius(), n in 1.3f64..2.0) {
        let lensmaker = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2));
        prop_assume!(lensmaker.abs() < 1e4);
        let sd = 0.1 * r1.abs().min(r2.abs());
        let mut last = f64::INFINITY;
        for t in [1.0, 1e-2, 1e-4, 1e-6] {
            let f = FirstOrder::of(&singlet(Some(r1), Some(r2), t, n, sd, 100.0)).unwrap();
            let err = rel(f.efl, lensmaker);
            prop_assert!(err <= last * 0.2 || err < 1e-12, "t {t}: error {err} did not shrink from {last}");
            // exactly the Gullstrand term: rel. error = t (n-1)^2 / (n R1 R2) * f
            let bound = t * (n - 1.0).powi(2) / (n * (r1 * r2).abs()) * f.efl.abs();
            prop_assert!((err - bound).abs() <= 1e-6 * bound + 1e-12, "t {t}: error {err} above {bound}");
            last = err;
        }
    }

    /// Finite objects obey the Gaussian lens equation measured from the
    /// principal planes, 1/s' - 1/s = 1/f, and m = s'/s.
    #[test]
    fn gaussian_conjugates(r1 in radius(), r2 in radius(), t in 0.5f64..10.0, n in 1.4f64..1.9, k in 1.2f64..50.0) {
        let sd = 0.3 * r1.abs().min(r2.abs());
        let p = singlet(Some(r1), Some(r2), t, n, sd, 100.0);
        let f = FirstOrder::of(&p).unwrap();
        prop_assume!(f.efl > 5.0);
        // object k focal lengths in front of the front principal plane
        let s = -k * f.efl;
        let d = -(f.front_principal_plane + s);
        prop_assume!(d > 1.0);
        let img = imaging(&p, &f, ObjectDistance::Finite(d)).unwrap();
        let s_img = 1.0 / (1.0 / f.efl + 1.0 / s);
        let z_img = f.back_principal_plane + s_img;
        prop_assert!((img.image_distance - (z_img - t)).abs() < 1e-9 * z_img.abs().max(1.0));
        prop_assert!((img.magnification - s_img / s).abs() < 1e-10);
    }
}

#[test]
fn plano_convex_efl_is_r_over_n_minus_1_for_any_thickness() {
    for t in [0.1, 5.0, 30.0] {
        let p = singlet(Some(51.68), None, t, 1.5168, 12.0, 100.0);
        let f = FirstOrder::of(&p).unwrap();
        assert!(rel(f.efl, 51.68 / 0.5168) < 1e-14);
        assert!(rel(f.bfl, 100.0 - t / 1.5168) < 1e-13);
    }
}

#[test]
fn cooke_triplet_matches_smith_published_values() {
    // W. J. Smith, Modern Optical Engineering, 4th ed., ch. 6: EFL 101.181,
    // BFL 77.405, NA 0.1443 (f-number 1 / (2 NA) = 3.465), to the printed
    // digits, with the book's indices (nd 1.61272 and 1.64769)...
    let text = std::fs::read_to_string(data_dir().join("cooke-triplet.json")).unwrap();
    let book = text
        .replace("\"glass\": \"SCHOTT:N-SK4\"", "\"ior\": 1.61272")
        .replace("\"glass\": \"SCHOTT:SF2\"", "\"ior\": 1.64769");
    let p = lens::Prescription::from_json_str(&book, "book").unwrap();
    assert!(!p.is_dispersive());
    let f = FirstOrder::of(&p).unwrap();
    assert!((f.efl - 101.181).abs() < 5e-4, "{}", f.efl);
    assert!((f.bfl - 77.405).abs() < 5e-4, "{}", f.bfl);
    assert!((f.f_number - 1.0 / (2.0 * 0.1443)).abs() < 2e-3, "{}", f.f_number);
    // ... and with the catalogue glasses the file names, whose formulas give
    // nd within 1e-5 of the book's: the focal lengths within 2e-3 mm
    let p = lens::Prescription::load(data_dir().join("cooke-triplet.json")).unwrap();
    assert!(p.is_dispersive());
    let g = FirstOrder::of(&p).unwrap();
    assert!((g.efl - 101.181).abs() < 2e-3 && (g.bfl - 77.405).abs() < 2e-3, "{} {}", g.efl, g.bfl);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Focus and its inverse agree, and the thick-lens model gives the same
    /// image as the full paraxial trace.
    #[test]
    fn focus_inverse_and_thick_lens_model_round_trip(d in 300.0f64..1e6) {
        for name in ["double-gauss-50mm.json", "cooke-triplet.json", "telephoto-250mm.json", "fisheye-10mm.json"] {
            let p = lens::Prescription::load(data_dir().join(name)).unwrap();
            let film = lens::paraxial::film_distance(&p, ObjectDistance::Finite(d)).unwrap();
            let back = lens::paraxial::object_distance_in_focus(&p, film).unwrap();
            let ObjectDistance::Finite(d2) = back else { return Err(TestCaseError::fail("infinite")) };
            prop_assert!(rel(d2, d) < 1e-9, "{name}: {d2} vs {d}");
            let thick = lens::paraxial::ThickLens::of(&p).unwrap();
            let z = thick.image_z(-d).unwrap();
            prop_assert!((z - (p.last_vertex_z() + film)).abs() < 1e-9 * z.abs().max(1.0), "{name}");
        }
    }
}

#[test]
fn film_at_the_rear_focal_plane_is_in_focus_at_infinity() {
    let p = lens::Prescription::load(data_dir().join("double-gauss-50mm.json")).unwrap();
    let f = FirstOrder::of(&p).unwrap();
    assert_eq!(lens::paraxial::object_distance_in_focus(&p, f.bfl).unwrap(), ObjectDistance::Infinity);
    let e = lens::paraxial::object_distance_in_focus(&p, f.bfl - 1.0).unwrap_err();
    assert!(matches!(e, lens::OpticsError::NoRealObject { .. }), "{e:?}");
}
