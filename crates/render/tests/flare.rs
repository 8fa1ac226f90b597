//! Lens flare in renders (`film.flare`): the ghost layer against the lens
//! crate's brute-force reference (rays reflecting or refracting at random
//! at every surface), and the primary image dimmed by what the surfaces
//! reflect.

use glam::DVec3;
use lens::ghost::image::Entrance;
use lens::ghost::reference::{brute_force, favouring};
use lens::ghost::{FilmGrid, GhostImage, Source};
use render::camera::flare::ghost_layer;
use render::camera::Camera;
use render::scene::format::SceneFile;
use render::{render, Options, Scene};
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

/// One lamp (radiance 1000, radius 2 cm) at `lamp` (m) seen through the
/// uncoated 100 mm singlet, at 550 nm alone, on a 160 x 120 film of 36 x
/// 27 mm (square pixels).
fn lamp_scene(lamp: DVec3, flare: &str) -> Scene {
    let (x, y, z) = (lamp.x, lamp.y, lamp.z);
    singlet_scene(
        &format!(r#"{{"type": "sphere", "center": [{x}, {y}, {z}], "radius": 0.02, "material": "l"}}"#),
        flare,
    )
}

/// The scene of [`lamp_scene`] with the one shape `shape` (JSON, of the
/// emissive material "l") for its lamp.
fn singlet_scene(shape: &str, flare: &str) -> Scene {
    let json = format!(
        r#"{{"camera": {{"type": "lens", "prescription": "../singlet-n-bk7-100mm.json", "f_number": 5.6,
              "focus_distance": 3.0, "sensor_mm": [36, 27], "coating": "none",
              "position": [0, 0, 0], "look_at": [0, 0, 1]}},
            "film": {{"width": 160, "height": 120, "spp": 16, "wavelength_nm": 550, "flare": "{flare}"}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{shape}]}}"#
    );
    let file: SceneFile = serde_json::from_str(&json).unwrap();
    Scene::build(file, &data(), "<test>").unwrap()
}

/// The lamp of 2 cm radius at `lamp` (m) as the reference sees it: the
/// lens at 550 nm, the lamp a point at its centre (the lens frame) of
/// intensity L times the solid angle its disc fills times the distance
/// squared (L its radiance at 550 nm, the RGB white of 1000 as a
/// spectrum), the film's pixel (mm) and a grid of `w` x `h` of them.
fn lamp_as_point(
    scene: &Scene,
    cam: &render::camera::real_lens::RealLensCamera,
    lamp: DVec3,
    w: usize,
    h: usize,
) -> (lens::Prescription, Source, f64, f64, FilmGrid) {
    let at = render::transport::Spectral::new(render::spectrum::SampledWavelengths::single(550.0));
    let radiance = scene.materials[scene.material_of[0]].emitted(&at, 1.0).0[0];
    let p = cam.prescription().at_wavelength(550.0).unwrap();
    let centre = cam.point_to_lens(lamp);
    let rho: f64 = 20.0;
    let r = (centre - DVec3::new(0.0, 0.0, -1.0)).length();
    let intensity = radiance * std::f64::consts::TAU * (1.0 - (1.0 - (rho / r).powi(2)).sqrt()) * r * r;
    let [sw, _] = cam.sensor_mm();
    let pix = sw / w as f64;
    (p, Source::Point(centre), intensity, pix, FilmGrid { centre_mm: [0.0; 2], pixel_mm: pix, nx: w, ny: h })
}

