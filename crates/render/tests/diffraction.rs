//! Diffraction at the aperture (`film.diffraction`): the Airy ring of an
//! ideal lens at f/16, the spikes of straight blades, and the image's
//! energy kept.

use glam::DVec3;
use render::camera::aperture::Aperture;
use render::camera::diffraction::{convolve, kernel, kernel_for, working_f_number, Kernel};
use render::camera::Camera;
use render::scene::format::SceneFile;
use render::scene::ColourMode;
use render::{render, Options, Scene};
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

fn scene(json: &str) -> Scene {
    let file: SceneFile = serde_json::from_str(json).unwrap();
    Scene::build(file, &data(), "<test>").unwrap()
}

/// The kernel's value at (dx, dy) pixels from its centre (bilinear; 0
/// outside), green channel.
fn at(k: &Kernel, dx: f64, dy: f64) -> f64 {
    let (c, r) = (dx + k.cx as f64, dy + k.cy as f64);
    let (c0, r0) = (c.floor(), r.floor());
    let (fc, fr) = (c - c0, r - r0);
    let mut v = 0.0;
    for (dr, wr) in [(0.0, 1.0 - fr), (1.0, fr)] {
        for (dc, wc) in [(0.0, 1.0 - fc), (1.0, fc)] {
            let (cc, rr) = (c0 + dc, r0 + dr);
            if cc >= 0.0 && rr >= 0.0 && (cc as usize) < k.nx && (rr as usize) < k.ny {
                v += k.rgb[rr as usize * k.nx + cc as usize].y * wr * wc;
            }
        }
    }
    v
}

/// A point source through an ideal 50 mm lens at f/16 (focused at
/// infinity, 550 nm), on pixels of 1 µm: the film's point spreads into the
/// Airy pattern, its first dark ring at 1.22 λ N = 10.74 µm, found within
/// a pixel, and the light is all kept.
#[test]
fn ideal_lens_at_f16_has_its_first_dark_ring_at_1_22_lambda_n() {
    let s = scene(
        r#"{"camera": {"type": "lens", "prescription": "../../crates/render/tests/data/ideal-50mm-f16.json", "sensor_mm": [0.2, 0.2],
              "focus_distance": 1e6, "position": [0, 0, 0], "look_at": [0, 0, 1]},
            "film": {"width": 200, "height": 200, "spp": 1, "wavelength_nm": 550, "diffraction": "on"},
            "materials": {}, "shapes": []}"#,
    );
    let Camera::Real(cam) = &s.camera else { panic!("a real lens") };
    let n = working_f_number(cam);
    assert!((n - 16.0).abs() < 0.01, "working f-number {n}");
    let k = kernel(cam, &s.colour, 200, 200);
    let mut film = vec![DVec3::ZERO; 200 * 200];
    film[100 * 200 + 100] = DVec3::ONE;
    convolve(&mut film, 200, 200, &k);
    // all but the far rings' light stays on this 200 µm frame
    let total: f64 = film.iter().map(|v| v.y).sum();
    assert!(total > 0.97 && total <= 1.0 + 1e-9, "{total}");
    // the azimuthal mean at each radius (pixel centres, the point at
    // pixel 100's centre)
    let mut ring = vec![(0.0, 0usize); 30];
    for y in 70..130 {
        for x in 70..130 {
            let r = (((x as f64 - 100.0).powi(2) + (y as f64 - 100.0).powi(2)).sqrt()).round() as usize;
            if r < 30 {
                ring[r].0 += film[y * 200 + x].y;
                ring[r].1 += 1;
            }
        }
    }
    let mean: Vec<f64> = ring.iter().map(|(s, c)| s / *c as f64).collect();
    let first_min = (6..16).min_by(|&a, &b| mean[a].total_cmp(&mean[b])).unwrap();
    let want = 1.22 * 550e-6 * 16.0 / 1e-3;
    eprintln!("first dark ring at {first_min} px, 1.22 λ N = {want:.2} px; profile {:?}", &mean[..16]);
    assert!((first_min as f64 - want).abs() <= 1.0, "{first_min} vs {want}");
    // and the second bright ring beyond it
    assert!(mean[first_min + 3] > 2.0 * mean[first_min]);
}

