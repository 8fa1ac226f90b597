//! The render passes (depth, position, normal, circle of confusion) against
//! analytic values and the lens crate's own analyses.

mod common;
use common::disk_diameter;
use glam::DVec3;
use render::passes::{Pass, Passes};
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

/// A plane through (0, 0, 4) with normal `n` (facing the camera), seen by
/// `camera` on a `w` x `h` film.
fn plane_scene(camera: &str, n: DVec3, w: usize, h: usize) -> Scene {
    scene(&format!(
        r#"{{"camera": {camera},
            "film": {{"width": {w}, "height": {h}, "spp": 1, "spectral": "off"}},
            "materials": {{"d": {{"type": "diffuse", "color": [0.5, 0.5, 0.5]}}}},
            "shapes": [{{"type": "plane", "point": [0, 0, 4], "normal": [{}, {}, {}], "material": "d"}}]}}"#,
        n.x, n.y, n.z
    ))
}

/// Through a pinhole and a thin lens, a tilted plane's depth, position and
/// normal in every pixel equal the analytic intersection of the pixel
/// centre's ray with the plane (the ray through the lens centre).
#[test]
fn depth_of_a_tilted_plane_is_the_analytic_distance() {
    let n = DVec3::new(0.2, 0.3, -1.0).normalize();
    let (w, h) = (48, 32);
    let tan_half = (30f64.to_radians() / 2.0).tan();
    for camera in [
        r#"{"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30}"#,
        r#"{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30, "aperture": 0.02,
            "focus_distance": 3}"#,
    ] {
        let s = plane_scene(camera, n, w, h);
        let p = Passes::of(&s).unwrap();
        let mut worst: f64 = 0.0;
        for y in 0..h {
            for x in 0..w {
                let (u, v) = ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
                // the camera looks along +z with up +y, so image right is -x
                let d = DVec3::new(-(2.0 * u - 1.0) * tan_half * w as f64 / h as f64, (1.0 - 2.0 * v) * tan_half, 1.0)
                    .normalize();
                let t = DVec3::new(0.0, 0.0, 4.0).dot(n) / d.dot(n);
                let (z, point) = (t * d.z, d * t);
                let i = y * w + x;
                worst = worst.max((p.depth[i] - z).abs());
                assert!((p.position[i] - point).length() < 1e-9, "{camera}: P at ({x}, {y})");
                assert!((p.normal[i] - n).length() < 1e-12, "{camera}: N at ({x}, {y})");
            }
        }
        assert!(worst < 1e-9, "{camera}: depth off by {worst:e} m");
    }
}

/// Through real lenses (the double Gauss; the 22 mm wide angle, whose
/// chief rays are bent far from the pinhole's by its distortion) a plane
/// square to the axis has the same depth in every pixel, its distance from
/// the film, to 1e-4 m (the issue's bound; seen: 1e-12), and every pixel's
/// chief ray meets it.
#[test]
fn real_lens_depth_of_a_plane_is_its_distance() {
    for (lens, sensor) in [("../double-gauss-50mm.json", "[36, 24]"), ("../wide-angle-22mm.json", "[36, 24]")] {
        let cam = format!(
            r#"{{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "{lens}",
                "focus_distance": 3.0, "sensor_mm": {sensor}}}"#
        );
        let s = plane_scene(&cam, DVec3::new(0.0, 0.0, -1.0), 36, 24);
        let p = Passes::of(&s).unwrap();
        let worst = p.depth.iter().map(|z| (z - 4.0).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-4, "{lens}: depth off by {worst:e} m");
        assert!(p.position.iter().all(|q| (q.z - 4.0).abs() < 1e-4), "{lens}: P on the plane");
        // the corner pixel looks farther off axis through the wide angle's
        // chief ray than a pinhole of the same focal length would: the
        // pass follows the lens, not a model of it
        let corner = p.position[0];
        assert!(corner.x.abs() > 0.1 && corner.y.abs() > 0.1, "{lens}: corner at {corner}");
    }
}

