//! Ray fan plots: tangential and sagittal transverse error against pupil.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::fan::RayFan;

/// A figure of the tangential (ey against py) and sagittal (ex against px)
/// fans, one row per field; errors in micrometres.
pub fn fan_chart(fans: &[RayFan], name: &str) -> String {
    let mut panels = Vec::new();
    for (k, f) in fans.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let field = crate::field_label(f.field_x_deg, f.field_deg);
        let t: Vec<Option<(f64, f64)>> = f.tangential.iter().map(|p| p.ey.map(|e| (p.py, e * 1e3))).collect();
        let s: Vec<Option<(f64, f64)>> = f.sagittal.iter().map(|p| p.ex.map(|e| (p.px, e * 1e3))).collect();
        panels.push(Panel {
            title: format!("tangential, {field}"),
            x_label: "py (normalised pupil)".into(),
            y_label: "ey (µm)".into(),
            series: vec![Series { label: String::new(), points: t, color: color.into(), style: Style::Line }],
            x_range: Some((-1.05, 1.05)),
            ..Panel::default()
        });
        panels.push(Panel {
            title: format!("sagittal, {field}"),
            x_label: "px (normalised pupil)".into(),
            y_label: "ex (µm)".into(),
            series: vec![Series { label: String::new(), points: s, color: color.into(), style: Style::Line }],
            x_range: Some((-1.05, 1.05)),
            ..Panel::default()
        });
    }
    Figure { title: format!("Ray fans: {name}"), panels, columns: 2, panel_size: (420.0, 300.0) }.to_svg()
}
