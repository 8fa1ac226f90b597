//! Fields with an x component ([`Field::Angles`], [`Field::Point`]): a lens
//! symmetric about its axis images an oblique field as the y field of the
//! same total angle turned about the axis, and an x field as the y field
//! mirrored in the plane x = y (fans, wavefronts and MTFs with x and y
//! swapped); an element decentred in x at an x field is the one decentred
//! in y at a y field, mirrored; y fields made through the new constructors
//! are the old ones; inputs that are not fields are named.

mod common;
use common::*;
use lens::analysis::fan::{ray_fan, ImagePlane};
use lens::analysis::wave::mtf::mtf;
use lens::analysis::wave::{stats, wavefront};
use lens::analysis::{Aim, Field, Launcher};
use lens::model::{ElementSpec, VignettingFactors};
use lens::paraxial::FirstOrder;
use lens::{DVec3, Prescription, PrescriptionSpec, Tracer};

fn load(name: &str) -> Prescription {
    Prescription::load(data_dir().join(name)).unwrap()
}

/// Where the ray of `launcher` through pupil point (px, py) lands on the
/// paraxial image plane of `p` (at infinity), `None` where it is blocked.
fn landing(p: &Prescription, launcher: &Launcher, px: f64, py: f64) -> Option<DVec3> {
    let image_z = launcher.paraxial_image_z(p).unwrap();
    let tracer = Tracer::forward_to_film(p, image_z - p.last_vertex_z());
    tracer.trace(launcher.ray(px, py).ok()?).reached().map(|r| r.origin)
}

/// Pupil points over the unit disc (a 9 x 9 grid inside radius 0.98).
fn pupil_points() -> Vec<(f64, f64)> {
    let u = |k: usize| -0.98 + 1.96 * k as f64 / 8.0;
    (0..9).flat_map(|i| (0..9).map(move |j| (u(i), u(j)))).filter(|(x, y)| x * x + y * y <= 0.98 * 0.98).collect()
}

#[test]
fn an_oblique_field_is_a_y_field_turned_about_the_axis() {
    // (x, y) component angles make the direction (tan x, tan y, 1): the y
    // field of angle atan(hypot(tan x, tan y)) turned by the rotation R
    // taking +y to (tan x, tan y)'s direction; pupil point q of the
    // oblique field is R^-1 q of the y field, and lands at R times its
    // landing.
    let cases = [
        ("double-gauss-50mm.json", Aim::Paraxial, 6.0, 8.0, 1e-10),
        ("double-gauss-50mm.json", Aim::Real, -9.0, 4.0, 1e-8),
        ("wide-angle-22mm.json", Aim::Real, 20.0, -25.0, 1e-8),
    ];
    for (name, aim, x_deg, y_deg, tol) in cases {
        let p = load(name);
        let (tx, ty) = (f64::to_radians(x_deg).tan(), f64::to_radians(y_deg).tan());
        let t = tx.hypot(ty);
        let (ux, uy) = (tx / t, ty / t);
        let turn = |x: f64, y: f64| (uy * x + ux * y, -ux * x + uy * y);
        let back = |x: f64, y: f64| (uy * x - ux * y, ux * x + uy * y);
        let oblique = Launcher::new(&p, Field::angles(x_deg, y_deg), aim).unwrap();
        let along_y = Launcher::new(&p, Field::Angle(t.atan().to_degrees()), aim).unwrap();
        let mut compared = 0;
        for (px, py) in pupil_points() {
            let (qx, qy) = back(px, py);
            match (landing(&p, &oblique, px, py), landing(&p, &along_y, qx, qy)) {
                (Some(a), Some(b)) => {
                    let (bx, by) = turn(b.x, b.y);
                    assert!(
                        (a.x - bx).abs() < tol && (a.y - by).abs() < tol,
                        "{name} ({px}, {py}): {a} vs ({bx}, {by})"
                    );
                    compared += 1;
                }
                (None, None) => {}
                (a, b) => panic!("{name} ({px}, {py}): vignetted differently: {a:?} vs {b:?}"),
            }
        }
        assert!(compared > 20, "{name}: only {compared} rays through");
    }
}

