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

/// A small white lamp seen through `camera`, rendered in RGB: these tests
/// check the lens's geometry at its primary wavelength (the spectral tests
/// are in spectral.rs).
fn lamp_scene(camera: &str, lamp: DVec3, radius: f64, size: usize) -> Scene {
    scene(&format!(
        r#"{{"camera": {camera},
            "film": {{"width": {size}, "height": {size}, "spp": 64, "spectral": "off"}},
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

/// The exit-pupil bounds contain every ray that passes: the camera's mean
/// weight at film points across the frame (relative to the centre) equals
/// a brute-force integral of cos^4 / d^2 over a dense grid of the whole rear
/// vertex plane, traced ray by ray; for the round stop (star-shaped and
/// cell bounds) and for a shaped stop (the stop's shape mapped back); for
/// the double Gauss and for the phone lens, whose eight surfaces are
/// aspheres (odd terms to r^10, conics to k = -222).
#[test]
fn pupil_bounds_lose_no_light() {
    const DG: (&str, [f64; 2], f64, f64) = ("../double-gauss-50mm.json", [36.0, 24.0], 30.0, 0.85);
    // the phone lens's last surface is 0.57 mm from the film: its bundles
    // there are a few tenths of a mm across, so the grid is that small
    const PHONE: (&str, [f64; 2], f64, f64) = ("../library/phone-5.6mm-f3.5-us7535658.json", [4.0, 3.0], 0.45, 0.3);
    // the aspheric cine prime wide open: its rear group clips the corner bundles
    const PRIME: (&str, [f64; 2], f64, f64) =
        ("../library/master-prime-100mm-t1.3-us20070236805.json", [36.0, 24.0], 30.0, 2.0);
    // the aspheric 35 mm wide open, its asphere on the rear group
    const WIDE: (&str, [f64; 2], f64, f64) =
        ("../library/canon-35mm-f2-is-aspheric-us20150205081.json", [36.0, 24.0], 30.0, 3.6);
    for ((lens_file, sensor, half, focus), fno, shape, blades) in [
        (DG, 2.0, r#"{"shape": "circle"}"#, 0),
        (DG, 8.0, r#"{"shape": "circle"}"#, 0),
        (DG, 2.8, r#"{"shape": "polygon", "blades": 6}"#, 6),
        (DG, 2.0, r#"{"shape": "polygon", "blades": 3, "rotation_deg": 90}"#, 3),
        (PHONE, 3.5, r#"{"shape": "circle"}"#, 0),
        (PHONE, 4.0, r#"{"shape": "polygon", "blades": 6}"#, 6),
        (PRIME, 1.24, r#"{"shape": "circle"}"#, 0),
        (WIDE, 2.05, r#"{"shape": "polygon", "blades": 6}"#, 6),
    ] {
        let cam = format!(
            r#"{{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "{lens_file}",
                 "f_number": {fno}, "focus_distance": {focus}, "sensor_mm": [{}, {}], "aperture_shape": {shape}}}"#,
            sensor[0], sensor[1]
        );
        let s = lamp_scene(&cam, DVec3::new(0.0, 0.0, 5.0), 0.01, 8);
        let render::camera::Camera::Real(real) = &s.camera else { panic!() };
        let p = real.prescription();
        let (z_film, z_rear) = (p.total_track(), p.last_vertex_z());
        let tracer = lens::Tracer::reverse(p);
        let stop = p.stop_index();
        let sd = p.stop_semi_diameter();
        let inside_shape = |at: Option<DVec3>| match at {
            None => false,
            Some(q) if blades > 0 => {
                let (x, y) = (q.x / sd, q.y / sd);
                let rotation = if blades == 3 { 90f64.to_radians() } else { 0.0 };
                let n = blades as f64;
                (0..blades).all(|k| {
                    let mid = rotation + std::f64::consts::TAU * (k as f64 + 0.5) / n;
                    x * mid.cos() + y * mid.sin() <= (std::f64::consts::PI / n).cos()
                })
            }
            Some(_) => true,
        };
        // grid cells across: the phone lens's bundles are small against its grid
        let n = if lens_file == PHONE.0 { 1100 } else { 600 };
        let brute = |fx: f64, fy: f64| {
            let h = 2.0 * half / n as f64;
            let film = DVec3::new(fx, fy, z_film);
            let mut sum = 0.0;
            for j in 0..n {
                for i in 0..n {
                    // a grid centred on the film point
                    let t = DVec3::new(fx - half + h * (i as f64 + 0.5), fy - half + h * (j as f64 + 0.5), z_rear);
                    let ray = lens::Ray::new(film, t - film).unwrap();
                    let (out, at) = tracer.trace_at_surface(ray, stop);
                    if out.reached().is_some() && inside_shape(at) {
                        sum += ray.direction.z.powi(4) * h * h;
                    }
                }
            }
            sum
        };
        let camera_mean = |u: f64, v: f64| {
            let n = 200_000;
            let g = 0.618_033_988_749_894_9;
            let samples: Vec<render::camera::CameraSample> = (0..n)
                .map(|k| {
                    render::camera::CameraSample::new((u, v), ((k as f64 + 0.5) / n as f64, (k as f64 * g).fract()))
                })
                .collect();
            let mut out = Vec::new();
            s.camera.rays(&samples, &mut out);
            out.iter().flatten().map(|(_, w)| w).sum::<f64>() / n as f64
        };
        let (b0, c0) = (brute(0.0, 0.0), camera_mean(0.5, 0.5));
        let d = z_film - z_rear;
        let centre = real.centre_weight() * d * d;
        assert!(
            (centre - b0).abs() < 0.005 * b0,
            "{lens_file} f/{fno} {shape}: centre {centre:.6} mm^2, brute force {b0:.6}"
        );
        for (u, v) in [(0.8, 0.5), (0.5, 0.05), (0.95, 0.9), (0.2, 0.3)] {
            let (fx, fy) = (-(u - 0.5) * sensor[0], -(0.5 - v) * sensor[1]);
            let want = brute(fx, fy) / b0;
            let got = camera_mean(u, v) / c0;
            assert!(
                (got - want).abs() < 0.01 * want.max(0.05),
                "{lens_file} f/{fno} {shape} at ({u}, {v}): camera {got:.4}, brute force {want:.4}"
            );
        }
    }
}

/// Under uniform light the real-lens camera's film falls off from the
/// centre as `lens field` says the lens's relative illumination does (the
/// light each field's bundle gathers, pupil growth and vignetting included,
/// times the image area per unit of object): the 14.42 mm end of the wide
/// zoom, whose retrofocus entrance pupil grows off the axis (at the frame's
/// edge 0.52 of the centre, where the cos^4 law would give 0.14), and the
/// double Gauss at f/2 (vignetted), within 3% of the centre's value.
#[test]
fn uniform_light_falls_off_as_the_relative_illumination() {
    use lens::analysis::curves::field_curves;
    use lens::analysis::Aim;
    for (file, fno, sensor, max_deg) in [
        ("../library/nikkor-z-14-30mm-f4-wide-jp2019008031.json", 4.0, [36.0, 20.25], 57.6),
        ("../double-gauss-50mm.json", 2.0, [36.0, 24.0], 23.0),
    ] {
        let (w, h) = (48usize, (48.0 * sensor[1] / sensor[0]) as usize);
        let s = scene(&format!(
            r#"{{"camera": {{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "{file}",
                 "f_number": {fno}, "focus_distance": 1000, "sensor_mm": [{}, {}]}},
                "film": {{"width": {w}, "height": {h}, "spp": 256, "spectral": "off"}},
                "background": {{"type": "sky", "horizon": [1, 1, 1], "zenith": [1, 1, 1], "ground": [1, 1, 1]}},
                "materials": {{}}, "shapes": []}}"#,
            sensor[0], sensor[1]
        ));
        let render::camera::Camera::Real(real) = &s.camera else { panic!() };
        let curves = field_curves(real.prescription(), Some(max_deg), 100, Aim::Real).unwrap();
        let ri_at = |r: f64| {
            let f = &curves.fields;
            let k = f.windows(2).position(|p| p[1].chief_height >= r).expect("height within the curves");
            let (a, b) = (&f[k], &f[k + 1]);
            let t = (r - a.chief_height) / (b.chief_height - a.chief_height);
            a.relative_illumination + t * (b.relative_illumination - a.relative_illumination)
        };
        let (img, _) = render(&s, Options { spp: 256, seed: 7 }, &|_| {});
        // 2 x 2 pixel blocks: the centre, the middle of the right edge and
        // of the top, the corner
        let block = |x: usize, y: usize| {
            let mut sum = 0.0;
            for (i, j) in [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)] {
                sum += img.pixels[j * w + i].y;
            }
            let (u, v) = ((x + 1) as f64 / w as f64 - 0.5, (y + 1) as f64 / h as f64 - 0.5);
            (sum / 4.0, (u * sensor[0]).hypot(v * sensor[1]))
        };
        let (centre, _) = block(w / 2 - 1, h / 2 - 1);
        for (x, y) in [(w - 2, h / 2 - 1), (w / 2 - 1, 0), (w - 2, 0)] {
            let (value, r) = block(x, y);
            let (got, want) = (value / centre, ri_at(r));
            println!("{file}: image height {r:.2} mm: film {got:.4} of the centre, relative illumination {want:.4}");
            assert!(
                (got - want).abs() < 0.03,
                "{file}: at {r} mm the film has {got} of the centre, the analysis {want}"
            );
        }
    }
}

/// A scene of lamps through the double Gauss at f/2 focused at 0.6 m, on
/// a 48 x 32 film (36 x 24 mm): `lamps` are (centre, radius) in metres;
/// `stop` is extra camera JSON (a shaped stop), `film` extra film JSON,
/// `extra` extra shapes.
fn lamps_scene_with(lamps: &[([f64; 3], f64)], stop: &str, film: &str, extra: &str) -> Scene {
    let shapes: Vec<String> = lamps
        .iter()
        .map(|(c, r)| {
            format!(
                r#"{{"type": "sphere", "center": [{}, {}, {}], "radius": {r}, "material": "lamp"}}"#,
                c[0], c[1], c[2]
            )
        })
        .collect();
    scene(&format!(
        r#"{{"camera": {{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                         "f_number": 2, "focus_distance": 0.6, "sensor_mm": [36, 24] {stop}}},
            "film": {{"width": 48, "height": 32, "spp": 16 {film}}},
            "background": {{"type": "constant", "radiance": [0.01, 0.01, 0.01]}},
            "materials": {{"lamp": {{"type": "emissive", "radiance": [50, 40, 30]}},
                           "grey": {{"type": "diffuse", "color": [0.5, 0.5, 0.5]}}}},
            "shapes": [{}{extra}]}}"#,
        shapes.join(", ")
    ))
}

fn lamps_scene(lamps: &[([f64; 3], f64)], stop: &str) -> Scene {
    lamps_scene_with(lamps, stop, "", "")
}

/// The scene with its lamps left to the camera paths alone (no light
/// traced from them).
fn camera_only(mut s: Scene) -> Scene {
    s.lamp_tracing = false;
    s
}

/// The sum of a render's pixels (all channels), averaged over `seeds`.
fn mean_total(s: &Scene, spp: u32, seeds: std::ops::Range<u64>) -> f64 {
    let n = seeds.end - seeds.start;
    seeds
        .map(|seed| render(s, Options { spp, seed }, &|_| {}).0.pixels.iter().map(|p| p.x + p.y + p.z).sum::<f64>())
        .sum::<f64>()
        / n as f64
}

/// The light of each quadrant of a 48 x 32 image (all channels).
fn quadrant(img: &render::Image, qx: usize, qy: usize) -> f64 {
    (qy * 16..qy * 16 + 16)
        .flat_map(|y| (qx * 24..qx * 24 + 24).map(move |x| (x, y)))
        .map(|(x, y)| img.pixels[y * 48 + x].element_sum())
        .sum::<f64>()
}

/// Light traced from the lamps into the real lens changes the noise, not
/// the picture: three lamps (two far behind the plane in focus, one in
/// front of it) and one half off the film, through round and hexagonal
/// stops, spectral (each wavelength through the glasses on its own), in
/// RGB and with the tent filter, one lamp half hidden behind a sphere,
/// give the same light quadrant by quadrant (within 3%) as camera paths
/// alone at eight times the samples; and the traced render is
/// much the cleaner at equal samples.
#[test]
fn light_traced_from_lamps_through_the_real_lens_is_unbiased() {
    let lamps =
        [([-1.6, 0.6, 12.0], 0.08), ([1.2, -0.5, 9.0], 0.05), ([0.05, 0.03, 0.3], 0.002), ([2.55, 0.8, 8.0], 0.05)];
    // a grey ball hiding half of the first lamp's disc
    let ball = r#", {"type": "sphere", "center": [-0.8, 0.3, 6.0], "radius": 0.05, "material": "grey"}"#;
    let hexagon = r#", "aperture_shape": {"shape": "polygon", "blades": 6, "rotation_deg": 10}"#;
    for (stop, film) in [("", ""), (hexagon, ""), ("", r#", "spectral": "off""#), (hexagon, r#", "filter": "tent""#)] {
        let traced = lamps_scene_with(&lamps, stop, film, ball);
        let model = render::camera::lamp_light::LampLight::build(&traced, 16).expect("lamps traced");
        assert_eq!(model.lamps(), &[0, 1, 2, 3], "every lamp traced");
        let plain = camera_only(lamps_scene_with(&lamps, stop, film, ball));
        let (a, _) = render(&traced, Options { spp: 512, seed: 1 }, &|_| {});
        let (b, _) = render(&plain, Options { spp: 4096, seed: 2 }, &|_| {});
        let tb: f64 = (0..4).map(|q| quadrant(&b, q % 2, q / 2)).sum();
        for qy in 0..2 {
            for qx in 0..2 {
                let (qa, qb) = (quadrant(&a, qx, qy), quadrant(&b, qx, qy));
                assert!(
                    (qa - qb).abs() <= 0.03 * qb.max(0.05 * tb),
                    "{stop}{film}: quadrant {qx},{qy}: {qa:.3} vs {qb:.3}"
                );
            }
        }
        // cleaner: at 16 spp, the traced render's error against the
        // camera-only reference is well below the camera-only render's
        let (a16, _) = render(&traced, Options { spp: 16, seed: 3 }, &|_| {});
        let (b16, _) = render(&plain, Options { spp: 16, seed: 3 }, &|_| {});
        let (ea, eb) = (a16.rmse(&b), b16.rmse(&b));
        assert!(ea < 0.5 * eb, "{stop}{film}: RMSE at 16 spp traced {ea:.4}, camera only {eb:.4}");
    }
}

/// The same for the bright parts of an environment seen out of focus: a
/// small sun (one texel, 1.4 degrees) and a larger window (6 x 4 texels)
/// on a dim sky, the sun half behind a ball, through the double Gauss
/// focused at 0.6 m (round and hexagonal stop): the sun, whose image is
/// smaller than its blur, is traced from the sky, the window (resolved)
/// left to the camera paths; together they give the light of camera
/// paths alone quadrant by quadrant (within 3%), much the cleaner.
#[test]
fn light_traced_from_a_bright_sky_through_the_real_lens_is_unbiased() {
    let (w, h) = (256, 128);
    let mut pixels = vec![DVec3::new(0.04, 0.05, 0.08); w * h];
    pixels[61 * w + 132] = DVec3::new(30000.0, 27000.0, 22000.0);
    for y in 66..70 {
        for x in 118..124 {
            pixels[y * w + x] = DVec3::new(40.0, 50.0, 60.0);
        }
    }
    let img = render::Image { width: w, height: h, pixels };
    let ball = r#", {"type": "sphere", "center": [0.53, 0.29, 5.0], "radius": 0.05, "material": "grey"}"#;
    let hexagon = r#", "aperture_shape": {"shape": "polygon", "blades": 6, "rotation_deg": 10}"#;
    let with_sky = |stop: &str, traced: bool| {
        let mut s = lamps_scene_with(&[], stop, r#", "spectral": "off""#, ball.trim_start_matches(", "));
        s.background = render::scene::Background::Environment(Box::new(img.clone()));
        s.env_sampler = render::envmap::EnvSampler::new(&img);
        s.lamp_tracing = traced;
        s
    };
    for stop in ["", hexagon] {
        let traced = with_sky(stop, true);
        let model = render::camera::lamp_light::LampLight::build(&traced, 16).expect("sky traced");
        assert_eq!(model.sky_patches(), 1, "the sun traced, the window left to camera paths");
        let plain = with_sky(stop, false);
        let (a, _) = render(&traced, Options { spp: 256, seed: 1 }, &|_| {});
        let (b, _) = render(&plain, Options { spp: 4096, seed: 2 }, &|_| {});
        let tb: f64 = (0..4).map(|q| quadrant(&b, q % 2, q / 2)).sum();
        for qy in 0..2 {
            for qx in 0..2 {
                let (qa, qb) = (quadrant(&a, qx, qy), quadrant(&b, qx, qy));
                assert!((qa - qb).abs() <= 0.03 * qb.max(0.05 * tb), "{stop}: quadrant {qx},{qy}: {qa:.3} vs {qb:.3}");
            }
        }
        let (a16, _) = render(&traced, Options { spp: 16, seed: 3 }, &|_| {});
        let (b16, _) = render(&plain, Options { spp: 16, seed: 3 }, &|_| {});
        let (ea, eb) = (a16.rmse(&b), b16.rmse(&b));
        assert!(ea < 0.5 * eb, "{stop}: RMSE at 16 spp traced {ea:.4}, camera only {eb:.4}");
    }
}

/// A defocused lamp's total light is the same, within 0.5%, traced from
/// the lamp as from the camera alone (means over eight seeds).
#[test]
fn a_traced_defocused_lamps_light_is_the_camera_paths() {
    let lamps = [([0.3, 0.2, 10.0], 0.06)];
    let traced = lamps_scene(&lamps, "");
    let plain = camera_only(lamps_scene(&lamps, ""));
    let (ta, tb) = (mean_total(&traced, 64, 0..8), mean_total(&plain, 4096, 100..108));
    assert!((ta / tb - 1.0).abs() < 0.005, "total light: traced {ta:.4}, camera only {tb:.4}");
}

/// A lens with a decentred or tilted surface is refused by the real-lens
/// camera, saying why and what to change, never rendered with bounds that
/// assume a symmetric lens.
#[test]
fn a_tilted_lens_is_refused_with_the_reason() {
    let mut spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data().join("../double-gauss-50mm.json")).unwrap()).unwrap();
    spec["surfaces"][3]["tilt_deg"] = serde_json::json!([0.5, 0.0]);
    let dir = std::env::temp_dir().join(format!("lens-tilted-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tilted.json"), spec.to_string()).unwrap();
    let file: SceneFile = serde_json::from_str(
        r#"{"camera": {"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "tilted.json",
             "focus_distance": 2.0, "sensor_mm": [2.0, 2.0]},
            "film": {"width": 8, "height": 8, "spp": 1},
            "materials": {"l": {"type": "emissive", "radiance": [1, 1, 1]}},
            "shapes": [{"type": "sphere", "center": [0, 0, 2], "radius": 0.1, "material": "l"}]}"#,
    )
    .unwrap();
    let Err(e) = Scene::build(file, &dir, "<test>") else { panic!("a tilted lens was rendered") };
    let e = e.to_string();
    std::fs::remove_dir_all(&dir).ok();
    assert!(e.contains("decentred or tilted") && e.contains("remove the motions"), "{e}");
}

