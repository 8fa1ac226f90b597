//! `lens bench`: throughput of the batch tracer on one thread, or
//! (`--wave DEG`) the time of one field's wave analyses.

use crate::args::{JsonArgs, LensArgs};
use crate::{print_json, CmdResult};
use lens::trace::bench::Workload;
use serde_json::json;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    /// Number of rays per pass.
    #[arg(long, default_value_t = 1_000_000)]
    rays: usize,
    /// Instead: time the wave analyses of one field at this angle
    /// (degrees): the wavefront on the grid it needs, its RMS, P-V and
    /// Strehl, both Zernike fits, and the T and S MTF at 10, 20 and 40
    /// cycles/mm; the library's time, runs repeated for 1.5 s, also
    /// without the Zernike fits and part by part (medians).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    wave: Option<f64>,
    #[command(flatten)]
    out: JsonArgs,
}

/// `--wave DEG`: the wave analyses of one field, timed.
fn wave(a: &Args, deg: f64) -> CmdResult {
    use lens::analysis::wave::{mtf::mtf, stats, wavefront_auto, zernike};
    let p = a.lens.load()?;
    let first = lens::paraxial::FirstOrder::of(&p)?;
    let plane = lens::analysis::fan::ImagePlane::ImageSurface;
    // The parts timed one by one, in the order a user's call runs them:
    // the wavefront (rays traced, OPD), its statistics with the Strehl
    // ratio, the two Zernike fits, the T and S MTF.
    const PARTS: [&str; 4] = ["wavefront", "rms_pv_strehl", "zernike_fits", "mtf"];
    let once = || -> Result<(usize, [f64; 4]), lens::OpticsError> {
        let mut parts = [0.0; 4];
        let mut t = std::time::Instant::now();
        let mut lap = |i: usize| {
            parts[i] = t.elapsed().as_secs_f64();
            t = std::time::Instant::now();
        };
        let launcher = lens::analysis::Launcher::with_first(
            &p,
            &first,
            lens::analysis::Field::at_angle(&p, &first, deg),
            lens::analysis::Aim::Paraxial,
        )?;
        let w = wavefront_auto(&p, &p, &launcher, plane)?;
        lap(0);
        std::hint::black_box(stats(&w));
        lap(1);
        std::hint::black_box(zernike::fit(&w, zernike::ZernikeKind::Fringe, zernike::TERMS));
        std::hint::black_box(zernike::fit(&w, zernike::ZernikeKind::Standard, zernike::TERMS));
        lap(2);
        std::hint::black_box(mtf(&p, &p, &launcher, plane, &[10.0, 20.0, 40.0])?);
        lap(3);
        Ok((w.grid.n, parts))
    };
    let (grid, _) = once()?;
    let mut runs: Vec<[f64; 4]> = Vec::new();
    let start = std::time::Instant::now();
    while start.elapsed().as_secs_f64() < 1.5 || runs.len() < 5 {
        runs.push(once()?.1);
    }
    let median = |f: &dyn Fn(&[f64; 4]) -> f64| {
        let mut v: Vec<f64> = runs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        (v[0], v[v.len() / 2])
    };
    let (fastest, median_total) = median(&|r| r.iter().sum());
    // The set (RMS, Strehl, T and S MTF) without the Zernike fits.
    let (fastest_no_zernike, median_no_zernike) = median(&|r| r[0] + r[1] + r[3]);
    let part_medians: Vec<f64> = (0..4).map(|i| median(&|r| r[i]).1).collect();
    let times_len = runs.len();
    if a.out.json {
        let parts: serde_json::Map<String, serde_json::Value> =
            PARTS.iter().zip(&part_medians).map(|(k, v)| (k.to_string(), json!(v))).collect();
        print_json(&json!({
            "wave_field_deg": deg,
            "pupil_samples": grid,
            "runs": times_len,
            "seconds_fastest": fastest,
            "seconds_median": median_total,
            "seconds_fastest_without_zernike": fastest_no_zernike,
            "seconds_median_without_zernike": median_no_zernike,
            "seconds_median_parts": parts,
        }))?;
    } else {
        outln!(
            "wave analyses at {deg} deg ({grid} x {grid} pupil grid): fastest {:.2} ms, median {:.2} ms over {times_len} runs; without the Zernike fits {:.2} ms (median {:.2})",
            fastest * 1e3,
            median_total * 1e3,
            fastest_no_zernike * 1e3,
            median_no_zernike * 1e3,
        );
        let parts: Vec<String> =
            PARTS.iter().zip(&part_medians).map(|(k, v)| format!("{k} {:.2} ms", v * 1e3)).collect();
        outln!("  median parts: {}", parts.join(", "));
    }
    Ok(ExitCode::SUCCESS)
}

pub fn run(a: Args) -> CmdResult {
    if let Some(deg) = a.wave {
        return wave(&a, deg);
    }
    let p = a.lens.load()?;
    let w = Workload::new(&p, a.rays)?;
    let budget = std::time::Duration::from_millis(1500);
    // a lens with glasses: the monochromatic and the mixed-wavelength
    // traces, passes alternating
    let (m, mixed) = if p.is_dispersive() {
        a.lens.catalogs.report(&p, &[400.0, 700.0])?;
        let (m, s) = w.measure_spectral(budget)?;
        (m, Some(s))
    } else {
        (w.measure(budget), None)
    };
    if a.out.json {
        let mut v = json!({
            "rays": a.rays,
            "surfaces": p.surfaces().len(),
            "passes": m.passes,
            "seconds": m.seconds,
            "rays_per_second": m.rays_per_second,
            "ray_surface_per_second": m.ray_surface_per_second,
            "median_rays_per_second": m.median_rays_per_second,
            "median_ray_surface_per_second": m.median_ray_surface_per_second,
            "reached_fraction": m.reached_fraction,
        });
        if let Some(s) = &mixed {
            v["mixed_wavelengths"] = json!({
                "wavelength_range_nm": [400.0, 700.0],
                "passes": s.passes,
                "rays_per_second": s.rays_per_second,
                "median_rays_per_second": s.median_rays_per_second,
                "ratio_to_monochromatic": s.rays_per_second / m.rays_per_second,
                "median_ratio_to_monochromatic": s.median_rays_per_second / m.median_rays_per_second,
            });
        }
        print_json(&v)?;
    } else {
        outln!("{} rays x {} passes through {} surfaces, one thread", a.rays, m.passes, p.surfaces().len());
        outln!("  {:.3e} rays/s (fastest pass; median {:.3e})", m.rays_per_second, m.median_rays_per_second);
        outln!(
            "  {:.3e} ray-surface intersections/s (fastest pass; median {:.3e})",
            m.ray_surface_per_second,
            m.median_ray_surface_per_second
        );
        outln!("  {:.1}% of rays reach the film", 100.0 * m.reached_fraction);
        if let Some(s) = &mixed {
            outln!(
                "  mixed wavelengths (each ray its own, 400-700 nm): {:.3e} rays/s = {:.1}% of monochromatic (median {:.1}%)",
                s.rays_per_second,
                100.0 * s.rays_per_second / m.rays_per_second,
                100.0 * s.median_rays_per_second / m.median_rays_per_second
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
