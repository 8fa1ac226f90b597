//! Circle of confusion against object distance: real lens beside thin lens.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::coc::{CocRow, CocTable};

/// A figure of blur diameter (mm) against object vergence 1/S2 (1/m, so
/// that infinity is the point at 0 and the thin-lens blur is two straight
/// lines meeting at the focus): the real geometric and RMS diameters and
/// the thin-lens prediction of `curve` (a dense table) as lines, and the
/// rows of `asked` as dots.
pub fn coc_chart(curve: &CocTable, asked: &CocTable, name: &str) -> String {
    let x = |r: &CocRow| r.distance.map_or(0.0, |d| 1e3 / d);
    let line = |t: &CocTable, f: &dyn Fn(&CocRow) -> f64| t.rows.iter().map(|r| (x(r), f(r))).collect::<Vec<_>>();
    let focus = match curve.focus_distance {
        Some(d) => format!("focused at {:.3} m", d / 1e3),
        None => "focused at infinity".to_string(),
    };
    let panel = Panel {
        title: format!("{focus} (film {:.4} mm)", curve.film_distance),
        x_label: "1 / object distance (1/m); 0 is infinity".into(),
        y_label: "blur diameter on film (mm)".into(),
        series: vec![
            Series::new("real lens, geometric", line(curve, &|r| r.geo_diameter), PALETTE[0], Style::Line),
            Series::new("real lens, RMS diameter", line(curve, &|r| r.rms_diameter), PALETTE[2], Style::Line),
            Series::new(
                "thin lens A|S2-S1|/S2 f/(S1-f)",
                line(curve, &|r| r.thin_lens_diameter),
                PALETTE[1],
                Style::Dashed,
            ),
            Series::new("asked distances, geometric", line(asked, &|r| r.geo_diameter), PALETTE[0], Style::Dots(3.5)),
            Series::new("asked distances, RMS", line(asked, &|r| r.rms_diameter), PALETTE[2], Style::Dots(3.5)),
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