/// An in-focus point lamp through the double Gauss at f/2, traced from the
/// lamp, images as the lens crate's spot: on a film of 2 um pixels at the
/// real-ray best focus (autofocus on the lamp), its RMS radius equals the
/// crate's RMS radius at best focus within 2%.
#[test]
fn an_in_focus_lamp_images_as_the_lens_crates_spot() {
    let s = scene(
        r#"{"camera": {"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../double-gauss-50mm.json",
                       "f_number": 2, "focus_on": "lamp", "sensor_mm": [0.2, 0.2]},
            "film": {"width": 100, "height": 100, "spp": 16, "spectral": "off"},
            "background": {"type": "constant", "radiance": [0, 0, 0]},
            "materials": {"lamp": {"type": "emissive", "radiance": [1000, 1000, 1000]}},
            "shapes": [{"type": "sphere", "name": "lamp", "center": [0, 0, 2], "radius": 0.00002, "material": "lamp"}]}"#,
    );
    let render::camera::Camera::Real(cam) = &s.camera else { panic!("a real lens") };
    let p = cam.prescription();
    let object = lens::paraxial::ObjectDistance::Finite(2000.0 - p.total_track());
    let want = lens::analysis::focus::focus(p, object).unwrap().rms_radius_at_best_focus * 1e3;
    let (img, _) = render(&s, Options { spp: 64, seed: 1 }, &|_| {});
    let (cx, cy, rms_px) = moments(&img);
    let got = rms_px * 2.0;
    assert!((cx - 50.0).abs() < 0.5 && (cy - 50.0).abs() < 0.5, "centroid {cx}, {cy}");
    assert!((got / want - 1.0).abs() < 0.02, "RMS radius: rendered {got:.3} um, lens crate {want:.3} um");
}

