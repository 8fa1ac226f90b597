//! `lens bench`: throughput of the batch tracer on one thread.

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
    #[command(flatten)]
    out: JsonArgs,
}

pub fn run(a: Args) -> CmdResult {
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
