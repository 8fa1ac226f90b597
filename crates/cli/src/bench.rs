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
    /// cycles/mm; the library's time, runs repeated for 1.5 s.
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
    let once = || -> Result<usize, lens::OpticsError> {
        let launcher = lens::analysis::Launcher::with_first(
            &p,
            &first,
            lens::analysis::Field::at_angle(&p, &first, deg),
            lens::analysis::Aim::Paraxial,
        )?;
        let w = wavefront_auto(&p, &p, &launcher, plane)?;
        std::hint::black_box(stats(&w));
        std::hint::black_box(zernike::fit(&w, zernike::ZernikeKind::Fringe, zernike::TERMS));
        std::hint::black_box(zernike::fit(&w, zernike::ZernikeKind::Standard, zernike::TERMS));
        std::hint::black_box(mtf(&p, &p, &launcher, plane, &[10.0, 20.0, 40.0])?);
        Ok(w.grid.n)
    };
    let grid = once()?;
    let mut times = Vec::new();
    let start = std::time::Instant::now();
    while start.elapsed().as_secs_f64() < 1.5 || times.len() < 5 {
        let t = std::time::Instant::now();
        once()?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let (fastest, median) = (times[0], times[times.len() / 2]);
    if a.out.json {
        print_json(&json!({
            "wave_field_deg": deg,
            "pupil_samples": grid,
            "runs": times.len(),
            "seconds_fastest": fastest,
            "seconds_median": median,
        }))?;
    } else {
        outln!(
            "wave analyses at {deg} deg ({grid} x {grid} pupil grid): fastest {:.2} ms, median {:.2} ms over {} runs",
            fastest * 1e3,
            median * 1e3,
            times.len()
        );
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
