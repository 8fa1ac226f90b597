//! Pictures of lens analyses: lens layouts, ray fans, spot diagrams,
//! circle-of-confusion and field curves. Each picture is built as an SVG
//! document ([`figure`]); [`save`] writes it as SVG or, rasterised with an
//! embedded font (Ubuntu Light, from `epaint_default_fonts`), as PNG. No
//! system fonts and no display are needed, so pictures can be made in CI.

pub mod chromatic;
pub mod coc;
pub mod fan;
pub mod field;
pub mod figure;
pub mod ghost;
pub mod glass;
pub mod layout;
pub mod raster;
pub mod spot;
pub mod tolerance;
pub mod wave;

use std::path::Path;

/// Why a picture could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The output extension is neither `.svg` nor `.png`.
    #[error("{0}: choose an output file ending in .svg or .png")]
    Extension(String),
    /// Writing the file failed.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// Rasterising failed.
    #[error("cannot rasterise the picture: {0}")]
    Raster(String),
}

/// A field's name in a panel title: `10 deg`, `x 2 deg, y 10 deg`, or
/// `finite object` (the analyses' `field_x_deg` and `field_deg`).
pub(crate) fn field_label(x_deg: Option<f64>, y_deg: Option<f64>) -> String {
    match (x_deg, y_deg) {
        (Some(x), Some(y)) => format!("x {x} deg, y {y} deg"),
        (_, Some(y)) => format!("{y} deg"),
        _ => "finite object".to_string(),
    }
}

/// Writes an SVG document to `path`: as is for `.svg`, rasterised for `.png`.
pub fn save(svg: &str, path: &Path) -> Result<(), PlotError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let bytes = match ext.as_deref() {
        Some("svg") => svg.as_bytes().to_vec(),
        Some("png") => raster::svg_to_png(svg)?,
        _ => return Err(PlotError::Extension(path.display().to_string())),
    };
    lens::io::files::write_bytes_atomic(path, &bytes)
        .map_err(|source| PlotError::Io { path: path.display().to_string(), source })
}
