//! Hostile and extreme input, one test per class of failure (issue 13): no
//! command panics, runs without bound, writes over its input, leaves a
//! partial output or writes inf/NaN; each refusal is exit 1 with a message
//! that names the flag, field or surface and what to change. The cases are
//! examples of their class; the fixes are for the class.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lens-hostile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn lens(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lens")).args(args).current_dir(root()).output().unwrap()
}

/// Runs `args`, expects exit 1 and a message (on stderr, or for
/// `validate` its report) containing every one of `words`; never a panic
/// (101) or a signal.
fn refused(args: &[&str], words: &[&str]) {
    let out = lens(args);
    let err = String::from_utf8_lossy(&out.stderr).to_string() + &String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{args:?}: exit {:?}, stderr: {err}", out.status);
    for w in words {
        assert!(err.contains(w), "{args:?}: the message lacks {w:?}: {err}");
    }
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    short_numbers(&err);
}

/// Every number in `text` has at most 17 significant digits (what it takes
/// to write any f64 exactly): no 309-digit focal lengths, no 300 zeros.
fn short_numbers(text: &str) {
    for token in text.split(|c: char| !(c.is_ascii_digit() || c == '.')) {
        let digits: String = token.chars().filter(char::is_ascii_digit).collect();
        let significant = digits.trim_start_matches('0');
        assert!(significant.len() <= 17 && digits.len() <= 24, "a number of {} digits: {token}\n{text}", digits.len());
    }
}

const DG: &str = "lens-data/double-gauss-50mm.json";

#[test]
fn outputs_are_checked_before_any_work() {
    let d = scratch("outputs");
    let scene = "lens-data/scenes/dof-pinhole.json";
    let missing = d.join("no/such/folder/x.png");
    refused(&["render", scene, "-o", missing.to_str().unwrap()], &["-o", "does not exist"]);
    let x_png = d.join("x.png");
    let x_jpg = d.join("x.jpg");
    // the second output's bad format is found before the first is written
    refused(&["render", scene, "-o", x_png.to_str().unwrap(), "--exr", x_jpg.to_str().unwrap()], &["--exr", ".exr"]);
    assert!(!x_png.exists(), "a partial output stayed behind");
    refused(&["layout", DG, "-o", d.join("l.gif").to_str().unwrap()], &["-o", ".svg or .png"]);
    refused(&["fan", DG, "--plot", d.to_str().unwrap()], &["--plot"]);
}

#[test]
fn no_output_overwrites_an_input() {
    let d = scratch("inputs");
    let scene = d.join("s.json");
    std::fs::copy(root().join("lens-data/scenes/dof-pinhole.json"), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let out_png = d.join("o.png");
    refused(&["render", scene.to_str().unwrap(), "-o", scene.to_str().unwrap()], &["-o"]);
    let report_on_image = d.join("r.md");
    let plot_png = d.join("r-plot.png");
    refused(
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            plot_png.to_str().unwrap(),
            "--report",
            report_on_image.to_str().unwrap(),
            "--spp",
            "2",
        ],
        &["give each output its own file"],
    );
    assert_eq!(std::fs::read(&scene).unwrap(), before, "the scene was overwritten");
    assert!(!out_png.exists());
    let lens_copy = d.join("dg.json");
    std::fs::copy(root().join(DG), &lens_copy).unwrap();
    let p = lens_copy.to_str().unwrap();
    refused(&["convert", p, "-o", p], &["is an input"]);
    refused(&["fan", p, "--plot", p], &["--plot"]);
    assert_eq!(std::fs::read(&lens_copy).unwrap(), std::fs::read(root().join(DG)).unwrap());
}

