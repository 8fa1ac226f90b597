//! A small figure model: panels with axes, ticks, lines, dots and circles,
//! written as SVG.

use crate::raster::FONT_FAMILY;
use std::fmt::Write;

/// Colours for series, in order.
pub const PALETTE: [&str; 8] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    /// Connected line.
    Line,
    /// Dashed line.
    Dashed,
    /// Dots of this radius in pixels.
    Dots(f64),
}

/// A named set of points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// Points in data units; a `None` breaks a line.
    pub points: Vec<Option<(f64, f64)>>,
    /// SVG colour.
    pub color: String,
    /// How it is drawn.
    pub style: Style,
}

impl Series {
    /// A series from plain points.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, color: &str, style: Style) -> Self {
        Series { label: label.into(), points: points.into_iter().map(Some).collect(), color: color.into(), style }
    }
}

/// A circle in data units (e.g. the Airy disk).
#[derive(Debug, Clone, PartialEq)]
pub struct Circle {
    /// Centre.
    pub center: (f64, f64),
    /// Radius, data units.
    pub radius: f64,
    /// SVG colour.
    pub color: String,
    /// Legend text.
    pub label: String,
}

/// One chart with axes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Data.
    pub series: Vec<Series>,
    /// Circles.
    pub circles: Vec<Circle>,
    /// Filled polygons (data units) drawn under everything else: outline, fill.
    pub polygons: Vec<(Vec<(f64, f64)>, String)>,
    /// Filled rectangles without outline (data units `[x0, y0, x1, y1]`,
    /// fill), drawn first: the cells of a map.
    pub cells: Vec<([f64; 4], String)>,
    /// Same scale on both axes.
    pub equal_aspect: bool,
    /// Fixed x range (else from the data).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (else from the data).
    pub y_range: Option<(f64, f64)>,
}

/// Panels laid out in a grid under a title.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title at the top.
    pub title: String,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Size of one panel, pixels.
    pub panel_size: (f64, f64),
}

const MARGIN: (f64, f64, f64, f64) = (70.0, 20.0, 40.0, 55.0); // left, right, top, bottom
const TITLE_H: f64 = 36.0;
/// The legend's first line, below the plot's bottom edge (under the axis
/// label), and its line height, pixels.
const LEGEND_TOP: f64 = 50.0;
const LEGEND_LINE: f64 = 15.0;

/// A panel's legend entries: label, colour, drawn as a dot.
fn legend_entries(panel: &Panel) -> Vec<(&str, &str, bool)> {
    panel
        .series
        .iter()
        .filter(|x| !x.label.is_empty())
        .map(|x| (x.label.as_str(), x.color.as_str(), matches!(x.style, Style::Dots(_))))
        .chain(
            panel.circles.iter().filter(|c| !c.label.is_empty()).map(|c| (c.label.as_str(), c.color.as_str(), false)),
        )
        .collect()
}

/// The width an entry takes in the legend's flow, pixels (11 px text).
fn legend_width(label: &str) -> f64 {
    34.0 + 6.0 * label.chars().count() as f64
}

/// The height the legend adds below a panel whose plot is `width` wide:
/// entries flow left to right, a new line when one would pass the plot's
/// right edge.
fn legend_height(panel: &Panel, width: f64) -> f64 {
    let entries = legend_entries(panel);
    if entries.is_empty() {
        return 0.0;
    }
    let (mut lines, mut x) = (1.0, 0.0);
    for (label, _, _) in entries {
        let wide = legend_width(label);
        if x > 0.0 && x + wide > width {
            lines += 1.0;
            x = 0.0;
        }
        x += wide;
    }
    lines * LEGEND_LINE + 4.0
}

