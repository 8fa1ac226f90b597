//! Colour figures against closed forms: a thin singlet's axial colour, an
//! F-C achromat's united foci, constant indices' absence of colour.

use lens::analysis::chromatic::chromatic;
use lens::analysis::Aim;
use lens::glass::{LINE_C_NM, LINE_D_NM, LINE_F_NM};
use lens::paraxial::FirstOrder;
use lens::Prescription;

fn data(f: &str) -> String {
    format!("{}/../../lens-data/{f}", env!("CARGO_MANIFEST_DIR"))
}

/// A thin equiconvex N-BK7 singlet: the F and C foci lie apart by
/// f_d (nd - 1) (1/(nF - 1) - 1/(nC - 1)) (thin lens, 1/f ∝ n - 1), about
/// -f/vd; the analysis's paraxial axial colour matches to the thickness's
/// share (1e-3 relative).
#[test]
fn thin_singlet_axial_colour_is_f_over_v() {
    let p = Prescription::from_json_str(
        r#"{"surfaces": [
          {"radius": 103.36, "thickness": 0.2, "glass": "SCHOTT:N-BK7", "semi_diameter": 2, "stop": true},
          {"radius": -103.36, "thickness": 99.9, "semi_diameter": 2}]}"#,
        "<singlet>",
    )
    .unwrap();
    let g = &p.glasses()[0];
    let (nd, nf, nc) = (g.index(LINE_D_NM).unwrap(), g.index(LINE_F_NM).unwrap(), g.index(LINE_C_NM).unwrap());
    let f = FirstOrder::of(&p).unwrap().efl;
    let want = f * (nd - 1.0) * (1.0 / (nf - 1.0) - 1.0 / (nc - 1.0));
    let c = chromatic(&p, 0.0, 1.0, Aim::Paraxial).unwrap();
    assert!((c.axial_colour - want).abs() < 1e-3 * want.abs(), "{} vs {want}", c.axial_colour);
    assert!((c.axial_colour + f / g.vd().unwrap()).abs() < 0.02 * want.abs());
    // one glass, on surface 1, with its data-sheet figures
    assert_eq!(c.glasses.len(), 1);
    assert_eq!(c.glasses[0].surfaces, vec![1]);
    assert!((c.glasses[0].vd - 64.17).abs() < 0.01);
}

/// The same thin singlet designed for an object at 3 f: each wavelength's
/// image lies at v = 1 / (1/f - 1/u), so the axial colour grows by
/// (v/f)^2 = 2.25 against the object at infinity (thin lens; the thickness's
/// share 1e-2 relative), and the lateral colour is the finite object's.
#[test]
fn axial_colour_follows_a_finite_design_object() {
    let singlet = |object: &str| {
        Prescription::from_json_str(
            &format!(
                r#"{{{object}"surfaces": [
          {{"radius": 103.36, "thickness": 0.2, "glass": "SCHOTT:N-BK7", "semi_diameter": 2, "stop": true}},
          {{"radius": -103.36, "thickness": 99.9, "semi_diameter": 2}}]}}"#
            ),
            "<singlet>",
        )
        .unwrap()
    };
    let inf = singlet("");
    let f = FirstOrder::of(&inf).unwrap().efl;
    let near = singlet(&format!(r#""object_distance_mm": {},"#, 3.0 * f));
    let (a, b) =
        (chromatic(&inf, 0.0, 1.0, Aim::Paraxial).unwrap(), chromatic(&near, 0.0, 1.0, Aim::Paraxial).unwrap());
    let ratio = b.axial_colour / a.axial_colour;
    assert!((ratio - 2.25).abs() < 0.01 * 2.25, "{ratio}");
    // each point of the focal-shift curve is that wavelength's image of the object at 3 f
    for pt in b.focal_shift.iter().step_by(10) {
        // u and v from the (thin) lens's middle, 0.1 mm behind the first vertex
        let v = 1.0 / (1.0 / pt.efl - 1.0 / (3.0 * f + 0.1));
        assert!((pt.image_distance - (v - 0.1)).abs() < 1e-3 * v, "{} vs {}", pt.image_distance, v - 0.1);
    }
}

/// The F-C achromat: F and C foci together (to the design's 1e-9 mm), d
/// apart from them by the secondary spectrum of an N-BK7/SF5 pair (about
/// f/2000), the focal-shift curve's minimum between F and C, and no
/// lateral colour on the axis.
#[test]
fn fc_achromat_unites_f_and_c() {
    let p = Prescription::load(data("achromat-fc-100mm.json")).unwrap();
    let c = chromatic(&p, 1.0, 5.0, Aim::Paraxial).unwrap();
    assert!(c.axial_colour.abs() < 1e-8, "{}", c.axial_colour);
    assert!(c.secondary_spectrum < -0.03 && c.secondary_spectrum > -0.08, "{}", c.secondary_spectrum);
    let min = c.focal_shift.iter().min_by(|a, b| a.focal_shift.total_cmp(&b.focal_shift)).unwrap();
    assert!(min.wavelength_nm > LINE_F_NM && min.wavelength_nm < LINE_C_NM, "{}", min.wavelength_nm);
    assert_eq!(c.lateral[0].field_deg, 0.0);
    assert!(c.lateral[0].lateral_colour.abs() < 1e-15);
    // the focal shift is 0 at the primary, as defined
    let d = c.focal_shift.iter().find(|f| (f.wavelength_nm - 585.0).abs() < 1e-9).unwrap();
    assert!(d.focal_shift.abs() < 0.01);
    // every wavelength's spot is there, and the polychromatic RMS is at
    // least the smallest single-wavelength one
    assert_eq!(c.spot.wavelengths.len(), 3);
    let smallest = c.spot.wavelengths.iter().map(|w| w.rms_radius).fold(f64::INFINITY, f64::min);
    assert!(c.spot.rms_radius >= smallest);
}

/// Constant indices: no colour at all, exactly.
#[test]
fn constant_indices_have_no_colour() {
    let p = Prescription::load(data("telephoto-250mm.json")).unwrap();
    let c = chromatic(&p, 2.0, 4.0, Aim::Paraxial).unwrap();
    assert_eq!(c.axial_colour, 0.0);
    assert_eq!(c.secondary_spectrum, 0.0);
    assert!(c.focal_shift.iter().all(|f| f.focal_shift == 0.0));
    assert!(c.lateral.iter().all(|l| l.lateral_colour == 0.0));
    assert!(c.glasses.is_empty());
}

/// A largest field that is not an angle is refused, naming the flag.
#[test]
fn bad_fields_are_refused() {
    let p = Prescription::load(data("achromat-fc-100mm.json")).unwrap();
    for m in [0.0, -1.0, 90.0, f64::NAN] {
        let e = chromatic(&p, 0.0, m, Aim::Paraxial).unwrap_err().to_string();
        assert!(e.contains("max_field_deg"), "{e}");
    }
}
