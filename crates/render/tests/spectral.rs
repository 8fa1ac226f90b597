//! Spectral rendering: energy, agreement with RGB where nothing depends on
//! wavelength, and the colour of real glasses against the lens crate's
//! own analyses at each wavelength.

mod common;
use common::moments;
use glam::DVec3;
use lens::analysis::pattern::Pattern;
use lens::analysis::spot::spot_traced;
use lens::analysis::{fan::ImagePlane, Aim, Field, Launcher};
use render::camera::Camera;
use render::scene::format::{SceneFile, SpectralSpec};
use render::spectrum::{cie, RgbSpectrum};
use render::{render, render_with, Companions, Image, Options, Scene};
use std::path::Path;

fn data() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes")
}

fn scene(json: &str) -> Scene {
    let file: SceneFile = serde_json::from_str(json).unwrap();
    Scene::build(file, &data(), "<test>").unwrap()
}

/// Luminance Y of each pixel.
fn luminance(img: &Image) -> Vec<f64> {
    img.pixels.iter().map(|p| cie::rgb_to_xyz(*p).y).collect()
}

/// The image as Y only (every channel Y), for the moments helper.
fn grey(img: &Image, y: &[f64]) -> Image {
    Image { width: img.width, height: img.height, pixels: y.iter().map(|v| DVec3::splat(*v)).collect() }
}

fn mean(img: &Image) -> DVec3 {
    img.pixels.iter().copied().sum::<DVec3>() / img.pixels.len() as f64
}

/// A small white lamp at `lamp` (m) seen through `camera`, on black.
fn lamp_scene(camera: &str, lamp: DVec3, radius: f64, size: (usize, usize), film_extra: &str) -> Scene {
    scene(&format!(
        r#"{{"camera": {camera},
            "film": {{"width": {}, "height": {}, "spp": 64 {film_extra}}},
            "materials": {{"l": {{"type": "emissive", "radiance": [1000, 1000, 1000]}}}},
            "shapes": [{{"type": "sphere", "center": [{}, {}, {}], "radius": {radius}, "material": "l"}}]}}"#,
        size.0, size.1, lamp.x, lamp.y, lamp.z
    ))
}

#[test]
fn spectral_white_furnace_is_one_within_a_percent() {
    // A white diffuse sphere and a sphere of dispersive glass in a uniform
    // white surround: every pixel is the surround's radiance, 1. Seen
    // through a pinhole and through a thin lens with glass (whose four
    // wavelengths leave along one ray from four film points).
    let cameras = [
        r#"{"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 50}"#,
        r#"{"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 50, "f_number": 2,
            "focal_length_mm": 50, "focus_distance": 1.5, "glass": "SCHOTT:N-SF5"}"#,
    ];
    for cam in cameras {
        let s = scene(&format!(
            r#"{{"camera": {cam}, "film": {{"width": 48, "height": 32, "spp": 64, "spectral": "on"}},
                "background": {{"type": "constant", "radiance": [1, 1, 1]}},
                "materials": {{"white": {{"type": "diffuse", "color": [1, 1, 1]}},
                               "prism": {{"type": "dielectric", "glass": "SCHOTT:N-SF11"}}}},
                "shapes": [{{"type": "sphere", "center": [-0.5, 0, 3], "radius": 0.7, "material": "white"}},
                           {{"type": "sphere", "center": [0.7, 0, 2.5], "radius": 0.5, "material": "prism"}}]}}"#
        ));
        assert!(matches!(s.colour, render::scene::ColourMode::Spectral(_)));
        let (img, _) = render(&s, Options { spp: 256, seed: 7 }, &|_| {});
        let m = mean(&img);
        eprintln!("furnace mean {m}");
        for c in m.to_array() {
            assert!((c - 1.0).abs() < 0.01, "{cam}: mean {m}");
        }
    }
}

