//! Frame sequences: keyframes checked before rendering, focus breathing out
//! of the real lens against the paraxial image, the same noise frame to
//! frame.

mod common;
use common::moments;
use render::animation::{frame_path, Animation};
use render::camera::Camera;
use render::scene::Overrides;
use render::{render, Options};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

/// A scene file beside the shipped scenes (so its relative paths work),
/// removed when dropped.
struct Temp(PathBuf);
impl Drop for Temp {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}
fn write(name: &str, json: &str) -> Temp {
    let p = scenes().join(format!("test-{}-{name}.json", std::process::id()));
    std::fs::write(&p, json).unwrap();
    Temp(p)
}

/// One small lamp 3 m away, 0.5 m off the axis, through the double Gauss
/// at f/8 (its defocused image's centroid near the chief ray), with
/// `animation`.
fn lamp_scene(animation: &str) -> String {
    format!(
        r#"{{"camera": {{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                        "f_number": 8, "focus_distance": 10, "sensor_mm": [36, 24]}},
            "film": {{"width": 192, "height": 128, "spp": 64, "spectral": "off"}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [0.5, 0, 3], "radius": 0.002, "material": "l"}}],
            "animation": {animation}}}"#
    )
}

/// The paraxial image height (mm on the film) of a point `y` mm off the
/// axis `z` mm in front of the film, through the camera's focused lens:
/// the chief ray through the entrance pupil's centre.
fn paraxial_height(cam: &Camera, y: f64, z: f64) -> f64 {
    let Camera::Real(r) = cam else { panic!() };
    let p = r.prescription();
    let first = lens::paraxial::FirstOrder::of(p).unwrap();
    let object = z - p.total_track();
    let u0 = -y / (first.entrance_pupil.z + object);
    let ray = lens::paraxial::trace(p, y + u0 * object, u0);
    ray.last_y() + ray.last_u() * p.film_distance()
}

/// A focus pull from 10 m to 1 m moves the film back and the image of a
/// lamp 3 m away grows by the ratio the paraxial chief ray predicts (focus
/// breathing, out of the real lens): measured 1.04683 against 1.04812,
/// within 0.2% (the heights themselves are 0.2-0.3% under the paraxial
/// ones: the lens's distortion at 9.5 degrees).
#[test]
fn focus_breathing_follows_the_paraxial_image() {
    let f = write(
        "breathing",
        &lamp_scene(
            r#"{"frames": 3, "keyframes": [{"frame": 0, "focus_distance": 10}, {"frame": 2, "focus_distance": 1}]}"#,
        ),
    );
    let anim = Animation::load(&f.0, &Overrides::default(), None).unwrap();
    assert_eq!(anim.frames(), 3);
    let mut measured = Vec::new();
    let mut predicted = Vec::new();
    for k in [0, 2] {
        // fine pixels: the lamp's image at 10 m is under a pixel of the
        // scene's 192 x 128 film, its centroid a pixel centre
        let mut s = anim.scene(k).unwrap();
        (s.film.width, s.film.height) = (960, 640);
        let (img, _) = render(&s, Options { spp: 4, seed: 1 }, &|_| {});
        let (cx, cy, _) = moments(&img);
        let mm_per_px = 36.0 / 960.0;
        measured.push(((cx - 480.0) * mm_per_px).hypot((cy - 320.0) * mm_per_px));
        predicted.push(paraxial_height(&s.camera, 500.0, 3000.0).abs());
    }
    // the middle frame is focused between them (in 1 / distance: 1 / 5.5 m)
    let Camera::Real(mid) = anim.scene(1).unwrap().camera else { panic!() };
    assert!((mid.focus_distance_m() - 1.0 / (0.5 * (0.1 + 1.0))).abs() < 1e-9, "{}", mid.focus_distance_m());
    let (m, p) = (measured[1] / measured[0], predicted[1] / predicted[0]);
    assert!(m > 1.02, "the image grows as the lens focuses near: {m}");
    assert!(
        (m - p).abs() < 2e-3 * p,
        "image scale change {m:.5}, paraxial {p:.5} (heights {measured:?} mm, {predicted:?})"
    );
}