/// A scene of 300 small lamps traces the 256 that send the most light
/// into the lens (the nearest, here, all alike) and leaves the rest to
/// camera paths; a lamp whose blur fills the frame draws at most two rays a camera
/// sample, and the picture is the camera paths' still (total light within
/// 2%, the camera paths' own noise there about 1%).
#[test]
fn many_lamps_and_a_huge_one_stay_bounded() {
    let lamps: Vec<([f64; 3], f64)> = (0..300)
        .map(|k| ([0.1 * ((k % 20) as f64 - 9.5), 0.1 * ((k / 20) as f64 - 7.0), 4.0 + 0.01 * k as f64], 0.005))
        .collect();
    let s = lamps_scene(&lamps, "");
    let model = render::camera::lamp_light::LampLight::build(&s, 4).expect("lamps traced");
    assert_eq!(model.lamps(), (0..256).collect::<Vec<usize>>().as_slice(), "the nearest 256");
    let huge = [([0.0, 0.0, 0.15], 0.0005)];
    let traced = lamps_scene(&huge, "");
    let model = render::camera::lamp_light::LampLight::build(&traced, 16).expect("the huge lamp traced");
    assert!(model.rays() <= 2.0 * 16.0 * 48.0 * 32.0 * 1.0001, "{} rays", model.rays());
    let (ta, tb) = (mean_total(&traced, 16, 0..4), mean_total(&camera_only(lamps_scene(&huge, "")), 2048, 10..14));
    // camera paths alone find so near a lamp by chance: their own noise
    // over four seeds of 2,048 spp is about 1%
    assert!((ta / tb - 1.0).abs() < 0.02, "total light: traced {ta:.4}, camera only {tb:.4}");
}

