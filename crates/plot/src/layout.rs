//! The lens layout: the classic cross-section of the elements, to scale,
//! with ray bundles from several fields.

use crate::figure::{Figure, Panel, Series, Style, PALETTE};
use lens::analysis::{Aim, Field, Launcher};
use lens::{Prescription, Tracer};

/// Points per surface profile.
const PROFILE: usize = 48;

/// The cross-section in the y-z plane (z across, y up, same scale; a
/// decentred or tilted surface drawn where it sits, projected): glass
/// elements filled with true sags and edges joined, the stop as two bars,
/// the film as a line, and `rays_per_field` meridional rays across the
/// entrance pupil for each field angle (degrees), traced to the film or to
/// where they are blocked.
pub fn layout_chart(p: &Prescription, fields_deg: &[f64], rays_per_field: usize, aim: Aim) -> String {
    let s = p.surfaces();
    let z = p.vertex_z();
    let placements = p.placements();
    // a point (0, h, z) of surface i's own frame, where the surface sits
    // (decentred or tilted), projected on the y-z plane
    let placed = |i: usize, h: f64, sag: f64| -> (f64, f64) {
        let q = placements[i]
            .map_or(lens::DVec3::new(0.0, h, sag), |at| at.rotation * lens::DVec3::new(0.0, h, sag) + at.offset);
        (z[i] + q.z, q.y)
    };
    let profile = |i: usize, sign: f64| -> Vec<(f64, f64)> {
        let sd = s[i].semi_diameter.unwrap_or_else(|| fallback_sd(p, i));
        (0..=PROFILE)
            .map(|k| {
                let h = sign * sd * (1.0 - 2.0 * k as f64 / PROFILE as f64);
                placed(i, h, s[i].sag(h.abs()).unwrap_or(0.0))
            })
            .collect()
    };
    let mut panel = Panel {
        title: match lens::paraxial::FirstOrder::of(p).map(|f| f.efl) {
            Ok(efl) if efl.is_finite() => format!("{} (EFL {efl:.2} mm)", p.name()),
            _ => format!("{} (afocal: no focal length)", p.name()),
        },
        x_label: "z (mm from the first vertex)".into(),
        y_label: "y (mm)".into(),
        equal_aspect: true,
        ..Panel::default()
    };
    // glass: surface i to surface i+1 where the medium is not air
    for (i, surf) in s.iter().enumerate().take(s.len().saturating_sub(1)) {
        if surf.ior != 1.0 {
            let mut poly = profile(i, 1.0);
            poly.extend(profile(i + 1, -1.0));
            panel.polygons.push((poly, "#cfe3f5".into()));
        }
    }
    // bare surfaces in air on both sides (and the stop) as outlines
    for (i, surf) in s.iter().enumerate() {
        let glass_before = i > 0 && s[i - 1].ior != 1.0;
        if surf.ior == 1.0 && !glass_before && !surf.stop {
            panel.series.push(Series::new("", profile(i, 1.0), "#333", Style::Line));
        }
    }
    // stop: two bars outside the clear aperture
    let st = p.stop_index();
    let r = p.stop_semi_diameter();
    let sag = s[st].sag(r).unwrap_or(0.0);
    let outer = r * 1.35 + 1.0;
    panel.series.push(Series::new("stop", vec![placed(st, r, sag), placed(st, outer, sag)], "#000", Style::Line));
    panel.series.push(Series::new("", vec![placed(st, -r, sag), placed(st, -outer, sag)], "#000", Style::Line));
    let z_film = p.total_track();
    let mut film_h = s.iter().filter_map(|x| x.semi_diameter).fold(0.0, f64::max);
    // rays
    let tracer = Tracer::forward(p);
    let n = rays_per_field.max(1);
    for (k, &deg) in fields_deg.iter().enumerate() {
        let Ok(launcher) = Launcher::new(p, Field::Angle(deg), aim) else { continue };
        let color = PALETTE[k % PALETTE.len()];
        for j in 0..n {
            let py = if n == 1 { 0.0 } else { -1.0 + 2.0 * j as f64 / (n - 1) as f64 };
            let Ok(mut ray) = launcher.ray(0.0, py) else { continue };
            // start the drawing a little in front of the first surface
            let start = -0.08 * z_film - 2.0;
            ray.origin = ray.at((start - ray.origin.z) / ray.direction.z);
            let (path, outcome) = tracer.trace_path(ray);
            if let Some(end) = outcome.reached() {
                film_h = film_h.max(end.origin.y.abs() * 1.05);
            }
            let pts = path.iter().map(|q| (q.z, q.y)).collect();
            let label = if j == 0 { format!("{deg} deg") } else { String::new() };
            panel.series.push(Series::new(label, pts, color, Style::Line));
        }
    }
    // film and axis
    panel.series.push(Series::new("film", vec![(z_film, -film_h), (z_film, film_h)], "#555", Style::Line));
    panel.series.push(Series::new("", vec![(-0.1 * z_film, 0.0), (z_film, 0.0)], "#999", Style::Dashed));
    Figure { title: "Lens layout".into(), panels: vec![panel], columns: 1, panel_size: (900.0, 520.0) }.to_svg()
}

/// A semi-diameter for drawing a surface that has none: its neighbours'.
fn fallback_sd(p: &Prescription, i: usize) -> f64 {
    let s = p.surfaces();
    let near =
        [i.checked_sub(1), Some(i + 1)].into_iter().flatten().filter_map(|j| s.get(j)).filter_map(|x| x.semi_diameter);
    let sd = near.fold(0.0, f64::max);
    let sd = if sd > 0.0 { sd } else { p.stop_semi_diameter() };
    match s[i].radius() {
        Some(r) => sd.min(r.abs()),
        None => sd,
    }
}