#[test]
fn a_grey_colour_round_trips_to_grey() {
    for g in [0.02, 0.18, 0.5, 0.9] {
        let back = RgbSpectrum::fit(DVec3::splat(g)).rgb();
        assert!((back - DVec3::splat(g)).abs().max_element() < 1e-12, "{g}: {back}");
    }
}

#[test]
fn rgb_and_spectral_renders_agree_where_nothing_depends_on_wavelength() {
    // White light, a grey floor and coloured balls apart from each other:
    // every path meets at most one coloured surface, so the spectral
    // estimate's expectation is the RGB one exactly.
    let json = r#"{"camera": {"type": "pinhole", "position": [0,1,-2], "look_at": [0,0.5,3], "fov_deg": 45},
        "film": {"width": 64, "height": 48, "spp": 64},
        "background": {"type": "constant", "radiance": [0.3, 0.3, 0.3]},
        "materials": {"floor": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
                      "red": {"type": "diffuse", "color": [0.8, 0.15, 0.1]},
                      "green": {"type": "diffuse", "color": [0.2, 0.7, 0.25]},
                      "blue": {"type": "diffuse", "color": [0.1, 0.2, 0.85]},
                      "lamp": {"type": "emissive", "radiance": [6, 6, 6]}},
        "shapes": [{"type": "plane", "point": [0,0,0], "normal": [0,1,0], "material": "floor"},
                   {"type": "sphere", "center": [-1.4, 0.5, 3], "radius": 0.5, "material": "red"},
                   {"type": "sphere", "center": [0, 0.5, 3], "radius": 0.5, "material": "green"},
                   {"type": "sphere", "center": [1.4, 0.5, 3], "radius": 0.5, "material": "blue"},
                   {"type": "quad", "corner": [-1, 3, 1.5], "u": [2, 0, 0], "v": [0, 0, 2], "material": "lamp"}]}"#;
    let mut s = scene(json);
    assert_eq!(s.colour, render::scene::ColourMode::Rgb, "nothing here depends on wavelength");
    let (rgb, _) = render(&s, Options { spp: 512, seed: 1 }, &|_| {});
    s.set_colour(SpectralSpec::On, None).unwrap();
    let (spec, _) = render(&s, Options { spp: 512, seed: 2 }, &|_| {});
    let (a, b) = (mean(&rgb), mean(&spec));
    for c in 0..3 {
        assert!((a[c] / b[c] - 1.0).abs() < 0.01, "channel {c}: RGB {a} vs spectral {b}");
    }
    // block by block (8 x 8 pixels): within the noise
    let block = |img: &Image, bx: usize, by: usize| {
        let mut s = DVec3::ZERO;
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                s += img.pixels[y * img.width + x];
            }
        }
        s / 64.0
    };
    let mut worst: f64 = 0.0;
    for by in 0..6 {
        for bx in 0..8 {
            let (p, q) = (block(&rgb, bx, by), block(&spec, bx, by));
            worst = worst.max(((p - q).abs() / (p + q).max(DVec3::splat(0.05))).max_element());
        }
    }
    eprintln!("RGB {a} vs spectral {b}; largest block difference {worst:.4}");
    assert!(worst < 0.04, "largest block difference {worst}");
}

/// The N-BK7 singlet focused at 2 m from the film, a lamp of radius
/// `radius` m on the axis at 1 m: its blur at `nm` (or spectral when
/// `None`), 128 x 128 px over 4 mm.
fn singlet_blur(nm: Option<f64>, spp: u32, radius: f64) -> (Scene, Image) {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../singlet-n-bk7-100mm.json",
                  "focus_distance": 2.0, "sensor_mm": [4.0, 4.0]}"#;
    let mut s = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), radius, (128, 128), "");
    s.set_colour(SpectralSpec::Auto, nm).unwrap();
    let (img, _) = render(&s, Options { spp, seed: 3 }, &|_| {});
    (s, img)
}

