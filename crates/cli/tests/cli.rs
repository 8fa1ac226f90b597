//! The `lens` command end to end: JSON keys are a public interface.

use std::process::Command;

fn lens(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lens"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn json(s: &str) -> serde_json::Value {
    serde_json::from_str(s.trim()).unwrap_or_else(|e| panic!("{e}: {s}"))
}

#[test]
fn info_json_has_the_contract_keys() {
    let (code, out, err) = lens(&["info", "lens-data/double-gauss-50mm.json", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    for k in [
        "efl",
        "bfl",
        "ffd",
        "front_principal_plane",
        "back_principal_plane",
        "f_number",
        "working_f_number",
        "image_distance",
        "magnification",
        "total_track",
    ] {
        assert!(v[k].is_f64(), "{k} missing in {v}");
    }
    for k in ["entrance_pupil", "exit_pupil"] {
        assert!(v[k]["z"].is_f64() && v[k]["diameter"].is_f64(), "{k} in {v}");
    }
    assert!((v["efl"].as_f64().unwrap() - 50.358).abs() < 1e-3);
    assert_eq!(v["image_distance"], v["bfl"]);
    assert_eq!(v["magnification"].as_f64(), Some(0.0));
}

#[test]
fn info_with_a_finite_object_and_f_number() {
    let (code, out, err) =
        lens(&["info", "lens-data/double-gauss-50mm.json", "--object-distance", "2000", "--f-number", "8", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert!((v["f_number"].as_f64().unwrap() - 8.0).abs() < 1e-12);
    let m = v["magnification"].as_f64().unwrap();
    assert!(m < 0.0 && m > -0.05, "{m}");
    assert!(v["working_f_number"].as_f64().unwrap() > 8.0);
    assert!(v["image_distance"].as_f64().unwrap() > v["bfl"].as_f64().unwrap());
    let (code, out, _) = lens(&["info", "lens-data/cooke-triplet.json"]);
    assert_eq!(code, 0);
    assert!(out.contains("effective focal length") && out.contains("101.18"), "{out}");
}

#[test]
fn focus_prints_paraxial_and_real_film_distances() {
    let (code, out, err) = lens(&["focus", "lens-data/double-gauss-50mm.json", "--object-distance", "2000", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let film = v["film_distance"].as_f64().unwrap();
    let best = v["best_focus_film_distance"].as_f64().unwrap();
    assert!(film > 36.1 && (best - film).abs() < 0.5, "{v}");
    // the inverse brings back the object distance
    let (code, out, err) =
        lens(&["focus", "lens-data/double-gauss-50mm.json", "--film-distance", &format!("{film:.12}"), "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!((json(&out)["object_distance"].as_f64().unwrap() - 2000.0).abs() < 1e-6, "{out}");
    // at the front focal plane: a clear error, exit 1, no NaN
    let (code, out, err) = lens(&["focus", "lens-data/double-gauss-50mm.json", "--object-distance", "27.1224456211"]);
    assert_eq!(code, 1, "{out}");
    assert!(err.contains("front focal plane") || err.contains("no real image"), "{err}");
    let (code, _, err) = lens(&["focus", "lens-data/double-gauss-50mm.json", "--object-distance", "-5"]);
    assert_eq!(code, 1);
    assert!(err.contains("object_distance"), "{err}");
}

#[test]
fn validate_reports_every_finding_and_exits_1_on_errors() {
    let dir = std::env::temp_dir().join(format!("lens-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"surfaces": [{"radius": 0, "thickness": 2, "semi_diameter": 5},
                          {"radius": 10, "thickness": -1, "semi_diameter": 12}]}"#,
    )
    .unwrap();
    let (code, out, _) = lens(&["validate", "lens-data/cooke-triplet.json", bad.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(out.contains("cooke-triplet.json: valid"), "{out}");
    for needle in
        ["surface 1: radius 0", "surface 2: thickness -1", "surface 2: semi_diameter 12 mm exceeds", "no aperture stop"]
    {
        assert!(out.contains(needle), "{needle} in {out}");
    }
    let malformed = dir.join("malformed.json");
    std::fs::write(&malformed, "{\"surfaces\": [\n  {\"thickness\": }\n]}").unwrap();
    let (code, out, _) = lens(&["validate", malformed.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(out.contains("line 2, column"), "{out}");
    let (code, out, _) = lens(&["validate", "lens-data/double-gauss-50mm.json", "--json"]);
    assert_eq!(code, 0);
    assert_eq!(json(&out)["valid"], true);
    let (code, _, err) = lens(&["info", "no/such/file.json"]);
    assert_eq!(code, 1);
    assert!(err.contains("no/such/file.json"), "{err}");
}

#[test]
fn bench_prints_rates() {
    let (code, out, err) = lens(&["bench", "lens-data/double-gauss-50mm.json", "--rays", "20000", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert!(v["rays_per_second"].as_f64().unwrap() > 0.0);
    assert!(v["ray_surface_per_second"].as_f64().unwrap() > v["rays_per_second"].as_f64().unwrap());
    // the headline is the fastest pass, never slower than the median one
    let median = v["median_ray_surface_per_second"].as_f64().unwrap();
    assert!(median > 0.0 && median <= v["ray_surface_per_second"].as_f64().unwrap());
    assert!(v["passes"].as_u64().unwrap() >= 3);
}

#[test]
fn fan_json_contract() {
    let (code, out, err) =
        lens(&["fan", "lens-data/double-gauss-50mm.json", "--field-deg", "10", "--points", "7", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["field_deg"].as_f64(), Some(10.0));
    assert!(v["image_z"].as_f64().unwrap() > 68.0);
    let t = v["tangential"].as_array().unwrap();
    let s = v["sagittal"].as_array().unwrap();
    assert_eq!((t.len(), s.len()), (7, 7));
    for (i, row) in t.iter().enumerate() {
        assert!((row["py"].as_f64().unwrap() - (-1.0 + i as f64 / 3.0)).abs() < 1e-15);
        for k in ["x", "y", "ey"] {
            assert!(row.get(k).is_some(), "{k} in {row}");
        }
    }
    assert_eq!(t[3]["ey"].as_f64(), Some(0.0));
    assert!(s[3].get("ex").is_some() && s[3].get("px").is_some());
    // the image lands near +EFL tan(theta)
    assert!((t[3]["y"].as_f64().unwrap() - 50.358 * 10f64.to_radians().tan()).abs() < 0.2);
}

#[test]
fn spot_coc_field_json_contracts() {
    let (code, out, err) =
        lens(&["spot", "lens-data/cooke-triplet.json", "--pattern", "square", "--n", "101", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    for k in ["rays", "vignetted", "rms_radius", "rms_radius_chief", "geo_radius"] {
        assert!(v[k].is_number(), "{k} in {v}");
    }
    assert_eq!(v["centroid"].as_array().unwrap().len(), 2);
    assert!(v["rays"].as_u64().unwrap() + v["vignetted"].as_u64().unwrap() > 7800);

    let (code, out, err) = lens(&[
        "coc",
        "lens-data/double-gauss-50mm.json",
        "--focus-mm",
        "2000",
        "--distances",
        "1000,2000,inf",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for r in rows {
        for k in ["distance", "geo_diameter", "rms_diameter", "thin_lens_diameter"] {
            assert!(r.get(k).is_some(), "{k} in {r}");
        }
    }
    assert_eq!(rows[0]["distance"].as_f64(), Some(1000.0));

    let (code, out, err) =
        lens(&["field", "lens-data/cooke-triplet.json", "--max-field-deg", "20", "--fields", "5", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["fields"].as_array().unwrap().len(), 5);
    assert!(v["fields"][4]["distortion_percent"].is_f64());
}

#[test]
fn pictures_are_written_as_svg_and_png() {
    let dir = std::env::temp_dir().join(format!("lens-cli-pics-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("layout.svg");
    let png = dir.join("layout.png");
    for out in [&svg, &png] {
        let (code, _, err) =
            lens(&["layout", "lens-data/double-gauss-50mm.json", "--fields", "0,10", "-o", out.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
    }
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("<polygon") && text.contains("polyline"));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert!(bytes.len() > 10_000, "{}", bytes.len());
    let plot = dir.join("spot.png");
    let (code, _, err) = lens(&["spot", "lens-data/double-gauss-50mm.json", "--plot", plot.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = lens(&["layout", "lens-data/double-gauss-50mm.json", "-o", "x.gif"]);
    assert_eq!(code, 1);
    assert!(err.contains(".svg or .png"), "{err}");
}

/// A write error on standard output (a full disk) is an error with exit 1,
/// not a panic, for every command that prints.
#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    let full = std::path::Path::new("/dev/full");
    if !full.exists() {
        return;
    }
    for args in [
        vec!["info", "lens-data/double-gauss-50mm.json"],
        vec!["info", "lens-data/double-gauss-50mm.json", "--json"],
        vec!["fan", "lens-data/double-gauss-50mm.json", "--json"],
        vec!["spot", "lens-data/double-gauss-50mm.json"],
        vec!["validate", "lens-data/double-gauss-50mm.json"],
        vec!["convert", "lens-data/double-gauss-50mm.json"],
        vec!["coc", "lens-data/double-gauss-50mm.json", "--focus-mm", "2000", "--distances", "1000"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_lens"))
            .args(&args)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .stdout(std::fs::File::create(full).unwrap())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("cannot write to standard output"), "{args:?}: {err}");
    }
}

#[test]
fn glass_json_has_the_contract_keys() {
    let (code, out, err) = lens(&["glass", "SCHOTT:N-BK7", "--wavelength-nm", "486.1327", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["catalog"], "SCHOTT");
    assert_eq!(v["name"], "N-BK7");
    assert!(v["formula"].is_string());
    assert!((v["nd"].as_f64().unwrap() - 1.5168).abs() < 5e-6);
    assert!((v["vd"].as_f64().unwrap() - 64.17).abs() < 0.01);
    assert!((v["n"].as_f64().unwrap() - 1.52238).abs() < 5e-6);
    assert_eq!(v["range_nm"][0].as_f64(), Some(300.0));
    let (code, _, err) = lens(&["glass", "SCHOTT:N-BK8"]);
    assert_eq!(code, 1);
    assert!(err.contains("N-BK7"), "{err}");
}

/// Every plotting flag parses and writes its picture (SVG).
#[test]
fn plots_are_written() {
    let dir = std::env::temp_dir().join(format!("lens-plots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = |name: &str| dir.join(name).display().to_string();
    let dg = "lens-data/double-gauss-50mm.json";
    for args in [
        vec!["fan", dg, "--plot-fields", "0,10", "--plot", &out("fan.svg")],
        vec!["spot", dg, "--plot-fields", "0,10", "--plot", &out("spot.svg")],
        vec!["coc", dg, "--focus-mm", "2000", "--distances", "1000,inf", "--plot", &out("coc.svg")],
        vec!["field", dg, "--plot", &out("field.svg")],
        vec!["layout", dg, "--fields", "0,10", "-o", &out("layout.svg")],
        vec!["glass", "SCHOTT:N-BK7", "--plot", &out("glass.svg")],
        vec!["glass", "--map", "--plot", &out("map.svg")],
    ] {
        let (code, _, err) = lens(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        let svg = std::fs::read_to_string(args.last().unwrap()).unwrap();
        assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "{args:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lens study`: a labelled grid, rows and columns changing settings; a bad
/// setting names its row or column.
#[test]
fn a_study_renders_a_labelled_grid() {
    let d = std::env::temp_dir().join(format!("lens-study-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = root.join("lens-data/scenes/dof-study.json");
    let study = d.join("s.json");
    std::fs::write(
        &study,
        format!(
            r#"{{"title": "apertures", "scene": "{}", "set": {{"width": 40, "height": 24, "spp": 2}},
                "rows": [{{"label": "focus 7 m", "set": {{"focus_distance": 7}}}}],
                "columns": [{{"label": "0 m", "set": {{"aperture": 0}}}}, {{"label": "0.5 m", "set": {{"aperture": 0.5}}}}]}}"#,
            scene.display()
        ),
    )
    .unwrap();
    let out = d.join("m.png");
    let r = Command::new(env!("CARGO_BIN_EXE_lens"))
        .args(["study", study.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let png = std::fs::read(&out).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // a bad setting is refused naming the column
    std::fs::write(
        &study,
        format!(
            r#"{{"title": "t", "scene": "{}", "rows": [{{"label": "r"}}],
                "columns": [{{"label": "c", "set": {{"aperture_shape": "hexagon"}}}}]}}"#,
            scene.display()
        ),
    )
    .unwrap();
    let r = Command::new(env!("CARGO_BIN_EXE_lens"))
        .args(["study", study.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1));
    assert!(err.contains("columns[0].set.aperture_shape"), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}

/// A wavelength a little outside a glass's stated data (HIKARI SK16:
/// 400-700 nm; the He r-line at 706.5188 nm) is computed with the formula
/// and warned about, on stderr and in the JSON's `warnings`, naming glass,
/// range and wavelength; `--strict-glass-range` refuses it; so do renders.
#[test]
fn glass_outside_its_data_is_extrapolated_with_a_warning() {
    let dir = std::env::temp_dir().join(format!("lens-cli-range-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sk16.json");
    std::fs::write(
        &file,
        r#"{"surfaces": [
  {"radius": 51.5, "thickness": 3.6, "glass": "HIKARI:SK16", "semi_diameter": 12.7, "stop": true},
  {"radius": -200, "thickness": 80, "semi_diameter": 12.7}]}"#,
    )
    .unwrap();
    let f = file.to_str().unwrap();
    for args in [
        vec!["info", f, "--wavelength-nm", "706.5188", "--json"],
        vec!["fan", f, "--wavelength-nm", "706.5188", "--json"],
        vec!["glass", "HIKARI:SK16", "--wavelength-nm", "706.5188", "--json"],
    ] {
        let (code, out, err) = lens(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(err.contains("warning: HIKARI:SK16: 706.5188 nm is outside the glass's data (400 to 700 nm)"), "{err}");
        let w = &json(&out)["warnings"][0];
        assert_eq!(w["kind"], "glass_range", "{args:?}: {out}");
        assert_eq!(w["glass"], "HIKARI:SK16");
        assert_eq!(w["range_nm"], serde_json::json!([400.0, 700.0]));
        assert_eq!(w["wavelength_nm"].as_f64(), Some(706.5188));
        let mut strict = args.clone();
        strict.push("--strict-glass-range");
        let (code, _, err) = lens(&strict);
        assert_eq!(code, 1, "{strict:?}");
        assert!(err.contains("HIKARI:SK16") && err.contains("706.5188 nm is outside") && err.contains("400 to 700"));
    }
    // inside the data: no warnings key
    let (code, out, _) = lens(&["info", f, "--json"]);
    assert_eq!(code, 0);
    assert!(json(&out).get("warnings").is_none(), "{out}");
    // a render at one wavelength past N-SF11's 370 nm
    let png = dir.join("p.png");
    let p = png.to_str().unwrap();
    let scene = "lens-data/scenes/prism.json";
    let small = ["--width", "16", "--height", "9", "--spp", "1"];
    let (code, _, err) = lens(&[&["render", scene, "-o", p, "--wavelength-nm", "365"][..], &small].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("SCHOTT:N-SF11: 365 nm is outside the glass's data (370 to 2500 nm)"), "{err}");
    let (code, _, err) =
        lens(&[&["render", scene, "-o", p, "--wavelength-nm", "365", "--strict-glass-range"][..], &small].concat());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("film.wavelength_nm") && err.contains("N-SF11"), "{err}");
    // spectral: 360-830 extrapolated, or narrowed to the data when strict
    let (code, _, err) = lens(&[&["render", scene, "-o", p][..], &small].concat());
    assert!(code == 0 && err.contains("spectral 360-830 nm") && err.contains("N-SF11: 360 nm"), "{err}");
    let (code, _, err) = lens(&[&["render", scene, "-o", p, "--strict-glass-range"][..], &small].concat());
    assert!(code == 0 && err.contains("spectral 370-830 nm") && !err.contains("warning"), "{err}");
}

/// `spot` takes every wavelength of the prescription with its weight
/// unless given one; fans and spots name the plane they are on.
#[test]
fn spot_defaults_to_every_wavelength_on_the_image_surface() {
    let (code, out, err) = lens(&["spot", "lens-data/achromat-doublet-100mm.json", "--field-deg", "2", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["wavelengths_nm"], serde_json::json!([486.1327, 587.5618, 656.2725]));
    assert_eq!(v["wavelength_weights"], serde_json::json!([1.0, 1.0, 1.0]));
    assert_eq!(v["image_plane"], "image_surface");
    let (_, out, _) = lens(&[
        "spot",
        "lens-data/achromat-doublet-100mm.json",
        "--field-deg",
        "2",
        "--wavelength-nm",
        "587.5618",
        "--film",
        "paraxial",
        "--json",
    ]);
    let one = json(&out);
    assert_eq!(one["wavelengths_nm"], serde_json::json!([587.5618]));
    assert_eq!(one["image_plane"], "paraxial");
    assert!(one["image_z"].as_f64() > v["image_z"].as_f64());
    let (_, text, _) = lens(&["fan", "lens-data/achromat-doublet-100mm.json", "--film", "paraxial"]);
    assert!(text.starts_with("ray fan at 0 deg on the paraxial image plane, z = "), "{text}");
    let (_, text, _) = lens(&["spot", "lens-data/achromat-doublet-100mm.json"]);
    assert!(text.contains("on the prescription's image surface, z = 103.568000 mm"), "{text}");
    assert!(text.contains("486.1327 (weight 1), 587.5618 (weight 1), 656.2725 (weight 1)"), "{text}");
}

/// Settings that render but are likely mistakes are warned about: a focus
/// distance in mm where the scene is in metres, a lens whose image circle
/// leaves the film's corners black; the closing line says the camera's
/// settings with units.
#[test]
fn render_warns_of_silent_traps_and_echoes_the_camera() {
    let dir = std::env::temp_dir().join(format!("lens-cli-traps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("t.png");
    let small = ["--width", "32", "--height", "18", "--spp", "1", "-o", png.to_str().unwrap()];
    let scene = "lens-data/scenes/dof-study.json";
    let (code, _, err) = lens(&[&["render", scene, "--focus-distance", "2000"][..], &small].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: the plane in focus, 2000 m away, lies beyond every object"), "{err}");
    assert!(err.contains("2000 mm would be 2 m"), "{err}");
    assert!(err.contains("camera: thin lens, aperture 100 mm, focus 2000 m"), "{err}");
    let (code, _, err) = lens(&[&["render", scene, "--focus-distance", "9"][..], &small].concat());
    assert!(code == 0 && !err.contains("warning"), "{err}");
    let lens85 = "lens-data/library/nikkor-85mm-f1.8-us4812027.json";
    let (code, _, err) = lens(&[&["render", scene, "--camera", "lens", "--prescription", lens85][..], &small].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("image circle does not cover the film: no ray from 4 of its 4 corners"), "{err}");
    assert!(err.contains("f = 84.8692 mm, f/1.8, focus 7 m, sensor"), "{err}");
    let (_, _, err) = lens(&[&["render", "lens-data/scenes/dof-double-gauss-f2.json"][..], &small].concat());
    assert!(!err.contains("warning") && err.contains("f = 50.3582 mm, f/2, focus 7 m, sensor 36 x 20.25 mm"), "{err}");
}

/// `--passes` writes the named channels into the EXR output and refuses
/// an output that is not EXR, an unknown pass, and a report, by name.
#[test]
fn render_passes_go_into_the_exr() {
    let dir = std::env::temp_dir().join(format!("lens-cli-passes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (png, exr) = (dir.join("t.png"), dir.join("t.exr"));
    let scene = "lens-data/scenes/dof-double-gauss-f2.json";
    let small = ["--width", "32", "--height", "18", "--spp", "1"];
    let (code, _, err) =
        lens(&[&["render", scene, "-o", png.to_str().unwrap(), "--passes", "depth,coc"][..], &small].concat());
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("--passes: the passes are channels of an OpenEXR file; give -o OUT.exr or --exr"), "{err}");
    let (code, _, err) =
        lens(&[&["render", scene, "-o", exr.to_str().unwrap(), "--passes", "depth,blur"][..], &small].concat());
    assert!(code == 2 && err.contains("unknown pass \"blur\""), "{err}");
    let (code, _, err) = lens(
        &[
            &["render", scene, "-o", png.to_str().unwrap(), "--exr", exr.to_str().unwrap(), "--passes", "depth,normal"]
                [..],
            &small,
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    assert!(png.exists());
    let meta = exr::meta::MetaData::read_from_file(&exr, false).unwrap();
    let names: Vec<String> = meta.headers[0].channels.list.iter().map(|c| c.name.to_string()).collect();
    assert_eq!(names, ["B", "G", "N.x", "N.y", "N.z", "R", "Z"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--focus-on` focuses on a pixel and says so; it cannot be given with
/// `--focus-distance`, and a pixel on the background is refused.
#[test]
fn render_focus_on_a_pixel() {
    let dir = std::env::temp_dir().join(format!("lens-cli-focus-on-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("t.png");
    let scene = "lens-data/scenes/dof-study.json";
    let small = ["--width", "32", "--height", "18", "--spp", "1", "-o", png.to_str().unwrap()];
    let (code, _, err) = lens(&[&["render", scene, "--focus-on", "16,10"][..], &small].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("(autofocus on pixel (16, 10), "), "{err}");
    let (code, _, err) =
        lens(&[&["render", scene, "--focus-on", "16,10", "--focus-distance", "3"][..], &small].concat());
    assert!(code == 2 && err.contains("cannot be used with"), "{err}");
    let (code, _, err) = lens(&[&["render", scene, "--focus-on", "16,0"][..], &small].concat());
    assert!(code == 1 && err.contains("camera.focus_on: pixel (16, 0) sees the background"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `lens animate` writes one file per frame, skips finished ones with
/// `--resume`, and refuses a name without the frame number.
#[test]
fn animate_writes_frames_and_resumes() {
    let dir = std::env::temp_dir().join(format!("lens-cli-animate-{}", std::process::id()));
    let pattern = dir.join("f%03d.png");
    let scene = "lens-data/scenes/focus-pull-portrait.json";
    let small = ["--frames", "3", "--width", "16", "--spp", "1", "-o", pattern.to_str().unwrap()];
    let (code, _, err) = lens(&[&["animate", scene][..], &small].concat());
    assert_eq!(code, 0, "{err}");
    for k in 0..3 {
        assert!(dir.join(format!("f{k:03}.png")).exists(), "frame {k}");
    }
    std::fs::remove_file(dir.join("f001.png")).unwrap();
    let (code, _, err) = lens(&[&["animate", scene, "--resume"][..], &small].concat());
    assert!(code == 0 && err.contains("resuming: 2 of 3 frames already written"), "{err}");
    assert!(dir.join("f001.png").exists());
    let (code, _, err) = lens(&["animate", scene, "-o", dir.join("f.png").to_str().unwrap()]);
    assert!(code == 1 && err.contains("%04d"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A study runs from any folder (its scene, masks and prescriptions are
/// relative to the study file) and takes the film and thread flags `render`
/// takes, for every cell.
#[test]
fn study_takes_render_flags_from_any_folder() {
    let dir = std::env::temp_dir().join(format!("lens-cli-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study =
        std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/studies/dof-apertures.json"));
    let png = dir.join("s.png");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lens"))
        .args(["study", study.to_str().unwrap(), "-o", png.to_str().unwrap()])
        .args(["--width", "40", "--height", "20", "--spp", "1", "--threads", "2"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let img = std::fs::read(&png).unwrap();
    // 2 rows of 20 px cells and 4 columns of 40 px: the picture is small
    let (w, h) =
        (u32::from_be_bytes(img[16..20].try_into().unwrap()), u32::from_be_bytes(img[20..24].try_into().unwrap()));
    assert!(w < 1100 && h == 46 + 30 + 2 * 20 + 3 * 6, "{w} x {h}");
    let (code, _, err) = lens(&["study", study.to_str().unwrap(), "-o", png.to_str().unwrap(), "--threads", "0"]);
    assert!(code == 1 && err.contains("--threads 0"), "{err}");
}

#[test]
fn wavefront_json_has_the_contract_keys_and_refuses_a_coarse_grid() {
    let (code, out, err) = lens(&["wavefront", "lens-data/double-gauss-50mm.json", "--field-deg", "5", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    for k in [
        "rms_waves",
        "pv_waves",
        "rms_centroid_waves",
        "pv_centroid_waves",
        "strehl",
        "exit_pupil_mm",
        "reference_radius_mm",
    ] {
        assert!(v[k].as_f64().is_some_and(f64::is_finite), "{k} in {v}");
    }
    assert_eq!(v["zernike_fringe"].as_array().unwrap().len(), 37);
    assert_eq!(v["zernike_standard"].as_array().unwrap().len(), 37);
    assert!(v["zernike_standard_order"].as_str().unwrap().contains("Noll"));
    // the default grid grows where the wavefront needs it
    assert!(v["pupil_samples"].as_u64().unwrap() >= 64);
    let (rms, centroid) = (v["rms_waves"].as_f64().unwrap(), v["rms_centroid_waves"].as_f64().unwrap());
    assert!(centroid <= rms && rms > 0.1 && v["strehl"].as_f64().unwrap() < 1.0);
    // a grid asked for that is too coarse: refused, with one that is not
    let (code, _, err) =
        lens(&["wavefront", "lens-data/plano-convex-singlet.json", "--grid", "32", "--field-deg", "0"]);
    assert_eq!(code, 1);
    assert!(err.contains("half a wave") && err.contains("grid of at least"), "{err}");
}

#[test]
fn mtf_json_has_the_contract_keys_and_refuses_bad_frequencies() {
    let (code, out, err) =
        lens(&["mtf", "lens-data/double-gauss-50mm.json", "--field-deg", "10", "--frequencies", "10,20,40", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["frequencies_per_mm"].as_array().unwrap().len(), 3);
    for k in ["tangential", "sagittal"] {
        let m: Vec<f64> = v[k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert_eq!(m.len(), 3);
        assert!(m.iter().all(|x| (0.0..=1.0).contains(x)), "{k}: {m:?}");
        let limit: Vec<f64> =
            v["diffraction_limit"][k].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert!(m.iter().zip(&limit).all(|(a, b)| a <= &(b + 1e-9)), "{k} above its diffraction limit");
    }
    for k in ["cutoff_per_mm", "cutoff_tangential_per_mm", "cutoff_sagittal_per_mm"] {
        assert!(v[k].as_f64().unwrap() > 500.0, "{k}");
    }
    for bad in ["0", "-10", "5000"] {
        let (code, _, err) = lens(&["mtf", "lens-data/double-gauss-50mm.json", "--frequencies", bad]);
        assert_eq!(code, 1, "{bad}");
        assert!(err.contains("frequency"), "{bad}: {err}");
    }
    // the geometric MTF of a badly aberrated field is near the diffraction one
    let (code, out, err) = lens(&[
        "mtf",
        "lens-data/double-gauss-50mm.json",
        "--field-deg",
        "10",
        "--frequencies",
        "10",
        "--geometric",
        "--polychromatic",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["wavelengths_nm"].as_array().unwrap().len(), 3);
    let (g, d) = (v["geometric"]["tangential"][0].as_f64().unwrap(), v["tangential"][0].as_f64().unwrap());
    assert!((g - d).abs() < 0.05, "geometric {g} against diffraction {d}");
    let (code, out, err) =
        lens(&["mtf", "lens-data/double-gauss-50mm.json", "--vs-field", "--frequencies", "10,30", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["fields_deg"].as_array().unwrap().len(), 11);
    assert_eq!(v["tangential"].as_array().unwrap().len(), 2);
}

#[test]
fn psf_json_has_its_keys_and_writes_an_exr() {
    let dir = std::env::temp_dir().join(format!("lens-psf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("psf.exr");
    for method in ["fft", "huygens"] {
        let (code, out, err) = lens(&[
            "psf",
            "lens-data/double-gauss-50mm.json",
            "--method",
            method,
            "--pixels",
            "32",
            "--json",
            "--exr",
            exr.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{method}: {err}");
        let v = json(&out);
        assert_eq!(v["method"], method);
        let strehl = v["strehl"].as_f64().unwrap();
        let peak = v["peak"].as_f64().unwrap();
        // the grid's largest pixel never above the off-grid peak
        assert!(peak <= strehl + 1e-9 && strehl > 0.0 && strehl < 1.0, "{method}: {peak} {strehl}");
        let ee: Vec<f64> =
            v["encircled_energy"]["fraction"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        assert!(ee.windows(2).all(|w| w[1] >= w[0]) && *ee.last().unwrap() <= 1.0 + 1e-9, "{method}: {ee:?}");
        let geo: Vec<f64> = v["geometric_encircled_energy"]["fraction"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(geo.windows(2).all(|w| w[1] >= w[0]) && *geo.last().unwrap() <= 1.0 + 1e-9, "{method}: {geo:?}");
        assert!(v["pixel_x_mm"].as_f64().unwrap() > 0.0 && v["size"].as_u64().unwrap() >= 32);
        assert!(std::fs::metadata(&exr).unwrap().len() > 1000);
    }
    let (code, _, err) = lens(&["psf", "lens-data/double-gauss-50mm.json", "--pad", "1"]);
    assert_eq!(code, 1);
    assert!(err.contains("--pad"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lens optimize` on the shipped design: the JSON keys of the issue, the
/// designed file and the report with its pictures written, and each
/// operand's value the number the analysis commands print for the designed
/// lens (EFL from `lens info`, RMS spot from `lens spot`, the same rings
/// and wavelengths, on its image surface).
#[test]
fn optimize_json_contract_and_values_match_the_analyses() {
    let dir = std::env::temp_dir().join(format!("lens-optimize-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("designed.json");
    let report = dir.join("report.md");
    let (code, stdout, err) = lens(&[
        "optimize",
        "lens-data/design/cooke-triplet.design.json",
        "-o",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&stdout);
    for k in ["merit_start", "merit_end", "seconds"] {
        assert!(v[k].is_f64(), "{k} missing in {v}");
    }
    assert!(v["iterations"].is_u64());
    assert!(v["merit_end"].as_f64().unwrap() < 0.1 * v["merit_start"].as_f64().unwrap(), "{v}");
    let ops = v["operands"].as_array().unwrap();
    assert_eq!(ops.len(), 6);
    assert_eq!(ops[0]["type"], "efl");
    assert!(ops.iter().all(|o| o["value"].is_f64() && o["type"].is_string()), "{v}");
    assert!(ops[4]["target"].is_null() && ops[4]["min"] == 1.0, "{v}");
    for f in ["report.md", "report-spot-start.png", "report-spot-end.png", "report-mtf-start.png", "report-mtf-end.png"]
    {
        assert!(dir.join(f).metadata().is_ok_and(|m| m.len() > 100), "{f} not written");
    }
    let designed = out.to_str().unwrap();
    let (code, info, err) = lens(&["info", designed, "--json"]);
    assert_eq!(code, 0, "{err}");
    let efl = json(&info)["efl"].as_f64().unwrap();
    assert!((efl - ops[0]["value"].as_f64().unwrap()).abs() < 1e-12 * efl);
    for (k, field) in [(1, "0"), (3, "14")] {
        let (code, spot, err) = lens(&["spot", designed, "--field-deg", field, "--json"]);
        assert_eq!(code, 0, "{err}");
        let rms = json(&spot)["rms_radius"].as_f64().unwrap();
        let op = ops[k]["value"].as_f64().unwrap();
        assert!((rms - op).abs() <= 1e-12 * rms, "field {field}: spot {rms} vs operand {op}");
    }
    // evaluating only: the start's merit, nothing changed
    let (code, stdout, err) =
        lens(&["optimize", "lens-data/design/cooke-triplet.design.json", "--max-iterations", "0", "--json"]);
    assert_eq!(code, 0, "{err}");
    let w = json(&stdout);
    assert_eq!(w["merit_start"], w["merit_end"]);
    assert_eq!(w["merit_start"], v["merit_start"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A bad design file is refused with exit code 1, the operand named, and
/// nothing written.
#[test]
fn optimize_refuses_a_bad_design() {
    let dir = std::env::temp_dir().join(format!("lens-optimize-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spec = dir.join("bad.json");
    let start = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/cooke-triplet.json");
    std::fs::write(
        &spec,
        format!(
            r#"{{"prescription": "{}", "variables": [{{"surface": 1, "param": "radius"}}],
                "operands": [{{"type": "f_number", "target": 0.2}}]}}"#,
            start.display()
        ),
    )
    .unwrap();
    let out = dir.join("designed.json");
    let (code, _, err) = lens(&["optimize", spec.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("operand 1 (f_number)") && err.contains("f/0.5"), "{err}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `lens tolerance`: the JSON keys, the picture, and shares that merge
/// into the one run's statistics exactly; a share out of range refused.
#[test]
fn tolerance_json_contract_and_shares_merge_to_the_whole_run() {
    let dir = std::env::temp_dir().join(format!("lens-tolerance-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spec = "lens-data/design/cooke-triplet.tolerance.json";
    let plot = dir.join("yield.png");
    let (code, out, err) =
        lens(&["tolerance", spec, "--trials", "90", "--seed", "4", "--json", "--plot", plot.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let whole = json(&out);
    assert!(whole["nominal"].is_f64() && whole["seconds"].is_f64(), "{whole}");
    let mc = &whole["monte_carlo"];
    for k in ["mean", "std", "yield"] {
        assert!(mc[k].is_f64(), "{k} missing in {mc}");
    }
    for k in ["p10", "p50", "p90", "p98"] {
        assert!(mc["percentiles"][k].is_f64(), "{k} missing in {mc}");
    }
    assert_eq!(mc["trials"], 90);
    assert_eq!(whole["sensitivity"].as_array().unwrap().len(), 16);
    assert!(plot.metadata().is_ok_and(|m| m.len() > 1000));
    let mut shares = Vec::new();
    for i in 1..=2 {
        let share = dir.join(format!("share{i}.json"));
        let (code, _, err) = lens(&[
            "tolerance",
            spec,
            "--trials",
            "90",
            "--seed",
            "4",
            "--shard",
            &format!("{i}/2"),
            "-o",
            share.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        shares.push(share.to_str().unwrap().to_string());
    }
    let (code, out, err) = lens(&["tolerance", "merge", spec, &shares[1], &shares[0], "--json"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(json(&out)["monte_carlo"], whole["monte_carlo"]);
    let (code, _, err) = lens(&["tolerance", "merge", spec, &shares[1]]);
    assert_eq!(code, 1);
    assert!(err.contains("in no share"), "{err}");
    let (code, _, err) = lens(&["tolerance", spec, "--shard", "5/4", "-o", dir.join("x.json").to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("1 <= I <= N"), "{err}");
    let (code, _, err) = lens(&["tolerance", spec, "--trials", "1000000000000"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("give 1 to 100000000"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn fields_in_x_are_taken_by_the_field_analyses_and_named() {
    // an x field of a symmetric lens lands on +x as the y field lands on +y
    let dg = "lens-data/double-gauss-50mm.json";
    let run = |args: &[&str]| {
        let (code, out, err) = lens(args);
        assert_eq!(code, 0, "{args:?}: {err}");
        json(&out)
    };
    let x = run(&["spot", dg, "--field-x-deg", "10", "--json"]);
    let y = run(&["spot", dg, "--field-deg", "10", "--json"]);
    assert_eq!((x["field_x_deg"].as_f64(), x["field_deg"].as_f64()), (Some(10.0), Some(0.0)));
    assert!(y.get("field_x_deg").is_none(), "a y field's report keeps its keys");
    assert!((x["chief"][0].as_f64().unwrap() - y["chief"][1].as_f64().unwrap()).abs() < 1e-12);
    assert!((x["rms_radius"].as_f64().unwrap() - y["rms_radius"].as_f64().unwrap()).abs() < 1e-12);
    let fan = run(&["fan", dg, "--field-x-deg", "-4", "--field-deg", "3", "--json", "--points", "5"]);
    assert_eq!((fan["field_x_deg"].as_f64(), fan["field_deg"].as_f64()), (Some(-4.0), Some(3.0)));
    assert!(fan["chief"][0].as_f64().unwrap() < -3.0 && fan["chief"][1].as_f64().unwrap() > 2.0, "{}", fan["chief"]);
    for cmd in [
        &["wavefront", dg, "--field-x-deg", "5", "--json"][..],
        &["mtf", dg, "--field-x-deg", "5", "--json"],
        &["psf", dg, "--field-x-deg", "5", "--json"],
    ] {
        assert_eq!(run(cmd)["field_x_deg"].as_f64(), Some(5.0), "{cmd:?}");
    }
    let (code, out, _) = lens(&["spot", dg, "--field-x-deg", "2", "--field-deg", "3"]);
    assert_eq!(code, 0);
    assert!(out.contains("spot at x 2 deg, y 3 deg"), "{out}");
    // where only y fields are defined the flag is refused by name
    for (args, what) in [
        (&["chromatic", dg, "--field-x-deg", "5"][..], "lens chromatic"),
        (&["mtf", dg, "--field-x-deg", "5", "--vs-field"], "--vs-field"),
        (&["fan", dg, "--field-x-deg", "5", "--plot", "/tmp/never.svg", "--plot-fields", "0,5"], "--plot-fields"),
        (&["spot", dg, "--field-x-deg", "95"], "--field-x-deg"),
    ] {
        let (code, _, err) = lens(args);
        assert_eq!(code, 1, "{args:?}");
        assert!(err.contains(what) && err.contains("--field-x-deg"), "{args:?}: {err}");
    }
}

#[test]
fn convert_writes_codev_and_pbrt_lens_files() {
    let dir = std::env::temp_dir().join(format!("lens-convert-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let seq = dir.join("dg.seq");
    let dat = dir.join("dg.dat");
    let (code, _, err) = lens(&["convert", "lens-data/double-gauss-50mm.json", "-o", seq.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let info = |path: &str| {
        let (code, out, err) = lens(&["info", path, "--json"]);
        assert_eq!(code, 0, "{err}");
        json(&out)
    };
    let (a, b) = (info("lens-data/double-gauss-50mm.json"), info(seq.to_str().unwrap()));
    assert!((a["efl"].as_f64().unwrap() - b["efl"].as_f64().unwrap()).abs() < 1e-12 * 50.0);
    // pbrt-v4 has no dispersion: a lens with glasses needs a wavelength
    let (code, _, err) = lens(&["convert", "lens-data/double-gauss-50mm.json", "-o", dat.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("--wavelength-nm") && !dat.exists(), "{err}");
    let (code, _, err) = lens(&[
        "convert",
        "lens-data/double-gauss-50mm.json",
        "-o",
        dat.to_str().unwrap(),
        "--wavelength-nm",
        "587.5618",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&dat).unwrap();
    assert!(text.contains("indices at 587.5618 nm") && text.lines().filter(|l| !l.starts_with('#')).count() == 11);
    let (code, _, err) =
        lens(&["convert", "lens-data/double-gauss-50mm.json", "-o", seq.to_str().unwrap(), "--wavelength-nm", "500"]);
    assert_eq!(code, 1);
    assert!(err.contains("only a pbrt-v4 .dat output"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `lens ghosts --json`: every two-reflection ghost with the contract keys
/// (surfaces numbered from 1, i < j), and the plot written; a bad field is
/// an error naming the flag.
#[test]
fn ghosts_json_lists_every_pair_with_the_contract_keys() {
    let (code, out, err) = lens(&["ghosts", "lens-data/double-gauss-50mm.json", "--field-deg", "10", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let ghosts = v["ghosts"].as_array().unwrap();
    // 10 glass-air or cemented surfaces and a stop in air: 10 * 9 / 2 pairs
    assert_eq!(ghosts.len(), 45);
    for g in ghosts {
        let s = g["surfaces"].as_array().unwrap();
        assert!(s[0].as_u64().unwrap() >= 1 && s[0].as_u64() < s[1].as_u64(), "{g}");
        for k in ["focus_z_mm", "image_height_mm", "radius_mm", "intensity"] {
            assert!(g.get(k).is_some(), "{k} missing: {g}");
        }
        assert!(g["radius_mm"].as_f64().unwrap() >= 0.0);
        let i = g["intensity"].as_f64().unwrap();
        assert!(i > 0.0 && i < 0.01, "{g}");
    }
    let dir = std::env::temp_dir().join(format!("lens-ghosts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let plot = dir.join("ghosts.svg");
    let (code, _, err) =
        lens(&["ghosts", "lens-data/double-gauss-50mm.json", "--field-deg", "5", "--plot", plot.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(&plot).unwrap().contains("<svg"));
    let (code, _, err) = lens(&["ghosts", "lens-data/double-gauss-50mm.json", "--field-deg", "95"]);
    assert_eq!(code, 1);
    assert!(err.contains("--field-deg"), "{err}");
}
