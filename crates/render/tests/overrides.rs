//! The command line's camera and film flags override a scene as its own
//! fields would, and switching camera type carries what it can.

use render::camera::Camera;
use render::scene::format::ApertureSpec;
use render::scene::{CameraKind, Overrides};
use render::Scene;
use std::path::Path;

fn scenes() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

#[test]
fn film_and_thin_lens_settings_override_the_file() {
    let o = Overrides {
        width: Some(64),
        height: Some(32),
        aperture: Some(0.5),
        focus_distance: Some(9.0),
        aperture_shape: Some(ApertureSpec::Polygon { blades: 6, rotation_deg: 0.0 }),
        ..Default::default()
    };
    let s = Scene::load_with(&scenes().join("dof-study.json"), &o).unwrap();
    assert_eq!((s.film.width, s.film.height), (64, 32));
    let Camera::ThinLens { radius, focus, .. } = &s.camera else { panic!("a thin lens") };
    assert_eq!((*radius, *focus), (0.25, 9.0));
}

#[test]
fn one_side_of_the_film_alone_keeps_the_files_aspect() {
    // dof-study.json is 320 x 180 (16:9)
    let load = |o: Overrides| Scene::load_with(&scenes().join("dof-study.json"), &o).unwrap().film;
    let f = load(Overrides { width: Some(160), ..Default::default() });
    assert_eq!((f.width, f.height), (160, 90));
    let f = load(Overrides { height: Some(45), ..Default::default() });
    assert_eq!((f.width, f.height), (80, 45));
    let f = load(Overrides { width: Some(1), ..Default::default() });
    assert_eq!((f.width, f.height), (1, 1));
}

#[test]
fn a_real_lens_becomes_the_thin_lens_matched_to_it() {
    let o = Overrides { camera: Some(CameraKind::ThinLens), ..Default::default() };
    let s = Scene::load_with(&scenes().join("dof-double-gauss-f2.json"), &o).unwrap();
    let Camera::ThinLens { radius, tan_half, .. } = &s.camera else { panic!("a thin lens") };
    // the double Gauss: EFL 50.358 mm at f/2 on a 20.25 mm high sensor
    let efl = 50.358167;
    assert!((radius * 2.0 - efl / 2.0 * 1e-3).abs() < 1e-6, "{radius}");
    assert!((tan_half - 10.125 / efl).abs() < 1e-6, "{tan_half}");
}

#[test]
fn flags_a_camera_cannot_take_are_refused_by_name() {
    let e = |o: Overrides, scene: &str| Scene::load_with(&scenes().join(scene), &o).err().unwrap().to_string();
    let msg = e(Overrides { aperture: Some(0.1), ..Default::default() }, "dof-pinhole.json");
    assert!(msg.contains("camera.aperture") && msg.contains("pinhole"), "{msg}");
    let msg = e(Overrides { focal_length_mm: Some(50.0), ..Default::default() }, "dof-double-gauss-f2.json");
    assert!(msg.contains("camera.focal_length_mm"), "{msg}");
    let msg = e(Overrides { camera: Some(CameraKind::Lens), ..Default::default() }, "dof-study.json");
    assert!(msg.contains("camera.prescription"), "{msg}");
    let msg = e(Overrides { width: Some(0), ..Default::default() }, "dof-study.json");
    assert!(msg.contains("film"), "{msg}");
}