#[test]
fn sizes_are_bounded_with_the_limit_named() {
    refused(&["validate", "/dev/zero"], &["MiB"]);
    refused(&["optimize", "/dev/zero"], &["MiB"]);
    refused(&["tolerance", "/dev/zero"], &["MiB"]);
    // a design file that is no JSON, and one whose output is its input
    refused(&["optimize", "lens-data/cooke-triplet.json"], &["line", "column"]);
    refused(
        &["optimize", "lens-data/design/cooke-triplet.design.json", "-o", "lens-data/design/cooke-triplet.design.json"],
        &["is an input"],
    );
    let d = scratch("sizes");
    let r = d.join("r.png");
    let md = d.join("r.md");
    refused(
        &[
            "render",
            "lens-data/scenes/report-pinhole.json",
            "-o",
            r.to_str().unwrap(),
            "--report",
            md.to_str().unwrap(),
            "--spp",
            "2147483648",
        ],
        &["--spp", "1048576"],
    );
    refused(
        &["render", "lens-data/scenes/dof-pinhole.json", "-o", r.to_str().unwrap(), "--threads", "5000"],
        &["--threads", "256"],
    );
    let big = d.join("big.json");
    std::fs::write(
        &big,
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40},
            "film": {"width": 16384, "height": 16384}}"#,
    )
    .unwrap();
    refused(&["render", big.to_str().unwrap(), "-o", r.to_str().unwrap()], &["film", "pixels"]);
}

#[test]
fn impossible_numbers_are_refused_where_they_are_written() {
    let d = scratch("numbers");
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    // a subnormal radius would make the curvature infinite
    let sub = write(
        "sub.json",
        r#"{"surfaces": [{"radius": 1e-320, "thickness": 5, "ior": 1.5, "semi_diameter": 1e-321, "stop": true},
                         {"thickness": 50, "semi_diameter": 10}]}"#,
    );
    refused(&["info", &sub], &["surface 1", "radius"]);
    let ior = write(
        "ior.json",
        r#"{"surfaces": [{"radius": 50, "thickness": 5, "ior": 1e300, "semi_diameter": 10, "stop": true},
                         {"thickness": 50, "semi_diameter": 10}]}"#,
    );
    refused(&["info", &ior], &["surface 1", "ior"]);
    // a film inside the lens, field angles that are not angles
    refused(&["fan", DG, "--film=-5", "--json"], &["--film", "inside the lens"]);
    for f in ["90", "nan", ""] {
        refused(&["layout", DG, "--fields", f, "-o", d.join("l.svg").to_str().unwrap()], &["--fields"]);
    }
    // lights too bright for any image format
    let bright = write(
        "bright.json",
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40},
            "film": {"width": 8, "height": 8}, "background": {"type": "constant", "radiance": [1e308, 1, 1]}}"#,
    );
    refused(&["render", &bright, "-o", d.join("b.exr").to_str().unwrap()], &["background.radiance"]);
    let negative = write(
        "negative.json",
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40},
            "film": {"width": 8, "height": 8}, "background": {"type": "constant", "radiance": [-1, 1, 1]}}"#,
    );
    refused(&["render", &negative, "-o", d.join("n.exr").to_str().unwrap()], &["background.radiance"]);
    let f0 = write(
        "f0.json",
        r#"{"camera": {"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40,
                       "f_number": 0, "focal_length_mm": 50, "focus_distance": 2},
            "film": {"width": 8, "height": 8}}"#,
    );
    refused(&["render", &f0, "-o", d.join("f.png").to_str().unwrap()], &["camera.f_number"]);
    let far = write(
        "far.json",
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40},
            "film": {"width": 8, "height": 8},
            "materials": {"m": {"type": "diffuse", "color": [1, 1, 1]}},
            "shapes": [{"type": "sphere", "center": [0, 0, 1e200], "radius": 1e199, "material": "m"}]}"#,
    );
    refused(&["render", &far, "-o", d.join("far.png").to_str().unwrap()], &["shapes[0].center"]);
}