#[test]
fn an_object_point_off_the_y_axis_is_the_y_point_turned() {
    // a finite object: the point (x, y) is the point (0, hypot(x, y)) turned
    let mut spec = lens::load_spec(&data_dir().join("double-gauss-50mm.json")).unwrap();
    spec.object_distance_mm = Some(600.0);
    let p = Prescription::from_spec(&spec).unwrap();
    let first = FirstOrder::of(&p).unwrap();
    let (x, y) = (-30.0, 45.0);
    let field = Field::at_angles(&p, &first, 4.0, -3.0);
    let Field::Point { object_distance, .. } = field else { panic!("{field:?}") };
    assert_eq!(object_distance, 600.0);
    let h = f64::hypot(x, y);
    let (ux, uy) = (x / h, y / h);
    let oblique = Launcher::new(&p, Field::point(600.0, x, y), Aim::Paraxial).unwrap();
    let along_y = Launcher::new(&p, Field::Height { object_distance: 600.0, height: h }, Aim::Paraxial).unwrap();
    for (px, py) in pupil_points() {
        let (qx, qy) = (uy * px - ux * py, ux * px + uy * py);
        let (Some(a), Some(b)) = (landing(&p, &oblique, px, py), landing(&p, &along_y, qx, qy)) else { continue };
        let (bx, by) = (uy * b.x + ux * b.y, -ux * b.x + uy * b.y);
        assert!((a.x - bx).abs() < 1e-10 && (a.y - by).abs() < 1e-10, "({px}, {py}): {a} vs ({bx}, {by})");
    }
    // the component angles of the field given as angles come back
    let [ax, ay] = field.angles_deg(first.entrance_pupil.z);
    assert!((ax - 4.0).abs() < 1e-12 && (ay + 3.0).abs() < 1e-12, "{ax}, {ay}");
}

#[test]
fn an_x_field_is_the_y_field_mirrored_in_every_analysis() {
    // mirrored in the plane x = y: the x field's sagittal fan is the y
    // field's tangential fan, its wavefront the same numbers, its MTF's
    // tangential (y) the y field's sagittal (x) (within the MTF
    // quadrature's refinement tolerance, 1e-3; they differ by 5e-5)
    let p = load("double-gauss-50mm.json");
    let x = Launcher::new(&p, Field::angles(12.0, 0.0), Aim::Paraxial).unwrap();
    let y = Launcher::new(&p, Field::angles(0.0, 12.0), Aim::Paraxial).unwrap();
    assert_eq!(y.field(), Field::Angle(12.0));
    let fx = ray_fan(&p, x.field(), 11, Aim::Paraxial, ImagePlane::Paraxial).unwrap();
    let fy = ray_fan(&p, y.field(), 11, Aim::Paraxial, ImagePlane::Paraxial).unwrap();
    assert_eq!((fx.field_x_deg, fx.field_deg), (Some(12.0), Some(0.0)));
    assert_eq!((fy.field_x_deg, fy.field_deg), (None, Some(12.0)));
    assert!((fx.chief[0] - fy.chief[1]).abs() < 1e-12 && fx.chief[1].abs() < 1e-12);
    for (s, t) in fx.sagittal.iter().zip(&fy.tangential) {
        assert_eq!(s.px, t.py);
        match (s.ex, t.ey) {
            (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "px {}: {a} vs {b}", s.px),
            (a, b) => assert_eq!(a.is_some(), b.is_some()),
        }
    }
    let json = serde_json::to_value(&fx).unwrap();
    assert_eq!(json["field_x_deg"], 12.0);
    assert!(serde_json::to_value(&fy).unwrap().get("field_x_deg").is_none(), "a y field's report is unchanged");

    let (wx, wy) = (
        wavefront(&p, &p, &x, 256, ImagePlane::Paraxial).unwrap(),
        wavefront(&p, &p, &y, 256, ImagePlane::Paraxial).unwrap(),
    );
    let (sx, sy) = (stats(&wx), stats(&wy));
    assert!(
        (sx.rms_to_chief - sy.rms_to_chief).abs() < 1e-9 * sy.rms_to_chief,
        "{} vs {}",
        sx.rms_to_chief,
        sy.rms_to_chief
    );
    assert!((sx.strehl - sy.strehl).abs() < 1e-9, "{} vs {}", sx.strehl, sy.strehl);
    let freqs = [10.0, 30.0];
    let (mx, my) = (
        mtf(&p, &p, &x, ImagePlane::Paraxial, &freqs).unwrap(),
        mtf(&p, &p, &y, ImagePlane::Paraxial, &freqs).unwrap(),
    );
    for k in 0..freqs.len() {
        assert!((mx.tangential[k] - my.sagittal[k]).abs() < 1e-3, "{:?} vs {:?}", mx.tangential, my.sagittal);
        assert!((mx.sagittal[k] - my.tangential[k]).abs() < 1e-3, "{:?} vs {:?}", mx.sagittal, my.tangential);
    }
}

