//! Colour: focal shift against wavelength, lateral colour against field,
//! the polychromatic spot (points coloured by wavelength) and the fans of
//! each wavelength overlaid.

use crate::figure::{Figure, Panel, Series, Style};
use lens::analysis::chromatic::Chromatic;

/// An sRGB colour for a visible wavelength (nm): a piecewise-linear
/// approximation of the spectral hues, darkened toward the ends of the
/// visible range; for telling wavelengths apart in a chart, not a
/// colorimetric conversion.
pub fn wavelength_color(nm: f64) -> String {
    let (r, g, b) = match nm {
        x if x < 440.0 => ((440.0 - x) / 60.0, 0.0, 1.0),
        x if x < 490.0 => (0.0, (x - 440.0) / 50.0, 1.0),
        x if x < 510.0 => (0.0, 1.0, (510.0 - x) / 20.0),
        x if x < 580.0 => ((x - 510.0) / 70.0, 1.0, 0.0),
        x if x < 645.0 => (1.0, (645.0 - x) / 65.0, 0.0),
        _ => (1.0, 0.0, 0.0),
    };
    // green and yellow are too light on white: darken them
    let k = if (490.0..600.0).contains(&nm) { 0.7 } else { 0.9 };
    let c = |v: f64| (255.0 * (k * v.clamp(0.0, 1.0))).round() as u8;
    format!("#{:02x}{:02x}{:02x}", c(r), c(g), c(b))
}

/// The four colour panels of [`Chromatic`].
pub fn chromatic_chart(c: &Chromatic, name: &str) -> String {
    let mut panels = Vec::new();
    // focal shift in micrometres against wavelength
    let shift: Vec<(f64, f64)> = c.focal_shift.iter().map(|f| (f.wavelength_nm, f.focal_shift * 1e3)).collect();
    let marks: Vec<Series> = c
        .wavelengths_nm
        .iter()
        .filter_map(|&nm| {
            let f = c
                .focal_shift
                .iter()
                .min_by(|a, b| (a.wavelength_nm - nm).abs().total_cmp(&(b.wavelength_nm - nm).abs()))?;
            ((f.wavelength_nm - nm).abs() <= 2.5).then(|| {
                Series::new(
                    format!("{nm} nm"),
                    vec![(f.wavelength_nm, f.focal_shift * 1e3)],
                    &wavelength_color(nm),
                    Style::Dots(4.0),
                )
            })
        })
        .collect();
    let mut series = vec![Series::new("", shift, "#222", Style::Line)];
    series.extend(marks);
    panels.push(Panel {
        // (a shift that rounds to zero is written 0.0, not -0.0)
        title: format!("focal shift (axial colour {:+.1} µm)", {
            let v = c.axial_colour * 1e3;
            if v.abs() < 0.05 {
                0.0
            } else {
                v
            }
        }),
        x_label: "wavelength (nm)".into(),
        y_label: "focal shift (µm)".into(),
        series,
        ..Panel::default()
    });
    // lateral colour in micrometres against field
    let lat: Vec<(f64, f64)> = c.lateral.iter().map(|l| (l.field_deg, l.lateral_colour * 1e3)).collect();
    let (s, l) = (c.wavelengths_nm[0], c.wavelengths_nm[c.wavelengths_nm.len() - 1]);
    panels.push(Panel {
        title: format!("lateral colour ({s} nm minus {l} nm)"),
        x_label: "field (deg)".into(),
        y_label: "lateral colour (µm)".into(),
        series: vec![Series::new("", lat, "#222", Style::Line)],
        ..Panel::default()
    });
    // the polychromatic spot about its centroid
    let cen = c.spot.centroid;
    let spot: Vec<Series> = c
        .spot
        .wavelengths
        .iter()
        .map(|w| {
            let pts = w.hits.iter().map(|h| ((h[0] - cen[0]) * 1e3, (h[1] - cen[1]) * 1e3)).collect();
            Series::new(format!("{} nm", w.wavelength_nm), pts, &wavelength_color(w.wavelength_nm), Style::Dots(1.4))
        })
        .collect();
    panels.push(Panel {
        title: format!("spot at {} deg: RMS {:.2} µm", c.spot.field_deg, c.spot.rms_radius * 1e3),
        x_label: "x - centroid (µm)".into(),
        y_label: "y - centroid (µm)".into(),
        series: spot,
        equal_aspect: true,
        ..Panel::default()
    });
    // tangential fans of every wavelength, about the primary's chief ray
    let primary = c.fans.iter().min_by(|a, b| {
        (a.wavelength_nm - c.primary_wavelength_nm).abs().total_cmp(&(b.wavelength_nm - c.primary_wavelength_nm).abs())
    });
    let chief_y = primary.map_or(0.0, |f| f.fan.chief[1]);
    let fans: Vec<Series> = c
        .fans
        .iter()
        .map(|f| Series {
            label: format!("{} nm", f.wavelength_nm),
            points: f.fan.tangential.iter().map(|t| t.y.map(|y| (t.py, (y - chief_y) * 1e3))).collect(),
            color: wavelength_color(f.wavelength_nm),
            style: Style::Line,
        })
        .collect();
    panels.push(Panel {
        title: format!("tangential fans at {} deg", c.spot.field_deg),
        x_label: "py (normalised pupil)".into(),
        y_label: "y - primary chief (µm)".into(),
        series: fans,
        x_range: Some((-1.05, 1.05)),
        ..Panel::default()
    });
    Figure { title: format!("Colour: {name}"), panels, columns: 2, panel_size: (460.0, 340.0) }.to_svg()
}
