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
