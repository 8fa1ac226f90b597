//! Autofocus (`focus_on`): the focus found by tracing the scene at a pixel
//! or toward a named shape, against the depth pass and the lens crate's
//! real-ray best focus.

use render::camera::Camera;
use render::passes::Passes;
use render::scene::format::SceneFile;
use render::Scene;
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

fn build(json: &str) -> Result<Scene, String> {
    let file: SceneFile = serde_json::from_str(json).map_err(|e| e.to_string())?;
    Scene::build(file, &data(), "<test>").map_err(|e| e.to_string())
}

/// Three spheres at 1.5, 3 and 6 m (the middle one named "ball", 0.3 m
/// off the axis) on a far wall, seen by `camera`.
fn scene(camera: &str) -> String {
    format!(
        r#"{{"camera": {camera},
            "film": {{"width": 64, "height": 48, "spp": 16, "spectral": "off"}},
            "materials": {{"d": {{"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
                           "l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [-0.2, 0, 1.5], "radius": 0.1, "material": "d"}},
                       {{"type": "sphere", "center": [0.3, 0, 3], "radius": 0.2, "material": "d", "name": "ball"}},
                       {{"type": "sphere", "center": [0, 0.3, 6], "radius": 0.3, "material": "d", "name": "far"}},
                       {{"type": "sphere", "center": [0, 0, 2], "radius": 0.0005, "material": "l", "name": "lamp"}},
                       {{"type": "plane", "point": [0, 0, 20], "normal": [0, 0, -1], "material": "d", "name": "wall"}}]}}"#
    )
}

const THIN: &str = r#"{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30,
                        "focal_length_mm": 50, "f_number": 2, "focus_on": FOCUS}"#;
const REAL: &str = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                        "f_number": 2, "sensor_mm": [36, 27], "focus_on": FOCUS}"#;

fn with(camera: &str, focus: &str) -> String {
    scene(&camera.replace("FOCUS", focus))
}

