//! Glasses: index against wavelength, and the glass map (nd against vd).

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::glass::{Catalogs, Glass};

/// n(λ) of `glasses` over their common valid range within 350-1100 nm,
/// 200 points each, with the F, d and C lines marked.
pub fn dispersion_chart(glasses: &[&Glass]) -> String {
    let lo = glasses.iter().map(|g| g.range_nm[0]).fold(350.0f64, f64::max);
    let hi = glasses.iter().map(|g| g.range_nm[1]).fold(1100.0f64, f64::min).max(lo + 1.0);
    let mut panel = Panel {
        title: "refractive index against wavelength".into(),
        x_label: "wavelength (nm)".into(),
        y_label: "n".into(),
        ..Panel::default()
    };
    for (k, g) in glasses.iter().enumerate() {
        let pts: Vec<(f64, f64)> = (0..=200)
            .map(|i| lo + (hi - lo) * i as f64 / 200.0)
            .filter_map(|nm| g.index(nm).ok().map(|n| (nm, n)))
            .collect();
        panel.series.push(Series::new(g.full_name(), pts, PALETTE[k % PALETTE.len()], Style::Line));
        let lines: Vec<(f64, f64)> = [lens::glass::LINE_F_NM, lens::glass::LINE_D_NM, lens::glass::LINE_C_NM]
            .iter()
            .filter_map(|&nm| g.index(nm).ok().map(|n| (nm, n)))
            .collect();
        let label = if k == 0 { "F, d, C lines" } else { "" };
        panel.series.push(Series::new(label, lines, PALETTE[k % PALETTE.len()], Style::Dots(3.5)));
    }
    let name = glasses.iter().map(|g| g.full_name()).collect::<Vec<_>>().join(", ");
    Figure { title: format!("Dispersion: {name}"), panels: vec![panel], columns: 1, panel_size: (640.0, 420.0) }
        .to_svg()
}

/// The glass map of the loaded catalogues: nd against vd (vd decreasing to
/// the right, as glass maps are drawn), one colour per catalogue.
pub fn glass_map(cats: &Catalogs) -> String {
    let mut panel = Panel {
        title: "nd against vd (vd decreasing to the right, drawn as -vd)".into(),
        x_label: "- Abbe number vd".into(),
        y_label: "nd".into(),
        ..Panel::default()
    };
    for (k, c) in cats.catalogs.iter().filter(|c| c.glasses.len() > 20).enumerate() {
        let pts: Vec<(f64, f64)> =
            c.glasses.iter().filter_map(|g| Some((-g.vd().ok()?, g.nd().ok()?))).filter(|(v, _)| *v > -110.0).collect();
        if !pts.is_empty() {
            panel.series.push(Series::new(
                format!("{} ({})", c.name, pts.len()),
                pts,
                PALETTE[k % PALETTE.len()],
                Style::Dots(2.0),
            ));
        }
    }
    Figure { title: "Glass map".into(), panels: vec![panel], columns: 1, panel_size: (900.0, 600.0) }.to_svg()
}
