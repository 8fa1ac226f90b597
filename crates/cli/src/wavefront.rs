//! `lens wavefront`: the wavefront error of one field (OPD to the exit
//! pupil's reference sphere), its statistics and Zernike fits.

use crate::args::{AimArgs, FieldArgs, GridArgs, JsonArgs, LensArgs, PlaneArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::wave::stats;
use lens::analysis::wave::zernike::{fit, ZernikeKind, TERMS};
use lens::analysis::Launcher;
use lens::paraxial::FirstOrder;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    lens: LensArgs,
    #[command(flatten)]
    field: FieldArgs,
    #[command(flatten)]
    aim: AimArgs,
    #[command(flatten)]
    plane: PlaneArgs,
    #[command(flatten)]
    wavelength: WavelengthArgs,
    #[command(flatten)]
    grid: GridArgs,
    /// With --json: also every sample of the map, as "samples": {"px",
    /// "py" (normalised pupil), "weight" (its cell's area inside the
    /// pupil, 0-1), "opd_waves" (null where vignetted)}.
    #[arg(long)]
    samples: bool,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(args: Args) -> CmdResult {
    args.lens.check_plot(args.plot.plot.as_deref())?;
    let plane = args.plane.plane()?;
    let (p, traced) = args.lens.load_at(args.wavelength.wavelength_nm)?;
    let first = FirstOrder::of(&p)?;
    let field_deg = args.field.field_deg;
    args.field.check()?;
    let launcher = Launcher::with_first(&p, &first, args.field.field(&p, &first), args.aim.aim())?;
    let w = args.grid.wavefront(&p, &traced, &launcher, plane)?;
    let s = stats(&w);
    let fringe = fit(&w, ZernikeKind::Fringe, TERMS);
    let standard = fit(&w, ZernikeKind::Standard, TERMS);
    if let Some(out) = &args.plot.plot {
        plot::save(&plot::wave::wavefront_map(&w, &s, &args.lens.name(&p)), out)?;
    }
    let exit = w.exit_pupil;
    if args.out.json {
        let fits = lens::report::Fits { fringe: fringe.as_ref(), standard: standard.as_ref() };
        print_json(&args.field.report(lens::report::wavefront(field_deg, plane, &w, &s, fits, args.samples)))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "wavefront at {}, {} nm, on {}: {} x {} pupil grid, {} rays, {} vignetted",
        args.field.describe(),
        w.wavelength_nm,
        crate::args::describe_plane(plane, w.image_z),
        w.grid.n,
        w.grid.n,
        w.opd_waves.len(),
        w.vignetted
    );
    outln!(
        "  RMS                 {:.6} waves (to chief), {:.6} waves (to centroid)",
        s.rms_to_chief,
        s.rms_to_centroid
    );
    outln!("  peak to valley      {:.6} waves (to chief), {:.6} waves (to centroid)", s.pv_to_chief, s.pv_to_centroid);
    outln!("  Strehl ratio        {:.6}", s.strehl);
    match exit {
        Some(e) => outln!(
            "  reference sphere    radius {:.6} mm, through the paraxial exit pupil (z = {:.6} mm, diameter {:.6} mm)",
            w.reference_radius,
            e.z,
            e.diameter
        ),
        None => outln!(
            "  reference sphere    radius {:.6} mm (image space telecentric: back to the last vertex's plane)",
            w.reference_radius
        ),
    }
    for (name, f) in [("Fringe", &fringe), ("Standard (Noll, RMS-normalised)", &standard)] {
        let Some(f) = f else {
            outln!("  Zernike {name}: too few rays pass to fit {TERMS} terms");
            continue;
        };
        outln!("  Zernike {name} coefficients, waves (fit residual RMS {:.2e}):", f.rms_residual);
        for (k, c) in f.coefficients.iter().enumerate() {
            outln!("    Z{:<3} {:+.6}", k + 1, c);
        }
    }
    Ok(ExitCode::SUCCESS)
}