#[test]
fn extreme_but_finite_distances_behave_like_their_limit() {
    let d = scratch("limits");
    // a thin lens focused as far as f64 goes renders what focus at
    // infinity renders: finite pixels
    let scene = d.join("far-focus.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40,
                       "f_number": 2, "focal_length_mm": 50, "focus_distance": 1.7e308},
            "film": {"width": 16, "height": 16, "spp": 4},
            "background": {"type": "constant", "radiance": [0.5, 0.5, 0.5]},
            "materials": {"m": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "shapes": [{"type": "sphere", "center": [0, 0, 5], "radius": 1, "material": "m"}]}"#,
    )
    .unwrap();
    let out = lens(&["render", scene.to_str().unwrap(), "-o", d.join("f.png").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = lens(&["focus", DG, "--object-distance", "1e200", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("NaN") && !text.contains("inf") && !text.contains("null"), "{text}");
}

#[test]
fn malformed_files_get_one_plain_message() {
    let d = scratch("malformed");
    let write = |name: &str, bytes: &[u8]| {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        p.to_str().unwrap().to_string()
    };
    let arr = write("arr.json", b"[1, 2]");
    refused(&["info", &arr], &["one JSON object"]);
    let bad = write("bad.json", b"{\"surfaces\": [}");
    let out = lens(&["info", &bad]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.matches("column").count(), 1, "the position is stated once: {err}");
    // a byte-order mark is fine
    let mut bom = b"\xef\xbb\xbf".to_vec();
    bom.extend_from_slice(&std::fs::read(root().join(DG)).unwrap());
    let bom = write("bom.json", &bom);
    assert!(lens(&["info", &bom]).status.success());
    // a material defined twice, a mesh with no faces
    let dup = write(
        "dup.json",
        br#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40}, "film": {"width": 8, "height": 8},
            "materials": {"a": {"type": "diffuse", "color": [1,0,0]}, "a": {"type": "diffuse", "color": [0,1,0]}}}"#,
    );
    refused(&["render", &dup, "-o", d.join("d.png").to_str().unwrap()], &["\"a\" is defined twice"]);
    write("empty.obj", b"# nothing here\n");
    let mesh = write(
        "mesh.json",
        br#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40}, "film": {"width": 8, "height": 8},
            "materials": {"a": {"type": "diffuse", "color": [1,0,0]}}, "shapes": [{"type": "mesh", "obj": "empty.obj", "material": "a"}]}"#,
    );
    refused(&["render", &mesh, "-o", d.join("m.png").to_str().unwrap()], &["shapes[0].obj", "no faces"]);
}