#[test]
fn an_x_decentre_at_an_x_field_is_the_y_decentre_at_the_y_field_mirrored() {
    let moved = |d: [f64; 2]| {
        let mut spec = lens::load_spec(&data_dir().join("double-gauss-50mm.json")).unwrap();
        spec.elements = Some(vec![ElementSpec { surfaces: [3, 5], decenter_mm: Some(d), tilt_deg: None }]);
        Prescription::from_spec(&spec).unwrap()
    };
    let (px_lens, py_lens) = (moved([0.3, 0.0]), moved([0.0, 0.3]));
    for aim in [Aim::Paraxial, Aim::Real] {
        let a = Launcher::new(&px_lens, Field::angles(7.0, 3.0), aim).unwrap();
        let b = Launcher::new(&py_lens, Field::angles(3.0, 7.0), aim).unwrap();
        let tol = if aim == Aim::Real { 1e-8 } else { 1e-11 };
        for (px, py) in pupil_points() {
            let (Some(u), Some(v)) = (landing(&px_lens, &a, px, py), landing(&py_lens, &b, py, px)) else { continue };
            assert!((u.x - v.y).abs() < tol && (u.y - v.x).abs() < tol, "{aim:?} ({px}, {py}): {u} vs {v}");
        }
    }
}

#[test]
fn y_fields_made_with_an_x_of_zero_are_the_y_fields() {
    let p = load("cooke-triplet.json");
    let first = FirstOrder::of(&p).unwrap();
    assert_eq!(Field::angles(0.0, 14.0), Field::Angle(14.0));
    assert_eq!(Field::point(500.0, 0.0, -20.0), Field::Height { object_distance: 500.0, height: -20.0 });
    assert_eq!(Field::at_angles(&p, &first, 0.0, 14.0), Field::at_angle(&p, &first, 14.0));
    assert!(!Field::Angle(3.0).has_x() && Field::angles(1.0, 0.0).has_x());
}

#[test]
fn bad_x_fields_and_y_only_factors_are_named() {
    let p = load("cooke-triplet.json");
    for (field, what) in [
        (Field::angles(90.0, 0.0), "x field angle"),
        (Field::angles(f64::NAN, 1.0), "x field angle"),
        (Field::Angles { x_deg: 1.0, y_deg: -95.0 }, "y field angle"),
        (Field::point(100.0, f64::INFINITY, 0.0), "object x"),
        (Field::Point { object_distance: -5.0, x: 1.0, y: 0.0 }, "object"),
    ] {
        let e = Launcher::new(&p, field, Aim::Paraxial).unwrap_err().to_string();
        assert!(e.contains(what), "{field:?}: {e}");
    }
    // vignetting factors belong to y fields
    let mut spec: PrescriptionSpec = lens::load_spec(&data_dir().join("cooke-triplet.json")).unwrap();
    spec.fields_deg = Some(vec![0.0, 14.0]);
    spec.vignetting_factors =
        Some(vec![VignettingFactors::default(), VignettingFactors { compress_y: 0.2, ..Default::default() }]);
    let p = Prescription::from_spec(&spec).unwrap();
    let e = ray_fan(&p, Field::angles(5.0, 5.0), 5, Aim::Paraxial, ImagePlane::Paraxial).unwrap_err().to_string();
    assert!(e.contains("vignetting factors") && e.contains("y only"), "{e}");
    assert!(ray_fan(&p, Field::Angle(10.0), 5, Aim::Paraxial, ImagePlane::Paraxial).is_ok());
}
