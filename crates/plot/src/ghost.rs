//! The ghost list drawn on the image plane: each ghost of a point source as
//! its paraxial blur circle (centre at its chief-ray height, radius its
//! marginal ray's), the brightest labelled.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::ghost::GhostFocus;

/// Ghosts labelled in the legend (the brightest by intensity).
const LABELLED: usize = 8;

/// A figure of the ghosts of `ghosts` (at `field_deg`) as circles on the
/// image plane, mm, with the primary image's height `primary_mm` marked;
/// ghosts dimmer than 1e-7 of the primary, or wider than `reach_mm`, are
/// left out.
pub fn ghost_chart(ghosts: &[GhostFocus], primary_mm: f64, reach_mm: f64, field_deg: f64, name: &str) -> String {
    let mut order: Vec<&GhostFocus> =
        ghosts.iter().filter(|g| g.intensity.is_some_and(|i| i >= 1e-7) && g.radius_mm <= reach_mm).collect();
    order.sort_by(|a, b| b.intensity.unwrap_or(0.0).total_cmp(&a.intensity.unwrap_or(0.0)));
    let mut series = Vec::new();
    for (k, g) in order.iter().enumerate() {
        let r = g.radius_mm.max(reach_mm * 2e-3);
        let points: Vec<(f64, f64)> = (0..=72)
            .map(|s| {
                let a = s as f64 / 72.0 * std::f64::consts::TAU;
                (r * a.cos(), g.image_height_mm + r * a.sin())
            })
            .collect();
        let label = if k < LABELLED {
            format!("{}-{}: {:.1e}", g.surfaces[0], g.surfaces[1], g.intensity.unwrap_or(0.0))
        } else {
            String::new()
        };
        let color = if k < LABELLED { PALETTE[k % PALETTE.len()] } else { "#bbbbbb" };
        series.push(Series::new(&label, points, color, Style::Line));
    }
    series.push(Series::new("primary image", vec![(0.0, primary_mm)], "#000000", Style::Dots(4.0)));
    let panel = Panel {
        title: format!("{} ghosts at {field_deg} deg (surfaces i-j: irradiance / primary)", order.len()),
        x_label: "image plane x (mm)".into(),
        y_label: "image plane y (mm)".into(),
        series,
        // circles stay round
        equal_aspect: true,
        ..Panel::default()
    };
    Figure { title: format!("Ghosts: {name}"), panels: vec![panel], columns: 1, panel_size: (640.0, 560.0) }.to_svg()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ghost's blur circle is drawn round (equal scales on both axes),
    /// even where the ghosts spread further one way than the other.
    #[test]
    fn circles_are_round() {
        let ghost = |surfaces, height, radius| GhostFocus {
            surfaces,
            focus_z_mm: None,
            image_height_mm: height,
            radius_mm: radius,
            intensity: Some(1e-3),
            reflectance: 1e-3,
        };
        let ghosts = [ghost([1, 2], 40.0, 5.0), ghost([2, 3], -10.0, 20.0)];
        let svg = ghost_chart(&ghosts, 10.0, 100.0, 5.0, "test");
        let first = svg.split(r#"<polyline points=""#).nth(1).expect("a circle");
        let points: Vec<(f64, f64)> = first
            .split('"')
            .next()
            .unwrap()
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        let span = |f: fn(&(f64, f64)) -> f64| {
            points.iter().map(f).fold(f64::NEG_INFINITY, f64::max) - points.iter().map(f).fold(f64::INFINITY, f64::min)
        };
        let (w, h) = (span(|p| p.0), span(|p| p.1));
        assert!(w > 10.0 && (w - h).abs() < 0.01 * w, "{w} x {h} px");
    }
}