/// Keyframes out of order, beyond the sequence, a focus behind the camera
/// and an f-number the lens cannot reach are named before any frame is
/// rendered (`check`), by keyframe.
#[test]
fn bad_keyframes_are_named() {
    let err = |anim: &str| -> String {
        let f = write("bad", &lamp_scene(anim));
        match Animation::load(&f.0, &Overrides::default(), None) {
            Err(e) => e.to_string(),
            Ok(a) => a.check().map(|_| "checked".to_string()).unwrap_or_else(|e| e.to_string()),
        }
    };
    let e =
        err(r#"{"frames": 10, "keyframes": [{"frame": 5, "focus_distance": 2}, {"frame": 3, "focus_distance": 4}]}"#);
    assert!(e.contains("animation.keyframes[1].frame") && e.contains("increasing frame order"), "{e}");
    let e = err(r#"{"frames": 10, "keyframes": [{"frame": 10, "focus_distance": 2}]}"#);
    assert!(e.contains("frame 10 of a 10-frame sequence"), "{e}");
    let e = err(r#"{"frames": 10, "keyframes": [{"frame": 0, "focus_distance": -2}]}"#);
    assert!(e.contains("keyframes[0].focus_distance") && e.contains("in front of the camera"), "{e}");
    let e = err(r#"{"frames": 10, "keyframes": [{"frame": 0, "f_number": 2}, {"frame": 9, "f_number": 0.6}]}"#);
    assert!(e.contains("animation.keyframes[1]") && e.contains("camera.f_number"), "{e}");
    let e = err(r#"{"frames": 4, "keyframes": [{"frame": 0, "focal_length_mm": 50}]}"#);
    assert!(e.contains("animation.zoom") && e.contains("list its prescriptions"), "{e}");
    let e = err(
        r#"{"frames": 10, "keyframes": [{"frame": 0, "focus_distance": 2}, {"frame": 9, "focus_distance": 0.01}]}"#,
    );
    assert!(e.contains("animation.keyframes[1]"), "{e}");
    assert_eq!(
        err(r#"{"frames": 10, "keyframes": [{"frame": 0, "focus_distance": 2}, {"frame": 9, "f_number": 4}]}"#),
        "checked"
    );
}

/// A zoom keyframed between the library zoom's two listed positions has
/// the focal length asked for (to 1e-9), and at a listed position the
/// position's own lens.
#[test]
fn zoom_focal_lengths_between_listed_positions() {
    let anim_json = r#"{"frames": 3, "zoom": ["../library/zoom-80-200mm-f2.8-at-80mm-jp53131852.json",
                                          "../library/zoom-80-200mm-f2.8-at-200mm-jp53131852.json"],
                        "keyframes": [{"frame": 0, "focal_length_mm": 80}, {"frame": 2, "focal_length_mm": 200}]}"#;
    let json = lamp_scene(anim_json)
        .replace("../double-gauss-50mm.json", "../library/zoom-80-200mm-f2.8-at-80mm-jp53131852.json")
        .replace("\"f_number\": 8,", "");
    let f = write("zoom", &json);
    let anim = Animation::load(&f.0, &Overrides::default(), None).unwrap();
    let efl = |k: u32| {
        let Camera::Real(r) = anim.scene(k).unwrap().camera else { panic!() };
        lens::paraxial::FirstOrder::of(r.prescription()).unwrap().efl
    };
    let listed = lens::paraxial::FirstOrder::of(
        &lens::Prescription::load(scenes().join("../library/zoom-80-200mm-f2.8-at-80mm-jp53131852.json")).unwrap(),
    )
    .unwrap()
    .efl;
    assert!((efl(0) - listed).abs() < 1e-12 * listed, "{} {listed}", efl(0));
    // 80 -> 200 in equal zoom ratios: the middle frame at sqrt(80 * 200)
    let mid = (80.0f64 * 200.0).sqrt();
    assert!((efl(1) - mid).abs() < 1e-9 * mid, "{} against {mid}", efl(1));
    let f = write("zoom-out", &json.replace("\"focal_length_mm\": 200", "\"focal_length_mm\": 300"));
    let e = Animation::load(&f.0, &Overrides::default(), None).unwrap().check().unwrap_err().to_string();
    assert!(e.contains("300 mm is outside the zoom's range"), "{e}");
}

/// Frame numbers go into the file name as %d or %0Nd; anything else is
/// refused saying how to write it.
#[test]
fn frame_names() {
    assert_eq!(frame_path("frames/f%04d.exr", 7).unwrap(), PathBuf::from("frames/f0007.exr"));
    assert_eq!(frame_path("f%d.png", 12).unwrap(), PathBuf::from("f12.png"));
    for bad in ["f.png", "f%x.png", "f%04d%d.png", "f%4d.png"] {
        assert!(frame_path(bad, 1).unwrap_err().contains("%04d"), "{bad}");
    }
}

/// A 24-frame focus pull of the portrait scene (320 x 180, as shipped:
/// the double Gauss, spectral; and with its camera matched by a thin
/// lens): consecutive frames draw the same random numbers in each pixel
/// and (through the real lens) aim them through the same exit-pupil
/// bounds, so in the region the pull leaves unchanged (the sky, rows 0-30)
/// their difference is below a tenth of the noise of one frame (the
/// difference between two seeds over the square root of 2): seen 0.084
/// through the real lens, 0.06 through the thin lens. Where the pull
/// changes the picture (the ground) the difference is the change.
#[test]
fn consecutive_frames_share_their_noise() {
    let portrait = std::fs::read_to_string(scenes().join("portrait-double-gauss.json")).unwrap();
    let json = portrait.trim_end().trim_end_matches('}').to_string()
        + r#", "animation": {"frames": 24, "keyframes": [{"frame": 0, "focus_distance": 1.85}, {"frame": 23, "focus_distance": 12}]}}"#;
    let f = write("pull", &json);
    for camera in [None, Some(render::scene::CameraKind::ThinLens)] {
        let o = Overrides { width: Some(320), camera, ..Default::default() };
        let anim = Animation::load(&f.0, &o, None).unwrap();
        let spp = 4;
        let a = render(&anim.scene(11).unwrap(), Options { spp, seed: 1 }, &|_| {}).0;
        let b = render(&anim.scene(12).unwrap(), Options { spp, seed: 1 }, &|_| {}).0;
        let c = render(&anim.scene(11).unwrap(), Options { spp, seed: 2 }, &|_| {}).0;
        assert_eq!((a.width, a.height), (320, 180));
        let rows = |x: &render::Image, y: &render::Image, r: std::ops::Range<usize>| {
            let n = r.len() * 320 * 3;
            let sum: f64 = r
                .flat_map(|row| (0..320).map(move |col| row * 320 + col))
                .map(|i| (x.pixels[i] - y.pixels[i]).length_squared())
                .sum();
            (sum / n as f64).sqrt()
        };
        let frame_to_frame = rows(&a, &b, 0..30);
        let noise = rows(&a, &c, 0..30) / 2f64.sqrt();
        assert!(noise > 0.0);
        assert!(
            frame_to_frame < 0.1 * noise,
            "{camera:?}: frame to frame {frame_to_frame:.6}, one frame's noise {noise:.6}"
        );
        // where the pull changes the picture (the ground), frames differ
        assert!(rows(&a, &b, 150..180) > 0.1 * rows(&a, &c, 150..180) / 2f64.sqrt());
    }
}

/// The exit-pupil bounds a sequence shares, seen from films other than
/// the one they were made at (the ends of a pull from 10 m to 0.6 m, the
/// bounds made at its middle and scaled), leave the image unbiased: a
/// uniformly bright sky through the double Gauss at f/2 renders as the
/// still focused there does, over the whole film and in its vignetted
/// corners, within 0.5% (seen: 0.04% and 0.16%).
#[test]
fn shared_pupil_bounds_keep_the_image() {
    let json = r#"{"camera": {"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                              "f_number": 2, "focus_distance": 10, "sensor_mm": [36, 24]},
                   "film": {"width": 48, "height": 32, "spp": 256, "spectral": "off"},
                   "background": {"type": "constant", "radiance": [1, 1, 1]},
                   "animation": {"frames": 3, "keyframes": [{"frame": 0, "focus_distance": 10}, {"frame": 2, "focus_distance": 0.6}]}}"#;
    let f = write("shared", json);
    let anim = Animation::load(&f.0, &Overrides::default(), None).unwrap();
    for (frame, focus) in [(0, "10"), (2, "0.6")] {
        let seq = render(&anim.scene(frame).unwrap(), Options { spp: 256, seed: 4 }, &|_| {}).0;
        let still_json = json.replace("\"focus_distance\": 10,", &format!("\"focus_distance\": {focus},"));
        let g = write("still", &still_json);
        let still = render(&render::Scene::load(&g.0).unwrap(), Options { spp: 256, seed: 9 }, &|_| {}).0;
        let mean = |img: &render::Image, pick: &dyn Fn(usize, usize) -> bool| {
            let (mut s, mut n) = (0.0, 0);
            for (i, p) in img.pixels.iter().enumerate() {
                if pick(i % 48, i / 48) {
                    s += p.x;
                    n += 1;
                }
            }
            s / n as f64
        };
        let all = |_: usize, _: usize| true;
        let corners = |x: usize, y: usize| !(8..40).contains(&x) && !(6..26).contains(&y);
        for (what, pick) in [("film", &all as &dyn Fn(usize, usize) -> bool), ("corners", &corners)] {
            let (a, b) = (mean(&seq, pick), mean(&still, pick));
            assert!((a - b).abs() < 5e-3 * b, "frame {frame}, {what}: sequence {a:.5}, still {b:.5}");
        }
    }
}
