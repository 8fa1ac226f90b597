//! Circle of confusion against object distance: real lens beside thin lens.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::coc::CocTable;

/// A figure of blur diameter (mm) against object distance (m): the real
/// geometric and RMS diameters and the thin-lens prediction.
pub fn coc_chart(t: &CocTable, name: &str) -> String {
    let finite: Vec<_> = t.rows.iter().filter_map(|r| r.distance.map(|d| (d / 1e3, r))).collect();
    let line =
        |f: &dyn Fn(&lens::analysis::coc::CocRow) -> f64| finite.iter().map(|(d, r)| (*d, f(r))).collect::<Vec<_>>();
    let panel = Panel {
        title: format!("focused at {:.3} m (film {:.4} mm)", t.focus_distance / 1e3, t.film_distance),
        x_label: "object distance (m)".into(),
        y_label: "blur diameter on film (mm)".into(),
        series: vec![
            Series::new("real lens, geometric", line(&|r| r.geo_diameter), PALETTE[0], Style::Line),
            Series::new("real lens, RMS diameter", line(&|r| r.rms_diameter), PALETTE[2], Style::Line),
            Series::new("thin lens A|S2-S1|/S2 f/(S1-f)", line(&|r| r.thin_lens_diameter), PALETTE[1], Style::Dashed),
        ],
        ..Panel::default()
    };
    Figure {
        title: format!("Circle of confusion: {name}"),
        panels: vec![panel],
        columns: 1,
        panel_size: (640.0, 420.0),
    }
    .to_svg()
}
