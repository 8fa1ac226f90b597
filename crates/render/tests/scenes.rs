//! Every shipped scene loads: its camera, lens, glasses, meshes and masks
//! resolve, and its colour mode is the one its contents call for.

use render::scene::ColourMode;
use render::Scene;
use std::path::Path;

#[test]
fn every_shipped_scene_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let s = Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        // the spectral demonstrations render spectrally; the study scenes
        // through lenses without glasses stay RGB
        let spectral = matches!(s.colour, ColourMode::Spectral(_));
        if ["chromatic-", "wu-", "lateral-colour", "prism", "bokeh-thin-glass"].iter().any(|p| name.starts_with(p)) {
            assert!(spectral, "{name} should render spectrally");
        }
        if (name.starts_with("bokeh-thin") && !name.contains("glass")) || name.starts_with("dof-pinhole") {
            assert!(!spectral, "{name} has nothing that depends on wavelength");
        }
        n += 1;
    }
    assert!(n >= 28, "{n} scenes");
}

#[test]
fn every_shipped_study_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data/studies");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let s = render::study::Study::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(s.cells.len(), s.rows.len() * s.columns.len());
        n += 1;
    }
    assert!(n >= 5, "{n} studies");
}

/// The README's first command renders a scene whose depth of field a
/// newcomer sees: focused at 2.5 m, the ball 1.5 m away and the lamps 12 m
/// and more away blur by many pixels at its 320 px width (the real lens's
/// circle of confusion, `lens coc`).
#[test]
fn the_readme_scene_shows_depth_of_field() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let scene = "lens-data/scenes/shallow-focus-100mm-f1.25.json";
    assert!(readme.contains(&format!("render {scene} -o dof.png")), "the README's command renders another scene");
    let s = Scene::load(&root.join(scene)).unwrap();
    let render::camera::Camera::Real(cam) = &s.camera else { panic!("a real lens") };
    let px_per_mm = s.film.width as f64 / 36.0;
    let p = lens::Prescription::load(root.join("lens-data/library/double-gauss-100mm-f1.25-us2771006.json")).unwrap();
    assert_eq!(cam.prescription().surfaces().len(), p.surfaces().len());
    let coc = lens::analysis::coc::circle_of_confusion(&p, 2500.0, &[1500.0, 12_000.0]).unwrap();
    let (near, far) = (coc.rows[0].geo_diameter * px_per_mm, coc.rows[1].geo_diameter * px_per_mm);
    // 18.7 and 23.4 px
    assert!(near > 15.0 && far > 20.0, "near {near} px, far {far} px");
}