/// The rendered ghost of the singlet (its one ghost, surfaces 1 and 2)
/// against the brute-force reference traced from the same lamp: the
/// same energy within 2%, the same centroid within a pixel, the same
/// image within the reference's noise (pixels where either has light).
#[test]
fn rendered_ghost_matches_the_brute_force_reference() {
    let lamp = DVec3::new(0.25, 0.15, 4.0);
    let scene = lamp_scene(lamp, "ghosts");
    let Camera::Real(cam) = &scene.camera else { panic!("a real lens") };
    let (w, h) = (160usize, 120usize);
    let layer = ghost_layer(&scene, cam, w, h, 0.0);
    let got: Vec<f64> = layer.iter().map(|v| v.y).collect();
    let (p, source, intensity, pix, grid) = lamp_as_point(&scene, cam, lamp, w, h);
    let tracer = lens::Tracer::ghost(&p, 0, 1, p.film_distance()).unwrap();
    let near = Entrance::of(&p, &source).around_passing(&tracer, &source, 128, 8).unwrap();
    const RUNS: usize = 8;
    let runs: Vec<GhostImage> = (0..RUNS as u64)
        .map(|seed| {
            let mut all = brute_force(&p, &source, &near, &grid, 500_000, &favouring(vec![0, 1], 0.5), seed);
            all.remove(&vec![1, 0]).unwrap()
        })
        .collect();
    // to film units (a pixel is 1 / (norm A_pix) of the power in it), the
    // film's x mirrored (u = 0.5 - x / sensor width)
    let to_film = |img: &GhostImage| -> Vec<f64> {
        let mut out = vec![0.0; w * h];
        for (k, v) in img.power.iter().enumerate() {
            let (i, j) = (k % w, k / w);
            out[j * w + (w - 1 - i)] = v * intensity / (cam.centre_weight() * pix * pix);
        }
        out
    };
    let refs: Vec<Vec<f64>> = runs.iter().map(to_film).collect();
    let mean: Vec<f64> = (0..w * h).map(|k| refs.iter().map(|r| r[k]).sum::<f64>() / RUNS as f64).collect();
    let totals: Vec<f64> = refs.iter().map(|r| r.iter().sum()).collect();
    let total = totals.iter().sum::<f64>() / RUNS as f64;
    let spread = (totals.iter().map(|t| (t - total).powi(2)).sum::<f64>() / (RUNS as f64 * (RUNS - 1) as f64)).sqrt();
    let sum: f64 = got.iter().sum();
    let centroid = |v: &[f64]| {
        let s: f64 = v.iter().sum();
        let (mut x, mut y) = (0.0, 0.0);
        for (k, a) in v.iter().enumerate() {
            x += a * ((k % w) as f64 + 0.5);
            y += a * ((k / w) as f64 + 0.5);
        }
        (x / s, y / s)
    };
    let (a, b) = (centroid(&got), centroid(&mean));
    let noise: f64 = (0..w * h)
        .map(|k| {
            let m = mean[k];
            refs.iter().map(|r| (r[k] - m).powi(2)).sum::<f64>() / ((RUNS - 1) * RUNS) as f64
        })
        .sum();
    let lit: Vec<usize> = (0..w * h).filter(|&k| got[k] > 0.0 || mean[k] > 0.0).collect();
    let err: f64 = lit.iter().map(|&k| (got[k] - mean[k]).powi(2)).sum();
    eprintln!(
        "ghost energy {sum:.4} vs {total:.4} +- {spread:.4}; centroid ({:.2}, {:.2}) vs ({:.2}, {:.2}) px; sq. error {err:.3e} vs the reference's noise {noise:.3e}",
        a.0, a.1, b.0, b.1
    );
    assert!(sum > 0.0);
    assert!((sum - total).abs() < 0.02 * total, "{sum} vs {total}");
    assert!(((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt() < 1.0, "{a:?} vs {b:?}");
    assert!(err < 1.5 * noise, "{err} vs {noise}");
}

/// With flare on, the primary image loses what the two faces reflect: the
/// lamp's light, less the ghost layer, is (1 - R)^2 of the light without
/// flare (bare N-BK7 at 550 nm, the lamp near the axis), and the ghost
/// layer holds less than R^2 of it (the rest of the ghost falls off the
/// frame).
#[test]
fn the_primary_image_loses_what_the_surfaces_reflect() {
    let lamp = DVec3::new(0.02, 0.0, 4.0);
    let opt = Options { spp: 16, seed: 3 };
    let off = render(&lamp_scene(lamp, "off"), opt, &|_| {}).0;
    let scene = lamp_scene(lamp, "ghosts");
    let on = render(&scene, opt, &|_| {}).0;
    let Camera::Real(cam) = &scene.camera else { panic!("a real lens") };
    let layer = ghost_layer(&scene, cam, 160, 120, 0.0);
    let sum = |v: &[DVec3]| v.iter().map(|p| p.y).sum::<f64>();
    let (e_off, e_on, e_ghost) = (sum(&off.pixels), sum(&on.pixels), sum(&layer));
    let n = cam.prescription().at_wavelength(550.0).unwrap().surfaces()[0].ior;
    let r = ((n - 1.0) / (n + 1.0)).powi(2);
    let kept = (e_on - e_ghost) / e_off;
    eprintln!(
        "kept {kept:.5} vs (1 - R)^2 = {:.5}; ghost / primary {:.3e} vs R^2 = {:.3e}",
        (1.0 - r).powi(2),
        e_ghost / e_off,
        r * r
    );
    assert!((kept - (1.0 - r).powi(2)).abs() < 0.005, "{kept}");
    // the singlet's ghost is wider than the frame: the frame holds part of
    // its R^2 (1 - R)^2
    assert!(e_ghost > 0.0 && e_ghost < r * r * e_off, "{e_ghost} vs {}", r * r * e_off);
}

/// Stopped down, every ghost's light is found: the ghost layer of a lamp
/// through the double Gauss at f/16 (its entrance pupil 3 mm across, a
/// sliver of the front element) holds the light of all its ghosts on the
/// frame, each rasterised on its own finely over where its light enters,
/// within 2%.
#[test]
fn stopped_down_ghosts_are_all_found() {
    let (got, want) = ghost_light_at_f16("", DVec3::new(0.35, 0.2, 5.0));
    eprintln!("ghost layer {got:.5} vs each ghost found finely {want:.5}");
    assert!(want > 0.0);
    assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
}

/// A stop of six blades shapes the ghosts it limits: at f/16 through the
/// double Gauss (every ghost limited by the stop) the ghost layer holds
/// the light of each ghost found finely through the hexagon within 2%;
/// and for a lamp on the axis, where each pass through the stop meets
/// the hexagon scaled about the axis (a ghost's passes clip it to the
/// smallest), the ghosts keep the hexagon's share of the round stop's
/// light: its area over the circle's, 3 sqrt 3 / 2 pi = 0.827, within
/// 2% (the primary image's exposure, which the film is normalised to,
/// loses the same share).
#[test]
fn ghosts_take_the_shape_of_the_blades() {
    let hexagon = r#""aperture_shape": {"shape": "polygon", "blades": 6, "rotation_deg": 10},"#;
    let off_axis = DVec3::new(0.35, 0.2, 5.0);
    let (got, want) = ghost_light_at_f16(hexagon, off_axis);
    eprintln!("hexagon: ghost layer {got:.5} vs each ghost finely {want:.5}");
    assert!(want > 0.0);
    assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
    let on_axis = DVec3::new(0.0, 0.0, 5.0);
    let (hex, _) = ghost_light_at_f16(hexagon, on_axis);
    let (round, _) = ghost_light_at_f16("", on_axis);
    let share = 3.0 * 3f64.sqrt() / (2.0 * std::f64::consts::PI);
    eprintln!(
        "on the axis the hexagon's ghosts hold {:.4} of the round stop's, the area's share {share:.4}",
        hex / round
    );
    assert!((hex / round - 1.0).abs() < 0.02, "{} of the round stop's light in film units", hex / round);
}

/// A lamp at `lamp` (m) through the double Gauss at f/16 with the
/// camera's extra fields `shape` (an aperture shape, or nothing): the
/// light (film units) of its ghost
/// layer and that of its ghosts each rasterised finely on its own over
/// where its light enters (through the same stop shape), on the frame.
fn ghost_light_at_f16(shape: &str, lamp: DVec3) -> (f64, f64) {
    let json = format!(
        r#"{{"camera": {{"type": "lens", "prescription": "../library/tronnier-double-gauss-50mm-f2-us2673491.json",
              "f_number": 16, "focus_distance": 3.0, "sensor_mm": [36, 24], {shape}
              "position": [0, 0, 0], "look_at": [0, 0, 1]}},
            "film": {{"width": 192, "height": 128, "spp": 4, "wavelength_nm": 550, "flare": "ghosts"}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [{}, {}, {}], "radius": 0.02, "material": "l"}}]}}"#,
        lamp.x, lamp.y, lamp.z
    );
    let file: SceneFile = serde_json::from_str(&json).unwrap();
    let scene = Scene::build(file, &data(), "<test>").unwrap();
    let Camera::Real(cam) = &scene.camera else { panic!("a real lens") };
    let (w, h) = (192usize, 128usize);
    let got: f64 = ghost_layer(&scene, cam, w, h, 0.0).iter().map(|v| v.y).sum();
    let (p, source, intensity, pix, grid) = lamp_as_point(&scene, cam, lamp, w, h);
    let stop = cam
        .aperture()
        .scaled(p.stop_semi_diameter())
        .map(|transmission| lens::trace::StopShape { surface: p.stop_index(), transmission });
    let mut want = 0.0;
    for [i, j] in lens::ghost::ghost_pairs(&p) {
        let Some(t) = lens::Tracer::ghost(&p, i, j, p.film_distance()) else { continue };
        let t = match &stop {
            Some(s) => t.with_stop_shape(s.clone()),
            None => t,
        };
        let Some(near) = Entrance::of(&p, &source).around_passing(&t, &source, 192, 2) else { continue };
        let img = lens::ghost::rasterise(&t, &source, &near, &grid, 48);
        want += img.power.iter().sum::<f64>() * intensity / (cam.centre_weight() * pix * pix);
    }
    (got, want)
}