#[test]
fn a_plot_stays_a_plot() {
    let d = scratch("plots");
    // three million rays draw about 20,000 points
    let svg = d.join("s.svg");
    let out = lens(&["spot", DG, "--pattern", "hexapolar", "--n", "1000", "--plot", svg.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let size = std::fs::metadata(&svg).unwrap().len();
    assert!(size < 5 << 20, "{size} bytes");
    // a control character in a lens's name leaves the SVG valid XML
    let p = d.join("ctl.json");
    std::fs::write(
        &p,
        "{\"name\": \"bad\\u0001name <&>\", \"surfaces\": [{\"radius\": 50, \"thickness\": 5, \"ior\": 1.5, \"semi_diameter\": 10, \"stop\": true}, {\"thickness\": 50, \"semi_diameter\": 10}]}",
    )
    .unwrap();
    let svg = d.join("ctl.svg");
    let out = lens(&["layout", p.to_str().unwrap(), "-o", svg.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(!text.chars().any(|c| (c as u32) < 0x20 && !"\t\n\r".contains(c)), "a control character reached the SVG");
    assert!(text.contains("&lt;&amp;&gt;"));
    assert!(!text.contains("NaN") && !text.contains("inf"), "non-finite numbers in the SVG");
}

#[test]
fn work_per_ray_and_per_run_is_bounded() {
    let d = scratch("work");
    let surfaces: Vec<String> = (0..1001)
        .map(|i| {
            let (r, n) = if i % 2 == 0 { (1000.0, 1.5) } else { (-1000.0, 1.0) };
            let stop = if i == 0 { ", \"stop\": true" } else { "" };
            format!("{{\"radius\": {r}, \"thickness\": 1, \"ior\": {n}, \"semi_diameter\": 10{stop}}}")
        })
        .collect();
    let many = d.join("many.json");
    std::fs::write(&many, format!("{{\"surfaces\": [{}]}}", surfaces.join(","))).unwrap();
    refused(&["bench", many.to_str().unwrap()], &["1001 surfaces", "at most 1000"]);
    let blades = d.join("blades.json");
    std::fs::write(
        &blades,
        r#"{"camera": {"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40, "aperture": 0.1,
                       "focus_distance": 2, "aperture_shape": {"shape": "polygon", "blades": 100000}},
            "film": {"width": 8, "height": 8}}"#,
    )
    .unwrap();
    refused(&["render", blades.to_str().unwrap(), "-o", d.join("b.png").to_str().unwrap()], &["blades", "64"]);
}

#[test]
fn decoder_errors_are_words_not_debug_dumps() {
    let d = scratch("decoders");
    std::fs::write(d.join("bad.png"), b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dageg\x00\x00").unwrap();
    let scene = d.join("mask.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"type": "thin_lens", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40, "aperture": 0.1,
                       "focus_distance": 2, "aperture_shape": {"shape": "mask", "image": "bad.png"}},
            "film": {"width": 8, "height": 8}}"#,
    )
    .unwrap();
    let out = lens(&["render", scene.to_str().unwrap(), "-o", d.join("m.png").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("camera.aperture_shape") && err.contains("\"ageg\""), "{err}");
    assert!(!err.contains("ChunkType {") && !err.contains("critical:"), "{err}");
}

#[test]
fn an_exr_declaring_a_huge_image_is_refused_before_allocation() {
    // 385 bytes whose header declares 40000 x 40000 pixels (a 1 x 1 image
    // with its data window rewritten)
    let d = scratch("exr");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/huge-header.exr"), d.join("huge.exr"))
        .unwrap();
    let scene = d.join("env.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40},
            "film": {"width": 8, "height": 8}, "background": {"type": "environment", "exr": "huge.exr"}}"#,
    )
    .unwrap();
    refused(
        &["render", scene.to_str().unwrap(), "-o", d.join("x.png").to_str().unwrap()],
        &["background.exr", "40000 x 40000"],
    );
}

#[test]
fn no_inf_or_nan_reaches_standard_output() {
    let d = scratch("stdout");
    // infinity is written as a word
    let out = lens(&["coc", DG, "--focus-mm", "2000", "--distances", "1000,inf"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("infinity") && !text.contains(" inf "), "{text}");
    // a stop too small to pass light is refused rather than given f/inf
    let p = d.join("tiny-stop.json");
    std::fs::write(
        &p,
        r#"{"surfaces": [{"radius": 50, "thickness": 5, "ior": 1.5, "semi_diameter": 1e-320, "stop": true},
                         {"thickness": 50, "semi_diameter": 10}]}"#,
    )
    .unwrap();
    refused(&["info", p.to_str().unwrap(), "--json"], &["surface 1", "semi_diameter"]);
}

/// An output that is a symbolic link keeps the link and writes its target
/// (a relative link to a file not there yet, a chain of links); a device
/// is refused before any work, or its write error is exit 1.
#[cfg(unix)]
#[test]
fn outputs_through_links_keep_the_link() {
    let d = scratch("links");
    std::fs::create_dir_all(d.join("renders")).unwrap();
    std::os::unix::fs::symlink("renders/x.png", d.join("latest.png")).unwrap();
    std::os::unix::fs::symlink(d.join("latest.png"), d.join("again.png")).unwrap();
    for (link, args) in [
        (
            "latest.png",
            vec!["render", "lens-data/scenes/dof-pinhole.json", "--width", "8", "--height", "8", "--spp", "1", "-o"],
        ),
        ("again.png", vec!["layout", DG, "-o"]),
    ] {
        let path = d.join(link);
        let out = lens(&[&args[..], &[path.to_str().unwrap()]].concat());
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(std::fs::symlink_metadata(&path).unwrap().file_type().is_symlink(), "{link} was replaced");
        let png = std::fs::read(d.join("renders/x.png")).unwrap();
        assert!(png.starts_with(b"\x89PNG"), "{link}");
    }
    assert_eq!(std::fs::read_dir(d.join("renders")).unwrap().count(), 1, "a temporary file stayed behind");
    if Path::new("/dev/full").exists() {
        refused(&["layout", DG, "-o", "/dev/full"], &["-o", "/dev/full"]);
        std::os::unix::fs::symlink("/dev/full", d.join("full.json")).unwrap();
        let full = d.join("full.json");
        refused(&["convert", DG, "-o", full.to_str().unwrap()], &["No space left"]);
    }
}

