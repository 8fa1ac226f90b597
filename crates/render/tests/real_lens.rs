//! The real-lens camera against the lens crate's own predictions.

mod common;
use common::moments;
use glam::DVec3;
use lens::paraxial::FirstOrder;
use render::scene::format::SceneFile;
use render::{render, Options, Scene};
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

fn scene(json: &str) -> Scene {
    let file: SceneFile = serde_json::from_str(json).unwrap();
    Scene::build(file, &data(), "<test>").unwrap()
}

fn lamp_scene(camera: &str, lamp: DVec3, radius: f64, size: usize) -> Scene {
    scene(&format!(
        r#"{{"camera": {camera},
            "film": {{"width": {size}, "height": {size}, "spp": 64}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [{}, {}, {}], "radius": {radius}, "material": "l"}}]}}"#,
        lamp.x, lamp.y, lamp.z
    ))
}

#[test]
fn double_gauss_blur_matches_the_coc_analysis() {
    // Focused at 2 m from the film; lamps on the axis at 1 m and 2 m from the
    // film. The lens crate's `coc` measures object distances from the first
    // vertex, so convert with the focused lens's total track.
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                 "f_number": 2, "focus_distance": 2.0, "sensor_mm": [2.0, 2.0]}"#;
    let probe = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), 0.0005, 8);
    let render::camera::Camera::Real(real) = &probe.camera else { panic!() };
    let p = real.prescription();
    let track = p.total_track();
    let coc = lens::analysis::coc::circle_of_confusion(p, 2000.0 - track, &[1000.0 - track, 2000.0 - track]).unwrap();
    assert!((coc.film_distance - p.film_distance()).abs() < 1e-9, "the camera focuses exactly");
    let px_per_mm = 128.0 / 2.0;
    let mut measured = Vec::new();
    for (k, z) in [1.0, 2.0].into_iter().enumerate() {
        let s = lamp_scene(cam, DVec3::new(0.0, 0.0, z), 0.0005, 128);
        let (img, stats) = render(&s, Options { spp: 96, seed: 3 }, &|_| {});
        assert!(stats.pass_rate() > 0.75, "{}", stats.pass_rate());
        let (cx, cy, rms_px) = moments(&img);
        assert!((cx - 64.0).abs() < 1.0 && (cy - 64.0).abs() < 1.0, "on axis: {cx} {cy}");
        let rms_mm = rms_px / px_per_mm;
        let predicted = coc.rows[k].rms_diameter / 2.0;
        measured.push(rms_mm);
        if k == 0 {
            let rel = (rms_mm - predicted).abs() / predicted;
            assert!(rel < 0.10, "1 m: rendered RMS blur radius {rms_mm:.4} mm vs lens coc {predicted:.4} mm");
        }
    }
    // the object at the focus distance is sharp: several times less blur
    assert!(measured[1] < measured[0] / 5.0, "{measured:?}");
}

#[test]
fn tiny_stop_converges_to_a_pinhole_of_the_same_field_of_view() {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                 "stop_semi_diameter": 0.05, "focus_distance": 5.0, "sensor_mm": [12.0, 12.0]}"#;
    let lamp = DVec3::new(0.25, 0.15, 5.0);
    let real = lamp_scene(cam, lamp, 0.003, 96);
    let render::camera::Camera::Real(r) = &real.camera else { panic!() };
    let p = r.prescription();
    let f = FirstOrder::of(p).unwrap();
    // the pinhole sits at the entrance pupil; its field of view is the angle
    // of the real ray through the top of the film
    let ep_world = (p.total_track() - f.entrance_pupil.z) * 1e-3;
    let top = (0..400)
        .find_map(|k| real.camera.ray(0.5, 0.0, ((k % 20) as f64 / 20.0 + 0.025, (k / 20) as f64 / 20.0 + 0.025)))
        .unwrap()
        .0;
    let fov = 2.0 * top.dir.y.atan2(top.dir.z).to_degrees();
    let pinhole =
        format!(r#"{{"type": "pinhole", "position": [0,0,{ep_world}], "look_at": [0,0,1], "fov_deg": {fov}}}"#);
    let pin = lamp_scene(&pinhole, lamp, 0.003, 96);
    let (a, _) = render(&real, Options { spp: 32, seed: 1 }, &|_| {});
    let (b, _) = render(&pin, Options { spp: 32, seed: 1 }, &|_| {});
    let (ax, ay, _) = moments(&a);
    let (bx, by, _) = moments(&b);
    assert!((ax - bx).abs() < 0.5 && (ay - by).abs() < 0.5, "real ({ax:.2}, {ay:.2}) vs pinhole ({bx:.2}, {by:.2})");
    // and the lamp is off-centre, up and to the side where the scene puts it
    assert!(ay < 48.0, "{ay}");
}

#[test]
fn a_triangular_stop_makes_triangular_bokeh() {
    // A defocused on-axis lamp through the double Gauss: with a triangle
    // inscribed in the stop the blur's RMS radius is sqrt(1/2) of the round
    // stop's (E[r^2] = R^2/4 for the triangle, R^2/2 for the disc).
    let cam = |shape: &str| {
        format!(
            r#"{{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                 "f_number": 4, "focus_distance": 2.0, "sensor_mm": [1.5, 1.5], "aperture_shape": {shape}}}"#
        )
    };
    let rms = |shape: &str| {
        let s = lamp_scene(&cam(shape), DVec3::new(0.0, 0.0, 1.0), 0.0005, 64);
        let (img, _) = render(&s, Options { spp: 64, seed: 5 }, &|_| {});
        moments(&img).2
    };
    let round = rms(r#"{"shape": "circle"}"#);
    let triangle = rms(r#"{"shape": "polygon", "blades": 3, "rotation_deg": 90}"#);
    let ratio = triangle / round;
    assert!((ratio - 0.5f64.sqrt()).abs() < 0.05, "{triangle} / {round} = {ratio}");
}