/// The spikes of a stop of straight blades, along the blades' normals: a
/// hexagon makes 6 (opposite edges share a line), a heptagon 14; counted
/// as peaks of the pattern around a circle well outside the core.
#[test]
fn straight_blades_make_spikes_along_their_normals() {
    for (blades, rotation_deg, spikes) in [(6u32, 0.0f64, 6usize), (7, 10.0, 14), (5, 0.0, 10)] {
        let a = Aperture::Polygon { blades, rotation: rotation_deg.to_radians() };
        let k = kernel_for(&a, 16.0, [0.002, 0.002], [400, 400], &ColourMode::Monochromatic(550.0));
        // around circles from 25 to 45 pixels (5 to 10 Airy radii)
        let steps = 1440;
        let raw: Vec<f64> = (0..steps)
            .map(|s| {
                let t = std::f64::consts::TAU * s as f64 / steps as f64;
                // angle measured in the lens frame: film x is the kernel's
                // -column, film y its row
                (25..45).map(|r| at(&k, -(r as f64) * t.cos(), r as f64 * t.sin())).sum::<f64>()
            })
            .collect();
        // smoothed over 3 degrees: a spike's own fringes are one peak
        let profile: Vec<f64> =
            (0..steps).map(|s| (0..13).map(|d| raw[(s + steps + d - 6) % steps]).sum::<f64>() / 13.0).collect();
        let median = {
            let mut v = profile.clone();
            v.sort_by(f64::total_cmp);
            v[steps / 2]
        };
        let peaks: Vec<f64> = (0..steps)
            .filter(|&s| {
                let (l, c, r) = (profile[(s + steps - 1) % steps], profile[s], profile[(s + 1) % steps]);
                c > l && c >= r && c > 1.25 * median
            })
            .map(|s| 360.0 * s as f64 / steps as f64)
            .collect();
        eprintln!("{blades} blades: peaks at {peaks:?}");
        assert_eq!(peaks.len(), spikes, "{blades} blades: {peaks:?}");
        // each along a blade's normal (either way)
        for p in &peaks {
            let off = (0..blades)
                .map(|j| {
                    let normal = rotation_deg + 360.0 * (j as f64 + 0.5) / blades as f64;
                    let d = (p - normal).rem_euclid(180.0);
                    d.min(180.0 - d)
                })
                .fold(f64::INFINITY, f64::min);
            assert!(off < 1.0, "{blades} blades: a spike at {p} deg is {off} deg off every normal");
        }
    }
}

/// Diffraction moves light, it does not make or lose it: a defocused lamp
/// near the frame's centre, the image's energy with diffraction on equals
/// the energy without within 0.5% (RGB, a hexagonal stop at f/8).
#[test]
fn diffraction_keeps_the_image_energy() {
    let json = |d: &str| {
        format!(
            r#"{{"camera": {{"type": "lens", "prescription": "../double-gauss-50mm.json", "f_number": 8,
                  "focus_distance": 2.0, "sensor_mm": [36, 24], "position": [0, 0, 0], "look_at": [0, 0, 1],
                  "aperture_shape": {{"shape": "polygon", "blades": 6}}}},
                "film": {{"width": 120, "height": 80, "spp": 16, "spectral": "off", "diffraction": "{d}"}},
                "materials": {{"l": {{"type": "emissive", "radiance": [500, 400, 300]}}}},
                "shapes": [{{"type": "sphere", "center": [0.02, 0.01, 0.8], "radius": 0.004, "material": "l"}}]}}"#
        )
    };
    let opt = Options { spp: 16, seed: 5 };
    let off = render(&scene(&json("off")), opt, &|_| {}).0;
    let on = render(&scene(&json("on")), opt, &|_| {}).0;
    let sum = |v: &[DVec3]| v.iter().sum::<DVec3>();
    let (a, b) = (sum(&off.pixels), sum(&on.pixels));
    eprintln!("energy off {a:?}, on {b:?}");
    for c in 0..3 {
        assert!((a[c] - b[c]).abs() < 0.005 * a[c], "channel {c}: {} vs {}", a[c], b[c]);
    }
    // and it did spread the light: the peak is lower
    let peak = |v: &[DVec3]| v.iter().map(|p| p.y).fold(0.0, f64::max);
    assert!(peak(&on.pixels) < peak(&off.pixels));
}
