//! Ghost images rasterised from ray grids against the brute-force
//! reference (rays reflecting or refracting at random at every surface),
//! on an uncoated singlet, a coated double Gauss and a wide angle: each
//! ghost's energy within 2%, its centroid within a pixel of a 960-pixel
//! full-frame film, its image within the reference's own noise; and the
//! paraxial ghost list against the plate's closed form.

mod common;

use lens::ghost::image::Entrance;
use lens::ghost::reference::{brute_force, favouring};
use lens::ghost::{ghost_list, rasterise, FilmGrid, GhostImage, Source};
use lens::{DVec3, Prescription, Tracer};

/// A pixel of a 960-pixel-wide full-frame (36 mm) film, mm.
const PIXEL_MM: f64 = 36.0 / 960.0;

fn rmse(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
}

/// The power-weighted mean pixel centre of an image on `grid`, mm.
fn frame_centroid(grid: &FilmGrid, power: &[f64]) -> [f64; 2] {
    let (mut sum, mut at) = (0.0, [0.0; 2]);
    for (k, w) in power.iter().enumerate() {
        let (i, j) = (k % grid.nx, k / grid.nx);
        let x = grid.centre_mm[0] + (i as f64 + 0.5 - grid.nx as f64 / 2.0) * grid.pixel_mm;
        let y = grid.centre_mm[1] + (j as f64 + 0.5 - grid.ny as f64 / 2.0) * grid.pixel_mm;
        sum += w;
        at = [at[0] + w * x, at[1] + w * y];
    }
    [at[0] / sum, at[1] / sum]
}

/// Mean and standard error of the mean.
fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (v / n).sqrt())
}

/// The ghost `[i, j]` of `p` at `field_deg` rasterised and by brute force
/// (8 independent runs favouring the ghost's surfaces): all its energy on
/// the film plane, its centroid and image on the full frame (36 x 24 mm,
/// 0.5 mm pixels) compared.
fn check_ghost(name: &str, p: &Prescription, i: usize, j: usize, field_deg: f64, rays: usize) {
    let f = field_deg.to_radians();
    let source = Source::Direction(DVec3::new(0.0, f.sin(), f.cos()));
    let entrance = Entrance::of(p, &source);
    let tracer = Tracer::ghost(p, i, j, p.film_distance()).unwrap();
    let grid = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 0.5, nx: 72, ny: 48 };
    let raster = rasterise(&tracer, &source, &entrance, &grid, 128);
    let choice = favouring(vec![i, j], 0.5);
    // the brute-force rays over the part of the entrance that the ghost's
    // light can take (with two cells of 128 to spare each side)
    let Some(near) = entrance.around_passing(&tracer, &source, 128, 8) else {
        assert_eq!(raster.total, 0.0);
        return;
    };
    const RUNS: usize = 8;
    let mc: Vec<GhostImage> = (0..RUNS as u64)
        .map(|seed| {
            let mut all = brute_force(p, &source, &near, &grid, rays / RUNS, &choice, 17 + seed);
            all.remove(&vec![j, i]).unwrap_or_else(|| GhostImage::empty(&grid))
        })
        .collect();
    let (total, noise) = mean_se(&mc.iter().map(|m| m.total).collect::<Vec<_>>());
    if total <= 0.0 {
        assert!(
            raster.total < 1e-9,
            "{name} ghost {}-{}: {} rasterised, none by brute force",
            i + 1,
            j + 1,
            raster.total
        );
        return;
    }
    let energy = (raster.total - total).abs() / total;
    let on_frame: f64 = raster.power.iter().sum();
    let mut shift_ok = true;
    let mut shift_px = 0.0;
    let mut shift_se = 0.0;
    if on_frame > 1e-3 * raster.total {
        let cs: Vec<[f64; 2]> = mc.iter().map(|m| frame_centroid(&grid, &m.power)).collect();
        let c = raster.power.iter().sum::<f64>();
        let rc = frame_centroid(&grid, &raster.power);
        assert!(c > 0.0);
        for k in 0..2 {
            let (m, se) = mean_se(&cs.iter().map(|c| c[k]).collect::<Vec<_>>());
            let d = (rc[k] - m).abs();
            shift_px = f64::max(shift_px, d / PIXEL_MM);
            shift_se = f64::max(shift_se, se / PIXEL_MM);
            shift_ok &= d < PIXEL_MM + 3.0 * se;
        }
    }
    let mean: Vec<f64> =
        (0..raster.power.len()).map(|k| mc.iter().map(|m| m.power[k]).sum::<f64>() / RUNS as f64).collect();
    let own = (0..raster.power.len())
        .map(|k| mean_se(&mc.iter().map(|m| m.power[k]).collect::<Vec<_>>()).1.powi(2))
        .sum::<f64>()
        .sqrt()
        / (raster.power.len() as f64).sqrt();
    let err = rmse(&raster.power, &mean);
    eprintln!(
        "{name} ghost {}-{}: energy {:.4e} vs {:.4e} ({:.2}%, ref noise {:.2}%), frame centroid off {:.2} px (ref noise {:.2} px), frame rmse {:.3e} (ref noise {:.3e})",
        i + 1,
        j + 1,
        raster.total,
        total,
        100.0 * energy,
        100.0 * noise / total,
        shift_px,
        shift_se,
        err,
        own
    );
    assert!(energy < 0.02, "{name} ghost {}-{}: energy off by {:.2}%", i + 1, j + 1, 100.0 * energy);
    assert!(shift_ok, "{name} ghost {}-{}: centroid {shift_px:.2} px off", i + 1, j + 1);
    assert!(err <= 1.25 * own, "{name} ghost {}-{}: rmse {err:.3e} vs noise {own:.3e}", i + 1, j + 1);
}

