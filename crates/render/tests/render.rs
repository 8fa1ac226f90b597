//! Renders with known answers.

mod common;
use common::disk_diameter;
use glam::DVec3;
use render::scene::format::SceneFile;
use render::{render, Image, Options, Scene};
use std::path::Path;

fn scene(json: &str) -> Scene {
    let file: SceneFile = serde_json::from_str(json).unwrap();
    Scene::build(file, Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes").as_path(), "<test>")
        .unwrap()
}

fn run(s: &Scene, spp: u32) -> Image {
    render(s, Options { spp, seed: 7 }, &|_| {}).0
}

#[test]
fn white_furnace_returns_the_environment() {
    for albedo in [1.0, 0.5] {
        let s = scene(&format!(
            r#"{{"camera": {{"type": "pinhole", "position": [0,0,-3], "look_at": [0,0,0], "fov_deg": 40}},
                "film": {{"width": 24, "height": 24, "spp": 4}},
                "background": {{"type": "constant", "radiance": [1, 1, 1]}},
                "materials": {{"m": {{"type": "diffuse", "color": [{albedo}, {albedo}, {albedo}]}}}},
                "shapes": [{{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}}]}}"#
        ));
        let img = run(&s, 16);
        let centre = img.pixels[12 * 24 + 12];
        assert!((centre - DVec3::splat(albedo)).abs().max_element() < 0.01 * albedo, "{centre}");
        for p in &img.pixels {
            // every pixel is the environment (1) or the sphere's albedo x 1
            let ok = (p.x - 1.0).abs() < 0.01 || (p.x - albedo).abs() < 0.01 * albedo || (albedo..=1.0).contains(&p.x);
            assert!(ok && (p.x - p.y).abs() < 1e-12, "{p}");
        }
        if albedo == 1.0 {
            assert!(img.pixels.iter().all(|p| (p.x - 1.0).abs() < 0.01), "the white furnace is uniform");
        }
    }
}

const STUDY: &str = r#""film": {"width": 48, "height": 32, "spp": 4},
    "background": {"type": "sky", "horizon": [0.6, 0.6, 0.7], "zenith": [0.1, 0.2, 0.5]},
    "materials": {"g": {"type": "checker", "a": [0.8,0.8,0.8], "b": [0.1,0.1,0.1], "scale": 1},
                  "r": {"type": "diffuse", "color": [0.8, 0.2, 0.1]},
                  "l": {"type": "emissive", "radiance": [20, 20, 20]}},
    "shapes": [{"type": "plane", "point": [0,0,0], "normal": [0,1,0], "material": "g"},
               {"type": "sphere", "center": [0, 0.5, 5], "radius": 0.5, "material": "r"},
               {"type": "sphere", "center": [1, 2, 9], "radius": 0.1, "material": "l"}]"#;

#[test]
fn thin_lens_with_aperture_zero_is_the_pinhole() {
    let pose = r#""position": [0, 1, -1], "look_at": [0, 0.5, 5], "fov_deg": 40"#;
    let pin = scene(&format!(r#"{{"camera": {{"type": "pinhole", {pose}}}, {STUDY}}}"#));
    let thin = scene(&format!(
        r#"{{"camera": {{"type": "thin_lens", {pose}, "aperture": 0, "focus_distance": 6}}, {STUDY}}}"#
    ));
    assert_eq!(run(&pin, 4), run(&thin, 4));
}

#[test]
fn renders_are_deterministic_across_thread_counts() {
    let s = scene(&format!(
        r#"{{"camera": {{"type": "thin_lens", "position": [0,1,-1], "look_at": [0,0.5,5], "fov_deg": 40, "aperture": 0.2, "focus_distance": 6}}, {STUDY}}}"#
    ));
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| run(&s, 4));
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(|| run(&s, 4));
    assert_eq!(one, two);
}

#[test]
fn thin_lens_point_light_blurs_into_the_thin_lens_circle_of_confusion() {
    // A small lamp at 4 m, focus at 6 m, aperture 0.2 m: on the focal plane
    // the blur is A |S2 - F| / S2 = 0.1 m across.
    let (s2, f, a, r) = (4.0, 6.0, 0.2, 0.01);
    let s = scene(&format!(
        r#"{{"camera": {{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 3, "aperture": {a}, "focus_distance": {f}}},
            "film": {{"width": 160, "height": 160, "spp": 64}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [0, 0, {s2}], "radius": {r}, "material": "l"}}]}}"#
    ));
    let img = run(&s, 64);
    let px_per_m = 160.0 / (2.0 * f * (1.5f64.to_radians()).tan());
    let expected = a * (s2 - f).abs() / s2 * px_per_m;
    // the lamp itself seen through the focal plane: 2 r F / S2
    let lamp = 2.0 * r * f / s2 * px_per_m;
    let measured = disk_diameter(&img, lamp);
    assert!((measured - expected).abs() < 2.0, "disk {measured:.2} px vs thin-lens {expected:.2} px");
}

