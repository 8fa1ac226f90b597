//! Wave optics pictures: the wavefront map over the pupil.

use crate::figure::{Figure, Panel, Series, Style};
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