#[test]
fn a_singlets_blur_at_each_wavelength_is_the_spot_analysis_there() {
    // The lamp's own image (radius r, through the stop's centre, which is
    // the first vertex) widens the blur: the RMS radii add in quadrature,
    // a uniform disc's being r / sqrt(2).
    let radius = 0.0015;
    for nm in [486.1327, 587.5618, 656.2725] {
        let (s, img) = singlet_blur(Some(nm), 64, radius);
        let Camera::Real(real) = &s.camera else { panic!() };
        let p = real.prescription();
        // the lamp, 1 m from the film, from the first vertex in mm
        let object = 1000.0 - p.total_track();
        let edge =
            lens::Ray::new(DVec3::new(0.0, radius * 1e3, -object), DVec3::new(0.0, -radius * 1e3, object)).unwrap();
        let at_nm = p.at_wavelength(nm).unwrap();
        let r_img = lens::Tracer::forward(&at_nm).trace(edge).reached().unwrap().origin.y.abs();
        let launcher = Launcher::new(p, Field::Height { object_distance: object, height: 0.0 }, Aim::Paraxial).unwrap();
        let at = p.at_wavelength(nm).unwrap();
        let spot = spot_traced(p, &at, &launcher, Pattern::Gauss, 24, ImagePlane::Film(p.film_distance())).unwrap();
        let (_, _, rms_px) = moments(&img);
        let rendered = rms_px * 4.0 / 128.0;
        let predicted = (spot.rms_radius.powi(2) + r_img * r_img / 2.0).sqrt();
        let rel = rendered / predicted - 1.0;
        eprintln!("{nm} nm: rendered {rendered:.4} mm, predicted {predicted:.4} mm ({:+.2}%)", 100.0 * rel);
        assert!(
            rel.abs() < 0.05,
            "{nm} nm: rendered RMS blur {rendered:.4} mm, spot analysis {:.4} mm with the lamp's image {r_img:.4} mm",
            spot.rms_radius
        );
    }
}

#[test]
fn a_spectral_render_is_the_integral_of_monochromatic_ones() {
    // Y of the spectral render against the CIE-weighted sum of renders at
    // single wavelengths (10 nm apart): the same total light, spread the
    // same way. The spectral render's four wavelengths per sample leave the
    // lens from four film points; this checks how they are combined.
    let radius = 0.003;
    let (_, spectral) = singlet_blur(None, 128, radius);
    let ys = luminance(&spectral);
    let mut sum = vec![0.0; ys.len()];
    let step = 10.0;
    let mut total_weight = 0.0;
    for k in 0..=40 {
        let nm = 380.0 + step * k as f64;
        let (_, img) = singlet_blur(Some(nm), 32, radius);
        let w = cie::cmf(nm).y * step * if k == 0 || k == 40 { 0.5 } else { 1.0 };
        total_weight += w;
        // a monochromatic render's pixel is the radiance at that wavelength
        for (s, p) in sum.iter_mut().zip(&img.pixels) {
            *s += w * p.x;
        }
    }
    let predicted: Vec<f64> = sum.iter().map(|v| v / cie::y_integral()).collect();
    let (ts, tp) = (ys.iter().sum::<f64>(), predicted.iter().sum::<f64>());
    assert!((total_weight / cie::y_integral() - 1.0).abs() < 2e-3, "{total_weight}");
    eprintln!("total Y {:+.2}%", 100.0 * (ts / tp - 1.0));
    assert!((ts / tp - 1.0).abs() < 0.01, "total Y: spectral {ts:.1} vs integral {tp:.1}");
    let (_, _, rs) = moments(&grey(&spectral, &ys));
    let (_, _, rp) = moments(&grey(&spectral, &predicted));
    eprintln!("RMS radius of Y {:+.2}%", 100.0 * (rs / rp - 1.0));
    assert!((rs / rp - 1.0).abs() < 0.02, "RMS radius of Y: spectral {rs:.3} px vs integral {rp:.3} px");
}