#[cfg(feature = "exr")]
#[test]
fn exr_round_trips() {
    let s = scene(&format!(
        r#"{{"camera": {{"type": "pinhole", "position": [0,1,-1], "look_at": [0,0.5,5], "fov_deg": 40}}, {STUDY}}}"#
    ));
    let img = run(&s, 2);
    let path = std::env::temp_dir().join(format!("render-roundtrip-{}.exr", std::process::id()));
    img.save(&path, 1.0).unwrap();
    let back = Image::load_exr(&path).unwrap();
    assert_eq!((back.width, back.height), (img.width, img.height));
    for (a, b) in img.pixels.iter().zip(&back.pixels) {
        // stored as f32
        assert!((*a - *b).abs().max_element() <= 1e-6 * a.abs().max_element().max(1.0), "{a} vs {b}");
    }
}

#[test]
fn bad_scenes_get_errors_naming_the_field() {
    let cases = [
        (r#""shapes": [{"type": "sphere", "center": [0,0,0], "radius": -1, "material": "m"}]"#, "shapes[0].radius"),
        (r#""shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "nope"}]"#, "shapes[0].material"),
        (r#""shapes": [{"type": "mesh", "obj": "missing.obj", "material": "m"}]"#, "shapes[0].obj"),
    ];
    for (shapes, field) in cases {
        let json = format!(
            r#"{{"camera": {{"type": "pinhole", "position": [0,0,-3], "look_at": [0,0,0], "fov_deg": 40}},
                "film": {{"width": 8, "height": 8}}, "materials": {{"m": {{"type": "diffuse", "color": [1,1,1]}}}}, {shapes}}}"#
        );
        let file: SceneFile = serde_json::from_str(&json).unwrap();
        let e = Scene::build(file, Path::new("."), "t.json").unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
    let e = serde_json::from_str::<SceneFile>(r#"{"camera": {"type": "pinhole", "fov": 40}}"#).unwrap_err().to_string();
    assert!(e.contains("unknown field `fov`"), "{e}");
}

#[cfg(feature = "exr")]
#[test]
fn environment_map_is_seen_by_the_camera_and_lights_a_furnace() {
    // a 64 x 32 equirectangular map: 0.7 everywhere, 3.0 in the 2 x 2 texels
    // around +z at the horizon (the image centre)
    let (w, h) = (64, 32);
    let mut px = vec![DVec3::splat(0.7); w * h];
    for (y, x) in [(h / 2 - 1, w / 2 - 1), (h / 2 - 1, w / 2), (h / 2, w / 2 - 1), (h / 2, w / 2)] {
        px[y * w + x] = DVec3::splat(3.0);
    }
    let env = Image { width: w, height: h, pixels: px };
    let dir = std::env::temp_dir().join(format!("render-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    env.save(&dir.join("env.exr"), 1.0).unwrap();
    let json = r#"{"camera": {"type": "pinhole", "position": [0,0,-3], "look_at": [0,0,0], "fov_deg": 40},
        "film": {"width": 16, "height": 16, "spp": 4},
        "background": {"type": "environment", "exr": "env.exr", "intensity": 2.0},
        "materials": {"m": {"type": "diffuse", "color": [1, 1, 1]}},
        "shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}]}"#;
    let s = Scene::build(serde_json::from_str(json).unwrap(), &dir, "<env>").unwrap();
    let img = run(&s, 64);
    // a white diffuse sphere in a (nearly) uniform environment of 1.4
    let corner = img.pixels[0];
    assert!((corner.x - 1.4).abs() < 1e-6, "{corner}"); // stored as f32
    let centre = img.pixels[8 * 16 + 8];
    assert!((centre.x - 1.4).abs() < 0.05, "{centre}");
    // looking straight at the bright texel
    let json2 = json
        .replace(
            r#""shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"}]"#,
            r#""shapes": []"#,
        )
        .replace(r#""fov_deg": 40"#, r#""fov_deg": 1"#);
    let s2 = Scene::build(serde_json::from_str(&json2).unwrap(), &dir, "<env>").unwrap();
    let img2 = run(&s2, 1);
    assert!((img2.pixels[8 * 16 + 8].x - 6.0).abs() < 1e-6, "{}", img2.pixels[8 * 16 + 8]);
    let missing = json.replace("env.exr", "nope.exr");
    let e = Scene::build(serde_json::from_str(&missing).unwrap(), &dir, "<env>").unwrap_err().to_string();
    assert!(e.contains("background.exr"), "{e}");
}

#[test]
fn aperture_masks_sample_where_they_transmit() {
    use render::camera::aperture::Mask;
    // left half transmits fully, right half a quarter
    let (w, h) = (8, 4);
    let values = (0..w * h).map(|i| if i % w < w / 2 { 1.0 } else { 0.25 }).collect();
    let m = Mask::new(w, h, values).unwrap();
    let n = 4000;
    let left = (0..n).filter(|k| m.sample(((*k as f64 + 0.5) / n as f64, 0.5)).0 < 0.0).count() as f64 / n as f64;
    assert!((left - 0.8).abs() < 0.01, "{left}");
    assert!(Mask::new(2, 2, vec![0.0; 4]).is_err());
    // the shipped star renders: a bokeh scene with a mask builds
    let _ = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes/bokeh-thin-star.json"))
        .unwrap();
}

#[test]
fn boxes_and_obj_meshes_are_hit() {
    let dir = std::env::temp_dir().join(format!("render-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // a unit square facing -z at z = 2, as a quad face of two triangles
    std::fs::write(dir.join("sq.obj"), "v -1 -1 2\nv 1 -1 2\nv 1 1 2\nv -1 1 2\nf 1 2 3 4\n").unwrap();
    let json = r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 20},
        "film": {"width": 8, "height": 8, "spp": 1},
        "materials": {"e": {"type": "emissive", "radiance": [2, 2, 2]}, "b": {"type": "emissive", "radiance": [5, 5, 5]}},
        "shapes": [{"type": "mesh", "obj": "sq.obj", "material": "e"},
                   {"type": "box", "min": [-10, -10, 50], "max": [10, 10, 60], "material": "b"}]}"#;
    let s = Scene::build(serde_json::from_str(json).unwrap(), &dir, "<obj>").unwrap();
    let img = run(&s, 1);
    // the mesh triangle winding faces +z (away from the camera): emission is
    // one-sided, so the camera sees its back, black; turn it around
    assert!(img.pixels.iter().all(|p| p.x == 0.0 || p.x == 2.0), "{:?}", img.pixels[27]);
    std::fs::write(dir.join("sq.obj"), "v -1 -1 2\nv 1 -1 2\nv 1 1 2\nv -1 1 2\nf 4 3 2 1\n").unwrap();
    let s = Scene::build(serde_json::from_str(json).unwrap(), &dir, "<obj>").unwrap();
    let img = run(&s, 1);
    assert!(img.pixels.iter().all(|p| (p.x - 2.0).abs() < 1e-12), "{:?}", img.pixels[27]);
    // without the mesh the camera sees the box's front face (emitting outward)
    let no_mesh = json.replace(r#"{"type": "mesh", "obj": "sq.obj", "material": "e"},"#, "");
    let s = Scene::build(serde_json::from_str(&no_mesh).unwrap(), &dir, "<obj>").unwrap();
    assert!(run(&s, 1).pixels.iter().all(|p| (p.x - 5.0).abs() < 1e-12));
    std::fs::write(dir.join("bad.obj"), "v 0 0\n").unwrap();
    let bad = json.replace("sq.obj", "bad.obj");
    let e = Scene::build(serde_json::from_str(&bad).unwrap(), &dir, "<obj>").unwrap_err().to_string();
    assert!(e.contains("shapes[0].obj") && e.contains("line 1"), "{e}");
}

#[test]
fn thin_lens_focus_distance_with_a_focal_length_is_from_the_film() {
    let json = |f: &str| {
        format!(
            r#"{{"camera": {{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 20,
               "f_number": 2, "focal_length_mm": 50, "focus_distance": {f}}},
               "film": {{"width": 4, "height": 4}}}}"#
        )
    };
    let s = scene(&json("2.0"));
    let render::camera::Camera::ThinLens { focus, radius, .. } = s.camera else { panic!() };
    // s + s' = 2 m with 1/s + 1/s' = 1/0.05
    let s_img = 2.0 - focus;
    assert!((1.0 / focus + 1.0 / s_img - 20.0).abs() < 1e-9, "{focus}");
    assert!((radius - 0.0125).abs() < 1e-15);
    let file: SceneFile = serde_json::from_str(&json("0.1")).unwrap();
    let e = Scene::build(file, Path::new("."), "t").unwrap_err().to_string();
    assert!(e.contains("camera.focus_distance"), "{e}");
}

#[test]
fn an_emissive_plane_lights_diffuse_surfaces_through_bounces() {
    // a diffuse white floor under an emissive ceiling plane (radiance 1) and
    // nothing else: looking down at the floor, every path ends on the
    // ceiling after one bounce, so the floor's radiance is albedo x 1.
    let s = scene(
        r#"{"camera": {"type": "pinhole", "position": [0,1,0], "look_at": [0,0,0.001], "fov_deg": 30},
            "film": {"width": 8, "height": 8, "spp": 64},
            "materials": {"w": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}, "e": {"type": "emissive", "radiance": [1, 1, 1]}},
            "shapes": [{"type": "plane", "point": [0,0,0], "normal": [0,1,0], "material": "w"},
                       {"type": "plane", "point": [0,2,0], "normal": [0,-1,0], "material": "e"}]}"#,
    );
    let img = run(&s, 64);
    for p in &img.pixels {
        assert!((p.x - 0.5).abs() < 1e-9, "{p}");
    }
}

/// A grey floor inside a box whose other five faces all emit: the floor
/// sees light over its whole hemisphere, so its radiance is albedo times
/// the walls' radiance exactly. Light sampling and the emitters that BSDF
/// sampling finds are weighted against each other (MIS); the weights must
/// sum to one, or the floor comes out too dark or too bright.
#[test]
fn light_sampling_and_bsdf_sampling_add_up_to_the_emitted_light() {
    let s = scene(
        r#"{"camera": {"type": "pinhole", "position": [0, 0.9, 0], "look_at": [0, 0, 0.01], "fov_deg": 40},
            "film": {"width": 24, "height": 24, "spp": 64},
            "materials": {"floor": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
                          "wall": {"type": "emissive", "radiance": [2, 2, 2]}},
            "shapes": [
              {"type": "quad", "corner": [-1, 0, -1], "u": [0, 0, 2], "v": [2, 0, 0], "material": "floor"},
              {"type": "quad", "corner": [-1, 1, -1], "u": [2, 0, 0], "v": [0, 0, 2], "material": "wall"},
              {"type": "quad", "corner": [-1, 0, -1], "u": [0, 1, 0], "v": [0, 0, 2], "material": "wall"},
              {"type": "quad", "corner": [1, 0, -1], "u": [0, 0, 2], "v": [0, 1, 0], "material": "wall"},
              {"type": "quad", "corner": [-1, 0, -1], "u": [2, 0, 0], "v": [0, 1, 0], "material": "wall"},
              {"type": "quad", "corner": [-1, 0, 1], "u": [0, 1, 0], "v": [2, 0, 0], "material": "wall"}]}"#,
    );
    let (img, _) = render(&s, Options { spp: 256, seed: 9 }, &|_| {});
    let mean = img.pixels.iter().map(|p| p.x).sum::<f64>() / img.pixels.len() as f64;
    assert!((mean - 1.0).abs() < 0.01, "floor radiance {mean}, expected 0.5 x 2 = 1");
}

