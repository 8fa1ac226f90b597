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
    let m = w.measure(std::time::Duration::from_millis(1500));
    if a.out.json {
        print_json(&json!({
            "rays": a.rays,
            "surfaces": p.surfaces().len(),
            "passes": m.passes,
            "seconds": m.seconds,
            "rays_per_second": m.rays_per_second,
            "ray_surface_per_second": m.ray_surface_per_second,
            "median_rays_per_second": m.median_rays_per_second,
            "median_ray_surface_per_second": m.median_ray_surface_per_second,
            "reached_fraction": m.reached_fraction,
        }))?;
    } else {
        outln!("{} rays x {} passes through {} surfaces, one thread", a.rays, m.passes, p.surfaces().len());
        outln!("  {:.3e} rays/s (fastest pass; median {:.3e})", m.rays_per_second, m.median_rays_per_second);
        outln!(
            "  {:.3e} ray-surface intersections/s (fastest pass; median {:.3e})",
            m.ray_surface_per_second,
            m.median_ray_surface_per_second
        );
        outln!("  {:.1}% of rays reach the film", 100.0 * m.reached_fraction);
    }
    Ok(ExitCode::SUCCESS)
}
