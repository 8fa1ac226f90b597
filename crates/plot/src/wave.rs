//! Wave optics pictures: the wavefront map over the pupil.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::wave::{Wavefront, WavefrontStats};

/// A diverging colour for `t` in [-1, 1]: blue (-1) through white (0) to
/// red (+1).
pub fn diverging(t: f64) -> String {
    let t = t.clamp(-1.0, 1.0);
    let (lo, mid, hi) = ([33.0, 102.0, 172.0], [247.0, 247.0, 247.0], [178.0, 24.0, 43.0]);
    let (a, b, u) = if t < 0.0 { (mid, lo, -t) } else { (mid, hi, t) };
    let c: Vec<u8> = (0..3).map(|i| (a[i] + (b[i] - a[i]) * u).round() as u8).collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The wavefront map of `w` over the normalised pupil (px right, py up),
/// coloured symmetrically about zero (white; blue behind the reference,
/// red ahead), the colours of a few values in the legend and the
/// statistics `s` in the panel's title; vignetted cells left blank.
pub fn wavefront_map(w: &Wavefront, s: &WavefrontStats, name: &str) -> String {
    let reach = w.opd_waves.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
    let h = 1.0 / w.grid.n as f64;
    let cells: Vec<([f64; 4], String)> = w
        .grid
        .cells
        .iter()
        .zip(&w.opd_waves)
        .filter_map(|(c, v)| {
            let v = (*v)?;
            let (x, y) = (-1.0 + (2 * c.column + 1) as f64 * h, -1.0 + (2 * c.row + 1) as f64 * h);
            Some(([x - h, y - h, x + h, y + h], diverging(v / reach)))
        })
        .collect();
    let map = Panel {
        title: format!(
            "RMS {:.4} waves (to chief), {:.4} (to centroid); P-V {:.4}; Strehl {:.4}",
            s.rms_to_chief, s.rms_to_centroid, s.pv_to_chief, s.strehl
        ),
        x_label: "normalised pupil x".into(),
        y_label: "normalised pupil y".into(),
        cells,
        equal_aspect: true,
        x_range: Some((-1.05, 1.05)),
        y_range: Some((-1.05, 1.05)),
        ..Panel::default()
    };
    // the colour key as the legend: the colours of a few values
    let key = [-1.0, -0.5, 0.5, 1.0]
        .map(|t| Series::new(format!("{:+.3} waves", t * reach), Vec::new(), &diverging(t), Style::Dots(5.0)));
    let map = Panel { series: key.to_vec(), ..map };
    let field = match w.field {
        lens::analysis::Field::Angle(d) => format!("{d} deg"),
        f => f.describe(),
    };
    let title = format!("Wavefront: {name}, {field}, {} nm, {} x {} pupil grid", w.wavelength_nm, w.grid.n, w.grid.n);
    Figure { title, panels: vec![map], columns: 1, panel_size: (620.0, 640.0) }.to_svg()
}

/// One MTF curve: a label and (frequency or field, MTF) points.
pub struct MtfCurve {
    /// Legend text.
    pub label: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// Colour index into the palette.
    pub colour: usize,
    /// Dashed (sagittal, or the diffraction limit) or solid.
    pub dashed: bool,
}

/// A chart of MTF curves against `x_label` (cycles/mm, or image height),
/// MTF from 0 to 1.
pub fn mtf_chart(title: &str, panel_title: &str, x_label: &str, curves: &[MtfCurve]) -> String {
    let series = curves
        .iter()
        .map(|c| {
            let colour = if c.colour == usize::MAX { "#222" } else { PALETTE[c.colour % PALETTE.len()] };
            Series::new(c.label.clone(), c.points.clone(), colour, if c.dashed { Style::Dashed } else { Style::Line })
        })
        .collect();
    let panel = Panel {
        title: panel_title.into(),
        x_label: x_label.into(),
        y_label: "MTF".into(),
        series,
        y_range: Some((0.0, 1.02)),
        ..Panel::default()
    };
    Figure { title: title.into(), panels: vec![panel], columns: 1, panel_size: (720.0, 520.0) }.to_svg()
}