#[test]
fn lateral_colour_is_the_analysis_within_half_a_pixel() {
    // The landscape singlet (stop in front): a distant round lamp 7.5
    // degrees off axis, its image 0.4 mm across, rendered at F and at C on
    // a strip of film 0.01 mm a pixel; the centroids differ by the lateral
    // colour `lens chromatic` finds.
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../landscape-n-bk7-100mm.json",
                  "focus_distance": 100.0, "sensor_mm": [30.0, 0.6]}"#;
    let angle = 7.5f64.to_radians();
    let lamp = DVec3::new(100.0 * angle.sin(), 0.0, 100.0 * angle.cos());
    let centroid = |nm: f64| {
        let mut s = lamp_scene(cam, lamp, 0.2, (3000, 60), "");
        s.set_colour(SpectralSpec::Auto, Some(nm)).unwrap();
        let (img, _) = render(&s, Options { spp: 16, seed: 4 }, &|_| {});
        let (cx, cy, _) = moments(&img);
        assert!((cy - 30.0).abs() < 1.0, "{cy}");
        cx
    };
    let rendered_px = centroid(486.1327) - centroid(656.2725);
    let probe = lamp_scene(cam, lamp, 0.005, (8, 8), "");
    let Camera::Real(real) = &probe.camera else { panic!() };
    let c = lens::analysis::chromatic::chromatic(real.prescription(), 7.5, 7.5, Aim::Paraxial).unwrap();
    let analysis_px = c.lateral.last().unwrap().lateral_colour / 0.01;
    eprintln!("lateral colour: rendered {rendered_px:.3} px, analysis {analysis_px:.3} px");
    assert!(
        (rendered_px.abs() - analysis_px.abs()).abs() < 0.5,
        "F - C centroid: rendered {rendered_px:.2} px, lens chromatic {analysis_px:.2} px"
    );
}

/// The colour-fringe energy of a scene, from two renders of it with
/// different seeds: the sum over pixels of the product of the two renders'
/// chroma (each pixel's colour less the grey of its luminance), over the
/// sum of the products of their luminances. The renders' noise is
/// independent, so it cancels from the products in expectation and what is
/// left is the fringes themselves.
fn fringe_energy(a: &Image, b: &Image) -> f64 {
    let (mut chroma, mut light) = (0.0, 0.0);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let (lp, lq) = (cie::rgb_to_xyz(*p).y, cie::rgb_to_xyz(*q).y);
        chroma += (*p - DVec3::splat(lp)).dot(*q - DVec3::splat(lq));
        light += lp * lq;
    }
    chroma / light
}

#[test]
fn the_achromats_colour_fringes_are_a_fifth_of_the_singlets() {
    // The same f/5 100 mm scene, a white lamp slightly behind focus.
    let energy = |lens: &str| {
        let cam = format!(
            r#"{{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../{lens}",
                 "focus_distance": 2.0, "sensor_mm": [2.0, 2.0]}}"#
        );
        let s = lamp_scene(&cam, DVec3::new(0.0, 0.0, 2.4), 0.003, (96, 96), "");
        let (a, _) = render(&s, Options { spp: 256, seed: 5 }, &|_| {});
        let (b, _) = render(&s, Options { spp: 256, seed: 6 }, &|_| {});
        fringe_energy(&a, &b)
    };
    let singlet = energy("singlet-n-bk7-100mm.json");
    let achromat = energy("achromat-fc-100mm.json");
    eprintln!("fringe energy: achromat {achromat:.5}, singlet {singlet:.5}, ratio {:.3}", achromat / singlet);
    assert!(achromat <= singlet / 5.0, "fringe energy: achromat {achromat:.4}, singlet {singlet:.4}");
}