impl Figure {
    /// The SVG document.
    pub fn to_svg(&self) -> String {
        let cols = self.columns.max(1);
        let rows = self.panels.len().div_ceil(cols).max(1);
        let (pw, ph) = self.panel_size;
        let w = cols as f64 * pw;
        // each row of panels grows by its tallest legend (drawn below the
        // plots, outside the data)
        let plot_w = pw - MARGIN.0 - MARGIN.1;
        let extra: Vec<f64> = (0..rows)
            .map(|r| self.panels.iter().skip(r * cols).take(cols).map(|p| legend_height(p, plot_w)).fold(0.0, f64::max))
            .collect();
        let h = TITLE_H + rows as f64 * ph + extra.iter().sum::<f64>();
        let mut s = String::new();
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT_FAMILY}, sans-serif">"#
        );
        let _ = write!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
        // a title too long for the figure (a lens's full name) is set
        // smaller so that it fits, about 0.56 em a character
        let chars = self.title.chars().count().max(1) as f64;
        let size = (17.0f64).min((w - 16.0) / (0.56 * chars)).max(8.0);
        let _ = write!(
            s,
            r#"<text x="{}" y="24" font-size="{size:.1}" text-anchor="middle">{}</text>"#,
            w / 2.0,
            esc(&self.title)
        );
        for (k, panel) in self.panels.iter().enumerate() {
            let (c, r) = (k % cols, k / cols);
            let y = TITLE_H + r as f64 * ph + extra[..r].iter().sum::<f64>();
            panel_svg(&mut s, panel, c as f64 * pw, y, pw, ph + extra[r]);
        }
        s.push_str("</svg>\n");
        s
    }
}

/// Escapes text for SVG: the XML specials, and characters XML 1.0 does
/// not allow at all (control characters other than tab and newlines, which
/// a lens's name might hold) replaced by U+FFFD, so the file stays valid.
pub fn esc(t: &str) -> String {
    let mut out = String::with_capacity(t.len());
    for c in t.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\t' | '\n' | '\r' => out.push(' '),
            c if (c as u32) < 0x20 || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// A data-to-pixel mapping of one panel.
#[derive(Debug, Clone, Copy)]
pub struct Mapping {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    left: f64,
    top: f64,
    width: f64,
    height: f64,
}

impl Mapping {
    /// Pixel position of a data point.
    pub fn px(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.left + (x - self.x0) / (self.x1 - self.x0) * self.width,
            self.top + self.height - (y - self.y0) / (self.y1 - self.y0) * self.height,
        )
    }
    /// Pixels per data unit along x.
    pub fn scale_x(&self) -> f64 {
        self.width / (self.x1 - self.x0)
    }
}

fn data_range(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let mut xs = (f64::INFINITY, f64::NEG_INFINITY);
    let mut ys = (f64::INFINITY, f64::NEG_INFINITY);
    let mut add = |x: f64, y: f64| {
        if x.is_finite() && y.is_finite() {
            xs = (xs.0.min(x), xs.1.max(x));
            ys = (ys.0.min(y), ys.1.max(y));
        }
    };
    for s in &panel.series {
        for &(x, y) in s.points.iter().flatten() {
            add(x, y);
        }
    }
    for (poly, _) in &panel.polygons {
        for &(x, y) in poly {
            add(x, y);
        }
    }
    for (r, _) in &panel.cells {
        add(r[0], r[1]);
        add(r[2], r[3]);
    }
    for c in &panel.circles {
        add(c.center.0 - c.radius, c.center.1 - c.radius);
        add(c.center.0 + c.radius, c.center.1 + c.radius);
    }
    let fix = |r: (f64, f64)| {
        if !r.0.is_finite() {
            (-1.0, 1.0)
        } else if r.1 - r.0 <= 1e-300 + 1e-12 * r.0.abs().max(r.1.abs()) {
            let d = if r.0 == 0.0 { 1.0 } else { r.0.abs() * 0.1 };
            (r.0 - d, r.1 + d)
        } else {
            let pad = 0.05 * (r.1 - r.0);
            (r.0 - pad, r.1 + pad)
        }
    };
    (panel.x_range.unwrap_or(fix(xs)), panel.y_range.unwrap_or(fix(ys)))
}