/// The bokeh scene (`report-real-lens.json`: 15 lamps through the double
/// Gauss at f/2, spectral), at 80 x 50: its mean pixel at 1,024 spp with
/// the lamps traced from the lamps equals camera paths alone (8 seeds of
/// 512 spp) within three of the latter's standard errors (about 0.6% each).
#[test]
fn the_bokeh_scenes_mean_is_the_camera_paths() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes/report-real-lens.json");
    let mut traced = Scene::load(&path).unwrap();
    (traced.film.width, traced.film.height) = (80, 50);
    let mut plain = traced.clone();
    plain.lamp_tracing = false;
    let ta = mean_total(&traced, 1024, 1..2);
    let b: Vec<f64> = (10..18).map(|seed| mean_total(&plain, 512, seed..seed + 1)).collect();
    let mean = b.iter().sum::<f64>() / b.len() as f64;
    let se = (b.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (b.len() - 1) as f64 / b.len() as f64).sqrt();
    assert!(se < 0.01 * mean, "camera paths' standard error {se:.3} of {mean:.3}");
    assert!((ta - mean).abs() < 3.0 * se, "mean: traced {ta:.4}, camera only {mean:.4} +- {se:.4}");
}

/// A source whose own image is larger than its blur is left to the camera
/// paths, however small it is against the front plane's cells: the sun
/// (1.2 degrees, 12 pixels across) in focus through the 22 mm wide angle
/// is not traced from its light (it was, its probes thinned to its
/// centre, and came out speckled), while a lamp far out of focus is.
#[test]
fn a_resolved_sun_is_left_to_camera_paths() {
    let sun = Scene::load(&data().join("flare-sun-wide-angle.json")).unwrap();
    let traced = render::camera::lamp_light::LampLight::build(&sun, 16);
    assert_eq!(traced.map_or(0, |l| l.sky_patches()), 0);
    let bokeh = Scene::load(&data().join("bokeh-double-gauss.json")).unwrap();
    let lamps = render::camera::lamp_light::LampLight::build(&bokeh, 16).unwrap();
    assert!(!lamps.lamps().is_empty());
}
