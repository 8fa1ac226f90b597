//! Spot diagram plots with the Airy disk for scale.

use crate::figure::{Circle, Figure, Panel, Series, Style, PALETTE};
use lens::analysis::spot::SpotDiagram;

/// A figure with one panel per spot: ray positions relative to the chief
/// ray in micrometres, same scale on both axes, the Airy disk drawn around
/// the chief ray.
pub fn spot_chart(spots: &[SpotDiagram], name: &str) -> String {
    let panels = spots
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let pts = s.hits.iter().map(|h| ((h[0] - s.chief[0]) * 1e3, (h[1] - s.chief[1]) * 1e3)).collect();
            let field = s.field_deg.map_or("finite object".to_string(), |d| format!("{d} deg"));
            Panel {
                title: format!("{field}: RMS {:.2} um, GEO {:.2} um", s.rms_radius * 1e3, s.geo_radius * 1e3),
                x_label: "x - chief (um)".into(),
                y_label: "y - chief (um)".into(),
                series: vec![Series::new(
                    format!("{} rays, {} vignetted", s.rays, s.vignetted),
                    pts,
                    PALETTE[k % PALETTE.len()],
                    Style::Dots(1.4),
                )],
                circles: vec![Circle {
                    center: (0.0, 0.0),
                    radius: s.airy_radius * 1e3,
                    color: "#222".into(),
                    label: format!("Airy radius {:.2} um", s.airy_radius * 1e3),
                }],
                equal_aspect: true,
                ..Panel::default()
            }
        })
        .collect::<Vec<_>>();
    let columns = panels.len().clamp(1, 3);
    Figure { title: format!("Spot diagram: {name}"), panels, columns, panel_size: (380.0, 380.0) }.to_svg()
}