/// The real lens's CoC pass over a tilted plane (depths 2.7 to 7.7 m, the
/// focus 3 m among them) equals the lens crate's circle of confusion at
/// each pixel's own depth to 0.5% (the table's interpolation in 1 / depth),
/// least near the focus.
#[test]
fn real_lens_coc_pass_is_the_lens_blur_at_each_depth() {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                 "f_number": 2, "focus_distance": 3.0, "sensor_mm": [36, 24]}"#;
    let s = plane_scene(cam, DVec3::new(0.0, 2.0, -1.0).normalize(), 36, 24);
    let p = Passes::of(&s).unwrap();
    let render::camera::Camera::Real(real) = &s.camera else { panic!() };
    let lens = real.prescription();
    let track = lens.total_track();
    let per_px = 36.0 / 36.0;
    let (lo, hi) = p.depth.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &z| (a.min(z), b.max(z)));
    assert!(lo < 3.0 && hi > 6.0, "depths {lo}..{hi}");
    let focus_object = (real.focus_distance_m() * 1e3) - track;
    assert!((real.focus_distance_m() - 3.0).abs() < 1e-9);
    for i in (0..p.depth.len()).step_by(7) {
        let z = p.depth[i];
        let table = lens::analysis::coc::circle_of_confusion(lens, focus_object, &[z * 1e3 - track]).unwrap();
        let want = table.rows[0].geo_diameter / per_px;
        let rel = (p.coc[i] - want).abs() / want;
        assert!(rel < 5e-3, "pixel {i} at {z} m: CoC {} px, the lens's blur {want} px", p.coc[i]);
    }
    let least = p.depth.iter().zip(&p.coc).min_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    // near the focus, a little beyond: the full blur of a lens with
    // spherical aberration is least short of the paraxial image
    assert!(*least.0 > 2.9 && *least.0 < 3.5, "least blur at {} m", least.0);
}

/// Through a thin lens the CoC pass is the diameter of the disc a
/// defocused point lamp renders to (a 1 mm lamp 1 m away, the lens focused
/// at 3 m): within 3%.
#[test]
fn thin_lens_coc_pass_is_the_rendered_disc() {
    let s = scene(
        r#"{"camera": {"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 10,
                       "aperture": 0.05, "focus_distance": 3},
            "film": {"width": 65, "height": 65, "spp": 256, "spectral": "off"},
            "materials": {"l": {"type": "emissive", "radiance": [1000, 1000, 1000]},
                          "d": {"type": "diffuse", "color": [0, 0, 0]}},
            "shapes": [{"type": "sphere", "center": [0, 0, 1], "radius": 0.0005, "material": "l"}]}"#,
    );
    let p = Passes::of(&s).unwrap();
    let centre = 32 * 65 + 32;
    assert!((p.depth[centre] - 0.9995).abs() < 1e-9, "{}", p.depth[centre]);
    let coc = p.coc[centre];
    let (img, _) = render(&s, Options { spp: 256, seed: 5 }, &|_| {});
    // the lamp's own image (1 mm at 1 m) and the pixels' box, removed
    let per_tan = 65.0 / (2.0 * (5f64.to_radians()).tan());
    let own = 2.0 * 0.0005 / 1.0 * per_tan;
    let disc = disk_diameter(&img, (own * own + 8.0 / 6.0).sqrt());
    assert!((disc - coc).abs() / coc < 0.03, "rendered disc {disc:.3} px, CoC pass {coc:.3} px");
}

/// The pass list parses names once each, `all`, and refuses an unknown
/// name saying which are known; the EXR holds the named channels.
#[test]
fn pass_names_and_exr_channels() {
    assert_eq!(Pass::parse_list("depth, coc,depth").unwrap(), vec![Pass::Depth, Pass::Coc]);
    assert_eq!(Pass::parse_list("all").unwrap(), Pass::ALL.to_vec());
    let e = Pass::parse_list("depth,alpha").unwrap_err();
    assert!(e.contains("\"alpha\"") && e.contains("depth, position, normal, coc"), "{e}");
    let s = plane_scene(
        r#"{"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30}"#,
        DVec3::new(0.0, 0.0, -1.0),
        8,
        6,
    );
    let p = Passes::of(&s).unwrap();
    let (img, _) = render(&s, Options { spp: 1, seed: 1 }, &|_| {});
    let dir = std::env::temp_dir().join(format!("lens-passes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.exr");
    img.save_exr_with(&path, &p.channels(&Pass::ALL)).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    let names: Vec<String> = meta.headers[0].channels.list.iter().map(|c| c.name.to_string()).collect();
    for c in ["R", "G", "B", "Z", "P.x", "P.y", "P.z", "N.x", "N.y", "N.z", "CoC"] {
        assert!(names.iter().any(|n| n == c), "{c} missing from {names:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
