//! The Monte Carlo tolerancing picture: a histogram of the criterion over
//! the trials, the pass mark, and the cumulative share of trials (the
//! yield at each mark).

use crate::figure::{Figure, Panel, Series, Style};

/// A histogram of `values` (the judged trials' criteria) in `bins` bars,
/// with the cumulative share of `total` trials as a second panel and
/// `threshold` marked on both.
pub fn histogram_chart(values: &[f64], total: usize, threshold: Option<f64>, title: &str, x_label: &str) -> String {
    let bins = 40;
    let (lo, hi) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo < hi { (lo, hi) } else { (lo - 0.5, lo + 0.5) };
    let w = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for &v in values {
        counts[(((v - lo) / w) as usize).min(bins - 1)] += 1;
    }
    let cells: Vec<([f64; 4], String)> = counts
        .iter()
        .enumerate()
        .map(|(i, &c)| ([lo + i as f64 * w, 0.0, lo + (i + 1) as f64 * w, c as f64], "#4a7bb7".to_string()))
        .collect();
    let top = counts.iter().copied().max().unwrap_or(1) as f64;
    let mut hist = Panel {
        title: format!("{} judged trials", values.len()),
        x_label: x_label.into(),
        y_label: "trials".into(),
        cells,
        x_range: Some((lo, hi)),
        y_range: Some((0.0, top * 1.05)),
        ..Panel::default()
    };
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = total.max(1) as f64;
    let cumulative: Vec<(f64, f64)> = sorted.iter().enumerate().map(|(i, &v)| (v, (i + 1) as f64 / n)).collect();
    let mut cum = Panel {
        title: "share of all trials at or below".into(),
        x_label: x_label.into(),
        y_label: "share of trials".into(),
        series: vec![Series::new("", cumulative, "#222", Style::Line)],
        x_range: Some((lo, hi)),
        y_range: Some((0.0, 1.02)),
        ..Panel::default()
    };
    if let Some(t) = threshold {
        hist.series.push(Series::new(
            format!("threshold {t}"),
            vec![(t, 0.0), (t, top * 1.05)],
            "#c0392b",
            Style::Dashed,
        ));
        cum.series.push(Series::new(format!("threshold {t}"), vec![(t, 0.0), (t, 1.02)], "#c0392b", Style::Dashed));
    }
    Figure { title: title.into(), panels: vec![hist, cum], columns: 2, panel_size: (560.0, 420.0) }.to_svg()
}
