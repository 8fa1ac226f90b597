//! `lens wavefront`: the wavefront error of one field (OPD to the exit
//! pupil's reference sphere), its statistics and Zernike fits.

use crate::args::{AimArgs, FieldArgs, GridArgs, JsonArgs, LensArgs, PlaneArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::wave::stats;
use lens::analysis::wave::zernike::{fit, ZernikeKind, TERMS};
use lens::analysis::{Field, Launcher};
use lens::paraxial::FirstOrder;
use serde_json::json;
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
    crate::args::check_fields("--field-deg", &[field_deg])?;
    let launcher = Launcher::with_first(&p, &first, Field::at_angle(&p, &first, field_deg), args.aim.aim())?;
    let w = args.grid.wavefront(&p, &traced, &launcher, plane)?;
    let s = stats(&w);
    let fringe = fit(&w, ZernikeKind::Fringe, TERMS);
    let standard = fit(&w, ZernikeKind::Standard, TERMS);
    if let Some(out) = &args.plot.plot {
        plot::save(&plot::wave::wavefront_map(&w, &s, &args.lens.name(&p)), out)?;
    }
    let exit = w.exit_pupil;
    if args.out.json {
        let samples = args.samples.then(|| {
            let cells = &w.grid.cells;
            json!({
                "px": cells.iter().map(|c| c.centre.0).collect::<Vec<_>>(),
                "py": cells.iter().map(|c| c.centre.1).collect::<Vec<_>>(),
                "weight": cells.iter().map(|c| c.area).collect::<Vec<_>>(),
                "opd_waves": &w.opd_waves,
            })
        });
        print_json(&json!({
            "field_deg": field_deg,
            "wavelength_nm": w.wavelength_nm,
            "image_plane": plane.name(),
            "image_z": w.image_z,
            "pupil_samples": w.grid.n,
            "rays": w.opd_waves.len(),
            "vignetted": w.vignetted,
            "rms_waves": s.rms_to_chief,
            "pv_waves": s.pv_to_chief,
            "rms_centroid_waves": s.rms_to_centroid,
            "pv_centroid_waves": s.pv_to_centroid,
            "strehl": s.strehl,
            "zernike_fringe": fringe.as_ref().map(|f| &f.coefficients),
            "zernike_fringe_order": "Fringe (University of Arizona) order, 1-based, not normalised, waves",
            "zernike_standard": standard.as_ref().map(|f| &f.coefficients),
            "zernike_standard_order": "Standard (Noll) order, 1-based, RMS-normalised, waves",
            "zernike_fringe_rms_residual_waves": fringe.as_ref().map(|f| f.rms_residual),
            "zernike_standard_rms_residual_waves": standard.as_ref().map(|f| f.rms_residual),
            "exit_pupil_mm": exit.map(|e| e.diameter),
            "exit_pupil_z": exit.map(|e| e.z),
            "reference_radius_mm": w.reference_radius,
            "chief_image": [w.chief_image.x, w.chief_image.y, w.chief_image.z],
            "samples": samples,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "wavefront at {} deg, {} nm, on {}: {} x {} pupil grid, {} rays, {} vignetted",
        lens::error::Fixed(field_deg),
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