/// Aiming a share of a thin lens's samples at the lamps changes the noise,
/// not the picture: defocused lamps through a wide aperture come out with
/// the same light, disc by disc, as with uniform aperture samples only (a
/// focus shift of 1e-12, which no picture can show, turns aiming off).
#[test]
fn aiming_at_lamps_through_the_aperture_is_unbiased() {
    let json = |shift: f64| {
        format!(
            r#"{{"camera": {{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 30,
                             "aperture": 0.3, "focus_distance": 3, "focus_shift": {shift}}},
                "film": {{"width": 48, "height": 32, "spp": 16}},
                "background": {{"type": "constant", "radiance": [0.01, 0.01, 0.01]}},
                "materials": {{"lamp": {{"type": "emissive", "radiance": [50, 40, 30]}}}},
                "shapes": [{{"type": "sphere", "center": [-1, 0.3, 12], "radius": 0.08, "material": "lamp"}},
                           {{"type": "sphere", "center": [1.2, -0.4, 9], "radius": 0.05, "material": "lamp"}},
                           {{"type": "sphere", "center": [0.2, 0.2, 1.5], "radius": 0.02, "material": "lamp"}}]}}"#
        )
    };
    let aimed = scene(&json(0.0));
    let plain = scene(&json(1e-12));
    let render::camera::Camera::ThinLens { lamps, .. } = &aimed.camera else { panic!() };
    assert!(lamps.share > 0.0, "aiming is on");
    let render::camera::Camera::ThinLens { lamps, .. } = &plain.camera else { panic!() };
    assert_eq!(lamps.share, 0.0, "aiming is off");
    let (a, _) = render(&aimed, Options { spp: 256, seed: 1 }, &|_| {});
    let (b, _) = render(&plain, Options { spp: 4096, seed: 2 }, &|_| {});
    let total = |img: &Image| img.pixels.iter().map(|p| p.x).sum::<f64>();
    let (ta, tb) = (total(&a), total(&b));
    assert!((ta / tb - 1.0).abs() < 0.02, "total light: aimed {ta:.2}, uniform {tb:.2}");
    // and quadrant by quadrant (each lamp's disc in its own)
    let quadrant = |img: &Image, qx: usize, qy: usize| {
        let mut s = 0.0;
        for y in qy * 16..qy * 16 + 16 {
            for x in qx * 24..qx * 24 + 24 {
                s += img.pixels[y * 48 + x].x;
            }
        }
        s
    };
    for qy in 0..2 {
        for qx in 0..2 {
            let (qa, qb) = (quadrant(&a, qx, qy), quadrant(&b, qx, qy));
            assert!((qa - qb).abs() <= 0.03 * qb.max(0.05 * tb), "quadrant {qx},{qy}: {qa:.2} vs {qb:.2}");
        }
    }
}