/// Through a dispersive lens with the box filter each wavelength's light
/// goes to the pixel it lands in (companions included, `splat.rs`): the
/// image is the same to the bit on one thread and on four (the splats are
/// added band by band in row order), and every wavelength's light stays
/// on the film (total Y of a lamp well inside it as on one thread, the
/// test above holds it to the monochromatic integral).
#[test]
fn splatted_companions_do_not_depend_on_the_thread_count() {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../singlet-n-bk7-100mm.json",
                  "focus_distance": 2.0, "sensor_mm": [4.0, 4.0]}"#;
    let s = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), 0.003, (96, 80), "");
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render(&s, Options { spp: 16, seed: 5 }, &|_| {}).0)
    };
    let (one, four) = (on(1), on(4));
    assert!(one.pixels.iter().any(|p| p.x > 0.0));
    let bits = |img: &Image| img.pixels.iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&one), bits(&four));
}

/// Through a real lens a sample traces its companion wavelengths only when
/// its radiance, at the brightest of its four, reaches a threshold; the
/// others keep their hero alone. The choice depends only on what the four
/// share, so every threshold gives the same image in expectation: the
/// singlet's defocused white lamp (radiance varying with wavelength as D65
/// does) with companions for every sample, for none, and from a threshold
/// inside the lamp's own range (so that the choice falls differently for
/// different wavelengths drawn) has the same light in each channel and the
/// same blur radius in each, within 1%.
#[test]
fn tracing_companions_for_bright_samples_only_keeps_the_image() {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../singlet-n-bk7-100mm.json",
                  "focus_distance": 2.0, "sensor_mm": [4.0, 4.0]}"#;
    let s = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), 0.003, (96, 96), "");
    let channel = |img: &Image, c: usize| Image {
        width: img.width,
        height: img.height,
        pixels: img.pixels.iter().map(|p| DVec3::splat(p[c])).collect(),
    };
    let stats = |from: f64, seed: u64| {
        let (img, _) = render_with(&s, Options { spp: 1024, seed }, &|_| {}, Companions::From(from));
        (0..3)
            .map(|c| {
                let ch = channel(&img, c);
                let total: f64 = ch.pixels.iter().map(|p| p.x).sum();
                let (_, _, rms) = moments(&ch);
                (total, rms)
            })
            .collect::<Vec<_>>()
    };
    let all = stats(0.0, 11);
    for (name, from, seed) in [("none", f64::INFINITY, 12), ("from 1050", 1050.0, 13)] {
        let other = stats(from, seed);
        for c in 0..3 {
            let (t, r) = (other[c].0 / all[c].0 - 1.0, other[c].1 / all[c].1 - 1.0);
            eprintln!("{name}, channel {c}: light {:+.3}%, RMS radius {:+.3}%", 100.0 * t, 100.0 * r);
            assert!(t.abs() < 0.01 && r.abs() < 0.01, "{name}, channel {c}: light {t:+.4}, radius {r:+.4}");
        }
    }
}

/// `film.companions: "all"` traces every sample's companions: the render is
/// the one with a threshold of 0, to the bit, and with `"auto"` (the
/// default) the one with the pilot's threshold.
#[test]
fn the_film_chooses_which_samples_trace_companions() {
    let cam = r#"{"type": "lens", "position": [0,0,0], "look_at": [0,0,1], "prescription": "../singlet-n-bk7-100mm.json",
                  "focus_distance": 2.0, "sensor_mm": [4.0, 4.0]}"#;
    let opt = Options { spp: 8, seed: 3 };
    let bits = |img: &Image| img.pixels.iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    let all = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), 0.003, (32, 32), r#", "companions": "all""#);
    assert_eq!(bits(&render(&all, opt, &|_| {}).0), bits(&render_with(&all, opt, &|_| {}, Companions::From(0.0)).0));
    let auto = lamp_scene(cam, DVec3::new(0.0, 0.0, 1.0), 0.003, (32, 32), "");
    assert_eq!(bits(&render(&auto, opt, &|_| {}).0), bits(&render_with(&auto, opt, &|_| {}, Companions::Auto).0));
}
