//! Studies: one scene rendered in a grid, each row and column changing some
//! of its film and camera settings (the same settings the command line
//! overrides), for comparisons like the original depth-of-field study's
//! (apertures by focus distances, sample counts, focus_shift against a real
//! lens, aperture shapes, real lenses). The file (JSON) names the scene
//! (relative to the study file), a title, settings for every cell, and the
//! rows and columns, each a label and its settings; a cell's settings are
//! the study's, then its column's, then its row's. docs/scene-format.md.

use crate::scene::format::ApertureSpec;
use crate::scene::overrides::{CameraKind, Overrides};
use crate::scene::{Scene, SceneError};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Settings as a study file writes them.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Film width, pixels.
    #[serde(default)]
    pub width: Option<u32>,
    /// Film height, pixels.
    #[serde(default)]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[serde(default)]
    pub spp: Option<u32>,
    /// `"pinhole"`, `"thin_lens"` or `"lens"`.
    #[serde(default)]
    pub camera: Option<String>,
    /// Thin-lens aperture diameter, m.
    #[serde(default)]
    pub aperture: Option<f64>,
    /// f-number.
    #[serde(default)]
    pub f_number: Option<f64>,
    /// Thin-lens focal length, mm.
    #[serde(default)]
    pub focal_length_mm: Option<f64>,
    /// Distance from the film to the plane in focus, m.
    #[serde(default)]
    pub focus_distance: Option<f64>,
    /// The thin lens's focus_shift.
    #[serde(default)]
    pub focus_shift: Option<f64>,
    /// `circle`, `polygon:N[:ROT_DEG]` or `mask:FILE.png`.
    #[serde(default)]
    pub aperture_shape: Option<String>,
    /// A real lens's prescription, relative to the study file.
    #[serde(default)]
    pub prescription: Option<String>,
    /// Lens flare: `"off"`, `"ghosts"` or `"ghosts+glare"`.
    #[serde(default)]
    pub flare: Option<String>,
    /// Diffraction at the aperture: `"off"` or `"on"`.
    #[serde(default)]
    pub diffraction: Option<String>,
    /// Every surface's coating of a real lens: `"none"`, `"MgF2"` or thin
    /// films (`camera.coating`).
    #[serde(default)]
    pub coating: Option<lens::model::CoatingSpec>,
}

/// A row or column: its label and settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Drawn beside the row or above the column.
    pub label: String,
    /// What it changes.
    #[serde(default)]
    pub set: Settings,
}

/// A study file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    /// Drawn above the grid.
    pub title: String,
    /// The scene file, relative to the study file.
    pub scene: String,
    /// Settings of every cell.
    #[serde(default)]
    pub set: Settings,
    /// The rows (at least one).
    pub rows: Vec<Entry>,
    /// The columns (at least one).
    pub columns: Vec<Entry>,
}

/// A study ready to render: its scenes built and checked.
pub struct Study {
    /// The title.
    pub title: String,
    /// Row labels.
    pub rows: Vec<String>,
    /// Column labels.
    pub columns: Vec<String>,
    /// The scene of each cell, row by row; each with its samples per pixel.
    pub cells: Vec<Scene>,
    /// Every file the study reads.
    pub inputs: Vec<PathBuf>,
}

/// The most cells a study may have.
pub const MAX_CELLS: usize = 64;