/// An environment image is light-sampled and found by BSDF sampling, the
/// two weighted (MIS): a white diffuse sphere under a uniform environment
/// is the environment's radiance exactly (a furnace), which fails if the
/// weights do not sum to one.
#[test]
fn an_environment_is_light_sampled_without_bias() {
    let d = std::env::temp_dir().join(format!("lens-env-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let uniform = Image { width: 16, height: 8, pixels: vec![DVec3::splat(0.7); 128] };
    uniform.save(&d.join("uniform.exr"), 1.0).unwrap();
    let s = scene(&format!(
        r#"{{"camera": {{"type": "pinhole", "position": [0, 0, -3], "look_at": [0, 0, 0], "fov_deg": 30}},
            "film": {{"width": 16, "height": 16, "spp": 64}},
            "background": {{"type": "environment", "exr": "{}"}},
            "materials": {{"white": {{"type": "diffuse", "color": [1, 1, 1]}}}},
            "shapes": [{{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}}]}}"#,
        d.join("uniform.exr").display()
    ));
    assert!(s.env_sampler.is_some());
    let (img, _) = render(&s, Options { spp: 128, seed: 3 }, &|_| {});
    let mean = img.pixels.iter().map(|p| p.x).sum::<f64>() / img.pixels.len() as f64;
    assert!((mean - 0.7).abs() < 0.007, "furnace {mean}, expected 0.7");
    std::fs::remove_dir_all(&d).unwrap();
}