/// A thin lens focused on a pixel is focused at that pixel's depth (the
/// depth pass there; the film at the image distance, so focus_distance is
/// depth + image distance), and its CoC there is 0; on a named sphere, at
/// the depth of its near surface toward its centre.
#[test]
fn thin_lens_focuses_where_the_pixel_looks() {
    let s = build(&with(THIN, "[20, 24]")).unwrap();
    let p = Passes::of(&s).unwrap();
    let i = 24 * 64 + 20;
    let Camera::ThinLens { focus, .. } = s.camera else { panic!() };
    assert!((focus - p.depth[i]).abs() < 1e-9 * focus, "focus {focus} m, depth there {} m", p.depth[i]);
    assert!(p.coc[i] < 1e-6, "CoC {} px at the pixel focused on", p.coc[i]);
    assert!(s.camera_summary.contains("autofocus on pixel (20, 24)"), "{}", s.camera_summary);
    let s = build(&with(THIN, r#""ball""#)).unwrap();
    let Camera::ThinLens { focus, .. } = s.camera else { panic!() };
    // the ray toward (0.3, 0, 3) meets the sphere 0.2 m before its centre
    let c = glam::DVec3::new(0.3, 0.0, 3.0);
    let near = c - c.normalize() * 0.2;
    assert!((focus - near.z).abs() < 1e-12, "focus {focus} m, the ball's near side at {} m", near.z);
}

/// A real lens focused on a pixel: its film is the lens crate's real-ray
/// best focus (`lens::analysis::focus`) of a point at the depth the chief
/// ray of that pixel meets, to 1e-9 mm; the depth pass there equals that
/// depth.
#[test]
fn real_lens_film_is_the_real_ray_best_focus_of_the_pixel() {
    let s = build(&with(REAL, "[46, 24]")).unwrap();
    let p = Passes::of(&s).unwrap();
    let Camera::Real(real) = &s.camera else { panic!() };
    let depth = p.depth[24 * 64 + 46];
    // image right is -x (the camera looks along +z, up +y): the near sphere
    assert!(depth > 1.35 && depth < 1.45, "the pixel sees the near sphere: {depth} m");
    let lens = real.prescription();
    let film = lens.film_distance();
    let object = depth * 1e3 - lens.last_vertex_z() - film;
    let best = lens::analysis::focus::focus(lens, lens::paraxial::ObjectDistance::Finite(object)).unwrap();
    assert!(
        (best.best_focus_film_distance - film).abs() < 1e-9,
        "film {film} mm, best focus {} mm (paraxial {})",
        best.best_focus_film_distance,
        best.film_distance
    );
    assert!((best.film_distance - film).abs() > 1e-3, "the real-ray focus differs from the paraxial");
}

/// Bad targets are named before anything is rendered.
#[test]
fn bad_targets_say_what_to_change() {
    let e = build(&with(THIN, r#""nothing""#)).unwrap_err();
    assert!(
        e.contains("camera.focus_on") && e.contains("no shape is named \"nothing\" (named: ball, far, lamp, wall)"),
        "{e}"
    );
    let e = build(&with(THIN, "[64, 10]")).unwrap_err();
    assert!(e.contains("pixel (64, 10) is outside the 64 x 48 film"), "{e}");
    let no_wall = |s: String| {
        s.replace(
            r#"{"type": "plane", "point": [0, 0, 20], "normal": [0, 0, -1], "material": "d", "name": "wall"}"#,
            "",
        )
        .replace(",\n                       ]", "]")
    };
    let e = build(&no_wall(with(REAL, "[0, 0]"))).map(|_| ()).unwrap_err();
    assert!(e.contains("pixel (0, 0) sees the background") || e.contains("no ray from pixel (0, 0)"), "{e}");
    let both = THIN.replace("\"focus_on\"", "\"focus_distance\": 3, \"focus_on\"");
    let e = build(&with(&both, r#""ball""#)).unwrap_err();
    assert!(e.contains("give focus_distance or focus_on, not both"), "{e}");
    let neither = THIN.replace(", \"focus_on\": FOCUS", "");
    let e = build(&scene(&neither)).unwrap_err();
    assert!(e.contains("camera.focus_distance: give focus_distance (m) or focus_on"), "{e}");
    let e = build(&scene(
        r#"{"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30, "focus_on": "ball"}"#,
    ))
    .unwrap_err();
    assert!(e.contains("focus_on"), "{e}");
    let twice = scene(&THIN.replace("FOCUS", r#""ball""#)).replace(r#""name": "far""#, r#""name": "ball""#);
    let e = build(&twice).unwrap_err();
    assert!(e.contains("shapes[2].name") && e.contains("its own, non-empty name"), "{e}");
    let e = build(&with(THIN, r#""wall""#)).map(|s| s.camera_summary).unwrap();
    assert!(e.contains("autofocus on the shape \"wall\", 20 m from the lens"), "{e}");
}

/// A lens that names a focus group focuses by moving it, the film staying:
/// on a focus distance paraxially, on autofocus at the real-ray best focus
/// (the lens crate's best focus of the moved lens on the unmoved film,
/// 1e-9 mm).
#[test]
fn a_focus_group_moves_instead_of_the_film() {
    let dir = std::env::temp_dir().join(format!("lens-focus-group-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(data().join("../double-gauss-50mm.json")).unwrap();
    let mut spec: serde_json::Value = serde_json::from_str(&text).unwrap();
    spec["focus_group"] = serde_json::json!([3, 5]);
    let lens_path = dir.join("dg.json");
    std::fs::write(&lens_path, spec.to_string()).unwrap();
    let designed = lens::Prescription::load(&lens_path).unwrap();
    let camera = |focus: &str| {
        format!(
            r#"{{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "{}",
                "sensor_mm": [36, 27], {focus}}}"#,
            lens_path.display()
        )
    };
    for focus in [r#""focus_distance": 2"#, r#""focus_on": "ball""#] {
        let s = build(&scene(&camera(focus))).unwrap();
        let Camera::Real(real) = &s.camera else { panic!() };
        let p = real.prescription();
        assert_eq!(p.film_distance(), designed.film_distance(), "{focus}: the film stays");
        assert!((p.total_track() - designed.total_track()).abs() < 1e-12);
        let moved = p.surfaces()[1].thickness - designed.surfaces()[1].thickness;
        assert!(moved > 1.0, "{focus}: the group moved {moved} mm");
        if focus.contains("focus_on") {
            let c = glam::DVec3::new(0.3, 0.0, 3.0);
            let depth = (c - c.normalize() * 0.2).z;
            let object = depth * 1e3 - p.total_track();
            let best = lens::analysis::focus::focus(p, lens::paraxial::ObjectDistance::Finite(object)).unwrap();
            assert!((best.best_focus_film_distance - p.film_distance()).abs() < 1e-9);
            assert!(s.camera_summary.contains("focus group moved"), "{}", s.camera_summary);
        } else {
            let object = 2000.0 - p.total_track();
            let image = lens::paraxial::film_distance(p, lens::paraxial::ObjectDistance::Finite(object)).unwrap();
            assert!((image - p.film_distance()).abs() < 1e-9);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
