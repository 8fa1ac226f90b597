//! Spot diagram plots with the Airy disk for scale.

use crate::figure::{Circle, Figure, Panel, Series, Style, PALETTE};
use lens::analysis::spot::SpotDiagram;

/// About the most ray points drawn in one panel.
pub const MAX_DRAWN: usize = 20_000;

/// SplitMix64's finaliser: a well-spread hash of an index.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A figure with one panel per spot: ray positions relative to the chief
/// ray in micrometres, same scale on both axes, the Airy disk drawn around
/// the chief ray.
pub fn spot_chart(spots: &[SpotDiagram], name: &str) -> String {
    let panels = spots
        .iter()
        .enumerate()
        .map(|(k, s)| {
            // a plot stays a plot: about MAX_DRAWN points, one in `every`
            // chosen by a hash of its index (a fixed stride would draw
            // moire patterns of the ring patterns); the statistics in the
            // title use them all
            let every = s.hits.len().div_ceil(MAX_DRAWN).max(1) as u64;
            let drawn = if every > 1 { format!(", 1 in {every} drawn") } else { String::new() };
            // one series per wavelength, coloured by it where there are several
            let mut series = Vec::new();
            let mut start = 0;
            for (w, &count) in s.hits_per_wavelength.iter().enumerate() {
                let pts = (start..start + count)
                    .filter(|i| every == 1 || mix(*i as u64).is_multiple_of(every))
                    .map(|i| ((s.hits[i][0] - s.chief[0]) * 1e3, (s.hits[i][1] - s.chief[1]) * 1e3))
                    .collect();
                start += count;
                let (label, colour) = match (s.wavelengths_nm.len(), s.wavelengths_nm.get(w)) {
                    (2.., Some(&nm)) => (format!("{nm} nm, {count} rays"), crate::chromatic::wavelength_color(nm)),
                    _ => (
                        format!("{} rays, {} vignetted{drawn}", s.rays, s.vignetted),
                        PALETTE[k % PALETTE.len()].to_string(),
                    ),
                };
                series.push(Series::new(label, pts, &colour, Style::Dots(1.4)));
            }
            let field = crate::field_label(s.field_x_deg, s.field_deg);
            Panel {
                title: format!("{field}: RMS {:.2} µm, GEO {:.2} µm", s.rms_radius * 1e3, s.geo_radius * 1e3),
                x_label: "x - chief (µm)".into(),
                y_label: "y - chief (µm)".into(),
                series,
                circles: vec![Circle {
                    center: (0.0, 0.0),
                    radius: s.airy_radius * 1e3,
                    color: "#222".into(),
                    label: format!("Airy radius {:.2} µm", s.airy_radius * 1e3),
                }],
                equal_aspect: true,
                ..Panel::default()
            }
        })
        .collect::<Vec<_>>();
    let columns = panels.len().clamp(1, 3);
    Figure { title: format!("Spot diagram: {name}"), panels, columns, panel_size: (380.0, 380.0) }.to_svg()
}
