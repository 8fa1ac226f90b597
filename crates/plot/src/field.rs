//! Field curvature, distortion, spherical aberration and illumination plots.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::curves::FieldCurves;

/// A 2 x 2 figure: field curvature (T and S), distortion, longitudinal
/// spherical aberration, relative illumination and vignetting.
pub fn field_chart(c: &FieldCurves, name: &str) -> String {
    let f = &c.fields;
    let pts = |g: &dyn Fn(&lens::analysis::curves::FieldPoint) -> (f64, f64)| f.iter().map(g).collect::<Vec<_>>();
    let panels = vec![
        Panel {
            title: "field curvature".into(),
            x_label: "focus from paraxial image plane (mm)".into(),
            y_label: "field (deg)".into(),
            series: vec![
                Series::new("tangential", pts(&|p| (p.tangential_focus, p.field_deg)), PALETTE[0], Style::Line),
                Series::new("sagittal", pts(&|p| (p.sagittal_focus, p.field_deg)), PALETTE[1], Style::Dashed),
            ],
            ..Panel::default()
        },
        Panel {
            title: "distortion".into(),
            x_label: "distortion (%)".into(),
            y_label: "field (deg)".into(),
            series: vec![Series::new("", pts(&|p| (p.distortion_percent, p.field_deg)), PALETTE[2], Style::Line)],
            ..Panel::default()
        },
        Panel {
            title: "longitudinal spherical aberration".into(),
            x_label: "focus from paraxial (mm)".into(),
            y_label: "pupil radius (normalised)".into(),
            series: vec![Series::new(
                "",
                c.spherical.iter().map(|z| (z.longitudinal, z.pupil)).collect(),
                PALETTE[3],
                Style::Line,
            )],
            y_range: Some((0.0, 1.05)),
            ..Panel::default()
        },
        Panel {
            title: "illumination".into(),
            x_label: "field (deg)".into(),
            y_label: "relative to the axis".into(),
            series: vec![
                Series::new(
                    "relative illumination",
                    pts(&|p| (p.field_deg, p.relative_illumination)),
                    PALETTE[4],
                    Style::Line,
                ),
                Series::new(
                    "unvignetted fraction",
                    pts(&|p| (p.field_deg, p.unvignetted_fraction)),
                    PALETTE[5],
                    Style::Dashed,
                ),
            ],
            y_range: Some((0.0, 1.1)),
            ..Panel::default()
        },
    ];
    Figure { title: format!("Field curves: {name}"), panels, columns: 2, panel_size: (460.0, 340.0) }.to_svg()
}