/// A small emissive quad makes ghosts as a point source of its area
/// times its cosine toward the lens: a square lamp 3.54 cm wide facing the
/// lens gives the ghost layer of a sphere lamp of 2 cm radius (the same
/// area across) at the same place within 0.5%; turned away, or 40 cm wide
/// (over 2 degrees from 4 m), it makes none.
#[test]
fn small_flat_lamps_make_ghosts() {
    let lamp = DVec3::new(0.25, 0.15, 4.0);
    let light = |scene: Scene| -> f64 {
        let Camera::Real(cam) = &scene.camera else { panic!("a real lens") };
        ghost_layer(&scene, cam, 160, 120, 0.0).iter().map(|v| v.y).sum()
    };
    let layer = |shape: &str| light(singlet_scene(shape, "ghosts"));
    let (x, y, z) = (lamp.x, lamp.y, lamp.z);
    let sphere = light(lamp_scene(lamp, "ghosts"));
    // a square `a` wide centred on the lamp, its front (u x v) toward -z
    // (the camera) or +z
    let quad = |a: f64, toward: f64| {
        format!(
            r#"{{"type": "quad", "corner": [{}, {}, {z}], "u": [{}, 0, 0], "v": [0, {a}, 0], "material": "l"}}"#,
            x - toward * a / 2.0,
            y - a / 2.0,
            toward * a,
        )
    };
    let a = 0.02 * std::f64::consts::PI.sqrt();
    let square = layer(&quad(a, -1.0));
    let away = layer(&quad(a, 1.0));
    let wide = layer(&quad(0.4, -1.0));
    eprintln!("ghost light: sphere {sphere:.5}, square {square:.5}, turned away {away}, 40 cm wide {wide}");
    assert!(sphere > 0.0);
    assert!((square - sphere).abs() < 5e-3 * sphere, "{square} vs {sphere}");
    assert_eq!(away, 0.0);
    assert_eq!(wide, 0.0);
}