/// Draws a panel at (x, y) of size (w, h); returns its mapping.
pub fn panel_svg(s: &mut String, panel: &Panel, x: f64, y: f64, w: f64, h: f64) -> Mapping {
    let (mut xr, mut yr) = data_range(panel);
    let (left, top) = (x + MARGIN.0, y + MARGIN.2);
    let width = w - MARGIN.0 - MARGIN.1;
    let height = h - MARGIN.2 - MARGIN.3 - legend_height(panel, width);
    if panel.equal_aspect {
        // widen the tighter axis so one data unit is the same on both
        let sx = width / (xr.1 - xr.0);
        let sy = height / (yr.1 - yr.0);
        if sx > sy {
            let c = 0.5 * (xr.0 + xr.1);
            let half = 0.5 * width / sy;
            xr = (c - half, c + half);
        } else {
            let c = 0.5 * (yr.0 + yr.1);
            let half = 0.5 * height / sx;
            yr = (c - half, c + half);
        }
    }
    let m = Mapping { x0: xr.0, x1: xr.1, y0: yr.0, y1: yr.1, left, top, width, height };
    let _ = write!(
        s,
        r##"<text x="{}" y="{}" font-size="14" text-anchor="middle">{}</text>"##,
        left + width / 2.0,
        y + 24.0,
        esc(&panel.title)
    );
    let _ = write!(s, r##"<rect x="{left}" y="{top}" width="{width}" height="{height}" fill="none" stroke="#444"/>"##);
    // ticks and grid
    for t in ticks(xr.0, xr.1) {
        let (px, _) = m.px(t, yr.0);
        let _ = write!(s, r##"<line x1="{px}" y1="{top}" x2="{px}" y2="{}" stroke="#e4e4e4"/>"##, top + height);
        let _ = write!(
            s,
            r##"<text x="{px}" y="{}" font-size="11" text-anchor="middle">{}</text>"##,
            top + height + 15.0,
            fmt_tick(t, xr)
        );
    }
    for t in ticks(yr.0, yr.1) {
        let (_, py) = m.px(xr.0, t);
        let _ = write!(s, r##"<line x1="{left}" y1="{py}" x2="{}" y2="{py}" stroke="#e4e4e4"/>"##, left + width);
        let _ = write!(
            s,
            r##"<text x="{}" y="{}" font-size="11" text-anchor="end">{}</text>"##,
            left - 5.0,
            py + 4.0,
            fmt_tick(t, yr)
        );
    }
    // zero lines
    if xr.0 < 0.0 && xr.1 > 0.0 {
        let (px, _) = m.px(0.0, 0.0);
        let _ = write!(s, r##"<line x1="{px}" y1="{top}" x2="{px}" y2="{}" stroke="#999"/>"##, top + height);
    }
    if yr.0 < 0.0 && yr.1 > 0.0 {
        let (_, py) = m.px(0.0, 0.0);
        let _ = write!(s, r##"<line x1="{left}" y1="{py}" x2="{}" y2="{py}" stroke="#999"/>"##, left + width);
    }
    let _ = write!(
        s,
        r##"<text x="{}" y="{}" font-size="12" text-anchor="middle">{}</text>"##,
        left + width / 2.0,
        top + height + 36.0,
        esc(&panel.x_label)
    );
    let (lx, ly) = (x + 16.0, top + height / 2.0);
    let _ = write!(
        s,
        r##"<text x="{lx}" y="{ly}" font-size="12" text-anchor="middle" transform="rotate(-90 {lx} {ly})">{}</text>"##,
        esc(&panel.y_label)
    );
    // clip data to the plot area
    let clip = format!("clip{}_{}", (x as i64), (y as i64));
    let _ = write!(
        s,
        r#"<clipPath id="{clip}"><rect x="{left}" y="{top}" width="{width}" height="{height}"/></clipPath><g clip-path="url(#{clip})">"#
    );
    for (r, fill) in &panel.cells {
        let (ax, ay) = m.px(r[0], r[1]);
        let (bx, by) = m.px(r[2], r[3]);
        // a hair wider than the cell, so neighbours leave no seam
        let _ = write!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{fill}"/>"##,
            ax.min(bx),
            ay.min(by),
            (bx - ax).abs() + 0.4,
            (by - ay).abs() + 0.4
        );
    }
    for (poly, fill) in &panel.polygons {
        let pts: Vec<String> = poly
            .iter()
            .map(|&(x, y)| {
                let (px, py) = m.px(x, y);
                format!("{px:.2},{py:.2}")
            })
            .collect();
        let _ = write!(s, r##"<polygon points="{}" fill="{fill}" stroke="#333" stroke-width="1"/>"##, pts.join(" "));
    }
    for c in &panel.circles {
        let (cx, cy) = m.px(c.center.0, c.center.1);
        let _ = write!(
            s,
            r#"<circle cx="{cx}" cy="{cy}" r="{}" fill="none" stroke="{}" stroke-width="1.5"/>"#,
            c.radius * m.scale_x(),
            c.color
        );
    }
    for se in &panel.series {
        series_svg(s, se, &m);
    }
    s.push_str("</g>");
    // legend, below the axis label: outside the data
    let mut lx = left;
    let mut ly = top + height + LEGEND_TOP;
    for (label, color, dot) in legend_entries(panel) {
        let wide = legend_width(label);
        if lx > left && lx + wide > left + width {
            lx = left;
            ly += LEGEND_LINE;
        }
        if dot {
            let _ = write!(s, r#"<circle cx="{}" cy="{}" r="3" fill="{color}"/>"#, lx + 9.0, ly - 4.0);
        } else {
            let _ = write!(
                s,
                r#"<line x1="{lx}" y1="{}" x2="{}" y2="{}" stroke="{color}" stroke-width="2"/>"#,
                ly - 4.0,
                lx + 18.0,
                ly - 4.0
            );
        }
        let _ = write!(s, r#"<text x="{}" y="{ly}" font-size="11">{}</text>"#, lx + 24.0, esc(label));
        lx += wide;
    }
    m
}

fn series_svg(s: &mut String, se: &Series, m: &Mapping) {
    match se.style {
        Style::Dots(r) => {
            for &(x, y) in se.points.iter().flatten() {
                let (px, py) = m.px(x, y);
                let _ = write!(s, r#"<circle cx="{px:.2}" cy="{py:.2}" r="{r}" fill="{}"/>"#, se.color);
            }
        }
        Style::Line | Style::Dashed => {
            let dash = if se.style == Style::Dashed { r#" stroke-dasharray="6 4""# } else { "" };
            for run in se.points.split(|p| p.is_none()) {
                if run.len() < 2 {
                    continue;
                }
                let pts: Vec<String> = run
                    .iter()
                    .flatten()
                    .map(|&(x, y)| {
                        let (px, py) = m.px(x, y);
                        format!("{px:.2},{py:.2}")
                    })
                    .collect();
                let _ = write!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.8"{dash}/>"#,
                    pts.join(" "),
                    se.color
                );
            }
        }
    }
}

/// "Nice" tick positions (1, 2, 5 x 10^k) covering [a, b].
pub fn ticks(a: f64, b: f64) -> Vec<f64> {
    let span = b - a;
    if !(span.is_finite() && span > 0.0) {
        return vec![];
    }
    let raw = span / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|k| k * mag).find(|st| span / st <= 7.0).unwrap_or(10.0 * mag);
    let first = (a / step).ceil() as i64;
    let last = (b / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn fmt_tick(t: f64, range: (f64, f64)) -> String {
    let span = (range.1 - range.0).abs();
    if t.abs() < span * 1e-9 {
        return "0".into();
    }
    let m = range.0.abs().max(range.1.abs());
    if !(1e-3..1e5).contains(&m) {
        return format!("{t:.1e}");
    }
    let decimals = (-(span / 6.0).log10().floor()).max(0.0) as usize + 1;
    let s = format!("{t:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