fn lens(path: &str) -> Prescription {
    Prescription::load(common::data_dir().join(path)).unwrap()
}

/// The ghosts a test checks: the three brightest (by the rasteriser) and
/// two more across the list.
fn chosen(p: &Prescription, field_deg: f64) -> Vec<[usize; 2]> {
    let f = field_deg.to_radians();
    let source = Source::Direction(DVec3::new(0.0, f.sin(), f.cos()));
    let entrance = Entrance::of(p, &source);
    let wide = FilmGrid { centre_mm: [0.0; 2], pixel_mm: 1.0, nx: 1, ny: 1 };
    let pairs = lens::ghost::ghost_pairs(p);
    let mut e: Vec<(f64, [usize; 2])> = pairs
        .iter()
        .map(|&[i, j]| {
            let t = Tracer::ghost(p, i, j, p.film_distance()).unwrap();
            (rasterise(&t, &source, &entrance, &wide, 24).total, [i, j])
        })
        .collect();
    e.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out: Vec<[usize; 2]> = e.iter().take(3).map(|x| x.1).collect();
    out.push(pairs[pairs.len() / 3]);
    out.push(pairs[2 * pairs.len() / 3]);
    out.dedup();
    out
}

#[test]
fn uncoated_singlet_ghost_matches_brute_force() {
    let p = common::singlet(Some(51.5), Some(-300.0), 6.0, 1.5168, 12.0, 85.0);
    assert_eq!(lens::ghost::ghost_pairs(&p), vec![[0, 1]]);
    check_ghost("singlet", &p, 0, 1, 3.0, 6_400_000);
}

#[test]
fn double_gauss_ghosts_match_brute_force() {
    let p = lens("double-gauss-50mm.json");
    for [i, j] in chosen(&p, 8.0) {
        check_ghost("double Gauss", &p, i, j, 8.0, 6_400_000);
    }
}

#[test]
fn wide_angle_ghosts_match_brute_force() {
    let p = lens("wide-angle-22mm.json");
    for [i, j] in chosen(&p, 20.0) {
        check_ghost("wide angle", &p, i, j, 20.0, 6_400_000);
    }
}

/// A plane-parallel plate in front of an ideal lens: the plate's ghost is
/// the primary image moved by the plate's extra crossings (same height,
/// chief ray unchanged), so its irradiance relative to the primary's is
/// R^2 exactly (the extra T^2 / T^2 cancels), bare or coated.
#[test]
fn plate_ghost_intensity_is_r_squared() {
    let n: f64 = 1.5168;
    for (coating, r) in [
        ("none", ((n - 1.0) / (n + 1.0)).powi(2)),
        ("MgF2", ((n - lens::coating::MGF2_INDEX.powi(2)) / (n + lens::coating::MGF2_INDEX.powi(2))).powi(2)),
    ] {
        let p = Prescription::from_json_str(
            &format!(
                r#"{{"wavelengths_nm": [550], "surfaces": [
                {{"thickness": 5, "ior": {n}, "semi_diameter": 15, "coating": "{coating}"}},
                {{"thickness": 10, "semi_diameter": 15, "coating": "{coating}"}},
                {{"type": "paraxial", "focal_length_mm": 50, "thickness": 50, "semi_diameter": 10, "stop": true}}]}}"#
            ),
            "<test>",
        )
        .unwrap();
        let g = ghost_list(&p, 10.0).unwrap();
        assert_eq!(g.len(), 1);
        let g = g[0];
        assert_eq!(g.surfaces, [1, 2]);
        assert!((g.intensity.unwrap() - r * r).abs() < 1e-12 * r * r, "{coating}: {:?} vs {}", g.intensity, r * r);
        assert!((g.reflectance - r * r).abs() < 1e-15);
        // in collimated light the plate's ghost focuses with the primary
        assert!((g.focus_z_mm.unwrap() - 65.0).abs() < 1e-9, "{:?}", g.focus_z_mm);
        assert!(g.radius_mm < 1e-12, "{}", g.radius_mm);
        assert!((g.image_height_mm - 50.0 * 10f64.to_radians().tan()).abs() < 1e-9);
    }
}

/// A plate behind a lens, in converging light: the ghost crosses the plate
/// three times, two of them folded back, so it focuses 2 t / n in front of
/// the primary image (unfolded, 3 t (1 - 1/n) of focus shift on a path 2 t
/// longer), and its blur on the film is the marginal ray's over that gap.
#[test]
fn plate_in_converging_light_moves_the_ghost_focus() {
    let (n, t, f) = (1.5168f64, 4.0, 50.0);
    let primary = f + 10.0 - 10.0 + t * (1.0 - 1.0 / n);
    let p = Prescription::from_json_str(
        &format!(
            r#"{{"surfaces": [
            {{"type": "paraxial", "focal_length_mm": {f}, "thickness": 10, "semi_diameter": 10, "stop": true}},
            {{"thickness": {t}, "ior": {n}, "semi_diameter": 15}},
            {{"thickness": {}, "semi_diameter": 15}}]}}"#,
            primary - 10.0 - t
        ),
        "<test>",
    )
    .unwrap();
    let g = ghost_list(&p, 0.0).unwrap();
    assert_eq!(g.len(), 1);
    let want = primary - 2.0 * t / n;
    assert!((g[0].focus_z_mm.unwrap() - want).abs() < 1e-9, "{:?} vs {want}", g[0].focus_z_mm);
    // marginal ray: height 10 at the lens, slope 10 / f in air (the plate
    // moves the focus, not the slope)
    let slope = 10.0 / f;
    assert!((g[0].radius_mm - slope * 2.0 * t / n).abs() < 1e-9, "{}", g[0].radius_mm);
}