impl Settings {
    /// As overrides: later settings win where both are given.
    fn merge(&self, o: &mut Overrides, dir: &Path, what: &str) -> Result<(), String> {
        macro_rules! take {
            ($($f:ident),*) => {$( if let Some(v) = self.$f { o.$f = Some(v); } )*};
        }
        take!(width, height, spp, aperture, f_number, focal_length_mm, focus_distance, focus_shift);
        if let Some(c) = &self.camera {
            o.camera = Some(match c.as_str() {
                "pinhole" => CameraKind::Pinhole,
                "thin_lens" => CameraKind::ThinLens,
                "lens" => CameraKind::Lens,
                _ => return Err(format!("{what}.camera \"{c}\": choose \"pinhole\", \"thin_lens\" or \"lens\"")),
            });
        }
        if let Some(s) = &self.aperture_shape {
            let shape = Overrides::parse_shape(s).map_err(|e| format!("{what}.aperture_shape: {e}"))?;
            // a mask named by the study is relative to the study file
            o.aperture_shape = Some(match shape {
                ApertureSpec::Mask { image } => ApertureSpec::Mask { image: dir.join(image).display().to_string() },
                other => other,
            });
        }
        if let Some(p) = &self.prescription {
            o.prescription = Some(dir.join(p));
        }
        if let Some(f) = &self.flare {
            o.flare = Some(f.parse().map_err(|e| format!("{what}.flare: {e}"))?);
        }
        if let Some(d) = &self.diffraction {
            o.diffraction = Some(d.parse().map_err(|e| format!("{what}.diffraction: {e}"))?);
        }
        if let Some(c) = &self.coating {
            c.coating().map_err(|e| format!("{what}.coating: {e}"))?;
            o.coating = Some(c.clone());
        }
        Ok(())
    }
}

impl Study {
    /// Reads a study file and builds the scene of every cell (so that every
    /// setting is checked before anything renders). Errors name the file and
    /// the row or column.
    pub fn load(path: &Path) -> Result<Study, SceneError> {
        Study::load_with(path, &Overrides::default())
    }

    /// [`Self::load`] with the command line's settings (`--width`,
    /// `--height`, `--spp`, `--strict-glass-range`) applied to every cell
    /// after the study's own.
    pub fn load_with(path: &Path, command_line: &Overrides) -> Result<Study, SceneError> {
        let name = path.display().to_string();
        let io = |message: String| SceneError::Io { path: name.clone(), message };
        let bytes = lens::io::files::read_bounded(path, 1 << 20).map_err(|e| io(e.reason()))?;
        let text = String::from_utf8(bytes).map_err(|_| io("not UTF-8 text: is it a study file?".into()))?;
        let file: StudyFile = lens::io::json::parse_object(&text, "a study (docs/scene-format.md)")
            .map_err(|(line, column, message)| SceneError::Json { path: name.clone(), line, column, message })?;
        let invalid =
            |field: String, message: String| SceneError::Invalid { path: name.clone(), field, source: message.into() };
        if file.rows.is_empty() || file.columns.is_empty() {
            return Err(invalid("rows".into(), "give at least one row and one column".into()));
        }
        if file.rows.len() * file.columns.len() > MAX_CELLS {
            return Err(invalid(
                "rows".into(),
                format!("{} x {} cells: at most {MAX_CELLS}", file.rows.len(), file.columns.len()),
            ));
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let scene_path = dir.join(&file.scene);
        let mut cells = Vec::new();
        for (r, row) in file.rows.iter().enumerate() {
            for (c, col) in file.columns.iter().enumerate() {
                let mut o = Overrides::default();
                file.set.merge(&mut o, dir, "set").map_err(|e| invalid("set".into(), e))?;
                let what = format!("columns[{c}].set");
                col.set.merge(&mut o, dir, &what).map_err(|e| invalid(what.clone(), e))?;
                let what = format!("rows[{r}].set");
                row.set.merge(&mut o, dir, &what).map_err(|e| invalid(what.clone(), e))?;
                o.width = command_line.width.or(o.width);
                o.height = command_line.height.or(o.height);
                o.spp = command_line.spp.or(o.spp);
                o.strict_glass_range |= command_line.strict_glass_range;
                let scene = Scene::load_with(&scene_path, &o).map_err(|e| {
                    invalid(format!("rows[{r}] x columns[{c}] (\"{}\", \"{}\")", row.label, col.label), e.to_string())
                })?;
                cells.push(scene);
            }
        }
        let mut inputs = vec![path.to_path_buf()];
        for s in &cells {
            for i in &s.inputs {
                if !inputs.contains(i) {
                    inputs.push(i.clone());
                }
            }
        }
        Ok(Study {
            title: file.title,
            rows: file.rows.into_iter().map(|r| r.label).collect(),
            columns: file.columns.into_iter().map(|c| c.label).collect(),
            cells,
            inputs,
        })
    }
}
