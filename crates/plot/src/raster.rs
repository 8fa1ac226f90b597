//! SVG to PNG with resvg and an embedded font.

use crate::PlotError;
use resvg::{tiny_skia, usvg};

/// Family name of the embedded font; figures use it for all text.
pub const FONT_FAMILY: &str = "Ubuntu";

/// Rasterises an SVG document at its own size into PNG bytes.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, PlotError> {
    let mut opt = usvg::Options::default();
    let db = opt.fontdb_mut();
    db.load_font_data(epaint_default_fonts::UBUNTU_LIGHT.to_vec());
    db.set_sans_serif_family(FONT_FAMILY);
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| PlotError::Raster(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| PlotError::Raster(format!("bad size {}x{}", size.width(), size.height())))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| PlotError::Raster(e.to_string()))
}

/// A band of `width` x `height` pixels, white, with `text` centred in it
/// in the embedded font at `font_size` px: a label for a montage, as PNG
/// bytes. The width a label needs is about 0.6 x font size per character.
pub fn label_png(text: &str, width: u32, height: u32, font_size: f64) -> Result<Vec<u8>, PlotError> {
    let svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}"><text x="{}" y="{}" font-family="{FONT_FAMILY}" font-size="{font_size}" text-anchor="middle" dominant-baseline="central" fill="#222">{}</text></svg>"##,
        width as f64 / 2.0,
        height as f64 / 2.0,
        crate::figure::esc(text)
    );
    svg_to_png(&svg)
}
