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

/// A sequential colour for `t` in [0, 1]: black through blue and orange to
/// white.
pub fn sequential(t: f64) -> String {
    let t = t.clamp(0.0, 1.0);
    let stops = [
        (0.0, [0.0, 0.0, 4.0]),
        (0.3, [60.0, 15.0, 110.0]),
        (0.6, [200.0, 60.0, 60.0]),
        (0.85, [250.0, 170.0, 40.0]),
        (1.0, [252.0, 252.0, 220.0]),
    ];
    let k = stops.iter().rposition(|s| s.0 <= t).unwrap_or(0).min(stops.len() - 2);
    let (a, b) = (stops[k], stops[k + 1]);
    let u = (t - a.0) / (b.0 - a.0);
    let c: Vec<u8> = (0..3).map(|i| (a.1[i] + (b.1[i] - a.1[i]) * u).round() as u8).collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// A PSF picture: the image (log10 over `decades` below its peak, or
/// linear) in micrometres about the chief ray's image point, cropped to
/// `half_width` pixels about the centre, and its encircled energy against
/// radius (micrometres), diffraction beside geometric (the spot's).
pub fn psf_chart(
    title: &str,
    psf: &lens::analysis::wave::psf::Psf,
    half_width: usize,
    log_decades: Option<f64>,
    ee: &[(f64, f64)],
    geometric_ee: &[(f64, f64)],
) -> String {
    let peak = psf.peak().max(f64::MIN_POSITIVE);
    let mid = psf.size / 2;
    let lo = mid.saturating_sub(half_width);
    let hi = (mid + half_width).min(psf.size - 1);
    let (px, py) = (psf.pixel_mm.0 * 1e3, psf.pixel_mm.1 * 1e3);
    let mut cells = Vec::new();
    for row in lo..=hi {
        for col in lo..=hi {
            let v = psf.intensity[row * psf.size + col] / peak;
            let t = match log_decades {
                Some(d) => 1.0 + v.max(1e-300).log10() / d,
                None => v,
            };
            if t <= 0.0 {
                continue;
            }
            let (x, y) = psf.position(col, row);
            let (x, y) = (x * 1e3, y * 1e3);
            cells.push(([x - 0.5 * px, y - 0.5 * py, x + 0.5 * px, y + 0.5 * py], sequential(t)));
        }
    }
    let (x0, _) = psf.position(lo, lo);
    let (x1, _) = psf.position(hi, hi);
    let span = (x0.abs().max(x1.abs()) * 1e3, (psf.position(lo, lo).1.abs().max(psf.position(hi, hi).1.abs())) * 1e3);
    let scale = match log_decades {
        Some(d) => format!("log10 scale, {d} decades below the peak (black)"),
        None => "linear scale".into(),
    };
    let image = Panel {
        title: format!("{} PSF, {scale}", psf.method.name().to_uppercase()),
        x_label: "x (µm from the chief ray)".into(),
        y_label: "y (µm)".into(),
        cells,
        equal_aspect: true,
        x_range: Some((-span.0, span.0)),
        y_range: Some((-span.1, span.1)),
        ..Panel::default()
    };
    let curve = Panel {
        title: "encircled energy about the centroid".into(),
        x_label: "radius (µm)".into(),
        y_label: "fraction".into(),
        series: vec![
            Series::new("diffraction", ee.iter().map(|(r, f)| (r * 1e3, *f)).collect(), PALETTE[0], Style::Line),
            Series::new(
                "geometric",
                geometric_ee.iter().map(|(r, f)| (r * 1e3, *f)).collect(),
                PALETTE[1],
                Style::Dashed,
            ),
        ],
        y_range: Some((0.0, 1.02)),
        ..Panel::default()
    };
    Figure { title: title.into(), panels: vec![image, curve], columns: 2, panel_size: (520.0, 520.0) }.to_svg()
}