/// Numbers in messages and text reports are written compactly, whatever
/// their size: huge radii give a focal length of 1e308, not 309 digits; a
/// sphere of radius 1e33 m, a distance of 1e-300 mm, a field of 1e-300
/// degrees are echoed as such; a surface without a clear aperture says so.
#[test]
fn numbers_in_messages_are_compact() {
    let d = scratch("numbers");
    let huge = d.join("huge.json");
    std::fs::write(
        &huge,
        r#"{"surfaces": [{"radius": 1e308, "thickness": 3.6, "ior": 1.5, "semi_diameter": 12.7, "stop": true},
            {"radius": -1e308, "thickness": 80}]}"#,
    )
    .unwrap();
    let out = lens(&["info", huge.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("1.000000e308"), "{text}");
    short_numbers(&text);
    let scene = d.join("big.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"type": "pinhole", "position": [0,0,0], "look_at": [0,0,1], "fov_deg": 40}, "film": {"width": 8, "height": 8},
            "materials": {"grey": {"type": "diffuse", "color": [0.5,0.5,0.5]}},
            "shapes": [{"type": "sphere", "center": [0,0,5], "radius": 1, "material": "grey"},
                       {"type": "sphere", "center": [0,0,5], "radius": 1e33, "material": "grey"}]}"#,
    )
    .unwrap();
    refused(&["render", scene.to_str().unwrap(), "-o", d.join("b.png").to_str().unwrap()], &["shapes[1].radius: 1e33"]);
    for args in [
        vec!["coc", DG, "--focus-mm", "2000", "--distances=1e-300"],
        vec!["coc", DG, "--focus-mm", "1e-300", "--distances=1000"],
        vec!["spot", DG, "--field-deg", "1e-300"],
        vec!["fan", DG, "--field-deg", "1e-300"],
        vec!["info", DG, "--object-distance", "1e300"],
        vec!["focus", DG, "--object-distance", "1e300"],
    ] {
        let out = lens(&args);
        assert!(matches!(out.status.code(), Some(0 | 1)), "{args:?}");
        short_numbers(&(String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr)));
    }
    // a surface without a clear aperture limits the bundle by missing it
    let open = d.join("open.json");
    std::fs::write(
        &open,
        r#"{"surfaces": [{"thickness": 5, "semi_diameter": 9, "stop": true},
            {"radius": 30, "thickness": 8, "ior": 1.5, "semi_diameter": 9},
            {"radius": -6, "thickness": 40}]}"#,
    )
    .unwrap();
    let out = lens(&["info", open.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("inf mm") && text.contains("surface 3, no clear aperture given"), "{text}");
    refused(&["info", open.to_str().unwrap(), "--f-number", "1"], &["surface 3 (no clear aperture given"]);
}

/// What a parser says about a broken file, in the project's words, its own
/// text kept as the detail: an empty file, a lone UTF-16 surrogate, a file
/// cut short; for prescriptions and scenes alike.
#[test]
fn broken_json_is_explained() {
    let d = scratch("json");
    for (name, text, words) in [
        ("empty.json", "", &["the file is empty", "one JSON object"][..]),
        ("blank.json", "  \n", &["the file is empty"][..]),
        ("lone.json", r#"{"\ud800": 1}"#, &["surrogate pair", "hex escape", "both halves"][..]),
        ("short.json", r#"{"\ud8": 1}"#, &["not a whole character"][..]),
        ("cut.json", r#"{"surf"#, &["ends in the middle", "cut short"][..]),
    ] {
        let f = d.join(name);
        std::fs::write(&f, text).unwrap();
        refused(&["info", f.to_str().unwrap()], words);
        refused(&["render", f.to_str().unwrap(), "-o", d.join("x.png").to_str().unwrap()], words);
    }
}
