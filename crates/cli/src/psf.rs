//! `lens psf`: the point spread function of a field (FFT or Huygens), its
//! Strehl ratio and encircled energy.

use crate::args::{AimArgs, FieldArgs, GridArgs, JsonArgs, LensArgs, PlaneArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::wave::field_psf::{field_psf, PsfOptions};
use lens::analysis::wave::psf::{Psf, PsfMethod};
use lens::analysis::Launcher;
use lens::paraxial::FirstOrder;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum MethodArg {
    /// The FFT of the zero-padded pupil function (Fraunhofer).
    Fft,
    /// Huygens wavelets from the reference sphere onto the image plane.
    Huygens,
}

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
    /// How the PSF is computed.
    #[arg(long, value_enum, default_value_t = MethodArg::Fft)]
    method: MethodArg,
    #[command(flatten)]
    grid: GridArgs,
    /// Samples per lambda N_w on the image plane (the FFT's padding Q:
    /// pixel = lambda N_w / Q along each direction).
    #[arg(long, value_name = "Q", default_value_t = 4)]
    pad: usize,
    /// Huygens image size, pixels across.
    #[arg(long, value_name = "N", default_value_t = 64)]
    pixels: usize,
    /// Plot the image on a linear scale instead of 4 decades of log10.
    #[arg(long)]
    linear: bool,
    /// Also write the image (linear, normalised to the aberration-free
    /// peak, +y up) as an OpenEXR file.
    #[arg(long, value_name = "OUT.exr")]
    exr: Option<PathBuf>,
    /// Every wavelength of the prescription with its weight
    /// (`wavelength_weights`): their PSFs (FFT method, each normalised to
    /// its own aberration-free peak) summed on the primary wavelength's
    /// grid about its chief ray.
    #[arg(long, conflicts_with = "wavelength_nm")]
    polychromatic: bool,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

pub fn run(args: Args) -> CmdResult {
    args.lens.check_plot(args.plot.plot.as_deref())?;
    args.lens.check_output(args.exr.as_deref(), "--exr", &["exr"])?;
    if !(2..=64).contains(&args.pad) {
        return Err(format!("--pad {}: give 2 to 64 samples per lambda N_w", args.pad).into());
    }
    if !(8..=1024).contains(&args.pixels) {
        return Err(format!("--pixels {}: give 8 to 1024 pixels across", args.pixels).into());
    }
    let plane = args.plane.plane()?;
    let (p, traced) = args.lens.load_at(args.wavelength.wavelength_nm)?;
    let first = FirstOrder::of(&p)?;
    let field_deg = args.field.field_deg;
    args.field.check()?;
    let launcher = Launcher::with_first(&p, &first, args.field.field(&p, &first), args.aim.aim())?;
    if args.polychromatic && matches!(args.method, MethodArg::Huygens) {
        return Err("--polychromatic sums FFT (Fraunhofer) images on one grid; leave out --method huygens".into());
    }
    if args.polychromatic {
        args.lens.catalogs.report(&p, p.wavelengths_nm())?;
    }
    let options = PsfOptions {
        method: match args.method {
            MethodArg::Fft => PsfMethod::Fft,
            MethodArg::Huygens => PsfMethod::Huygens,
        },
        pad: args.pad,
        pixels: args.pixels,
        grid: args.grid.grid,
        polychromatic: args.polychromatic,
    };
    let f = field_psf(&p, &traced, &launcher, plane, &options)?;
    let (w, s, psf, centroid) = (&f.wavefront, &f.stats, &f.psf, f.centroid);
    let (radii, ee, geo_ee) = (&f.radii_mm, f.encircled.as_slice(), f.geometric_encircled.as_slice());
    let reach = 0.45 * psf.size as f64 * psf.pixel_mm.0.min(psf.pixel_mm.1);
    if let Some(out) = &args.plot.plot {
        // crop to where the encircled energy reaches 99%, at least 16 pixels
        let r99 = radii.iter().zip(ee).find(|(_, f)| **f >= 0.99).map_or(reach, |(r, _)| *r);
        let half = ((r99 / psf.pixel_mm.0.min(psf.pixel_mm.1)).ceil() as usize).clamp(16, psf.size / 2);
        let light = if args.polychromatic {
            format!("{} wavelengths", p.wavelengths_nm().len())
        } else {
            format!("{} nm, Strehl {:.4}", w.wavelength_nm, s.strehl)
        };
        let title = format!("PSF: {}, {}, {light}", args.lens.name(&p), args.field.describe());
        let curve: Vec<(f64, f64)> =
            std::iter::once((0.0, 0.0)).chain(radii.iter().copied().zip(ee.iter().copied())).collect();
        let geometric: Vec<(f64, f64)> =
            std::iter::once((0.0, 0.0)).chain(radii.iter().copied().zip(geo_ee.iter().copied())).collect();
        let log = (!args.linear).then_some(4.0);
        plot::save(&plot::wave::psf_chart(&title, psf, half, log, &curve, &geometric), out)?;
    }
    if let Some(path) = &args.exr {
        write_exr(psf, path)?;
    }
    if args.out.json {
        print_json(&args.field.report(lens::report::psf(field_deg, plane, &f)))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "{} PSF at {}, {} nm, on {}: {} x {} pixels of {:.4e} x {:.4e} mm, pupil grid {}",
        psf.method.name(),
        args.field.describe(),
        w.wavelength_nm,
        crate::args::describe_plane(plane, w.image_z),
        psf.size,
        psf.size,
        psf.pixel_mm.0,
        psf.pixel_mm.1,
        w.grid.n
    );
    if args.polychromatic {
        outln!(
            "  peak                {:.6} of the wavelengths' aberration-free peaks (Strehl ratio at {} nm: {:.6})",
            psf.peak(),
            w.wavelength_nm,
            s.strehl
        );
    } else {
        outln!(
            "  Strehl ratio        {:.6} (peak found off-grid; the grid's largest pixel {:.6})",
            s.strehl,
            psf.peak()
        );
    }
    outln!("  centroid            x {:+.4e}, y {:+.4e} mm from the chief ray's image point", centroid.0, centroid.1);
    for target in [0.5, 0.8, 0.9] {
        let at = |v: &[f64]| {
            radii.iter().zip(v).find(|(_, f)| **f >= target).map_or("-".to_string(), |(r, _)| format!("{r:.4e}"))
        };
        outln!(
            "  encircled {:>3.0}%      within {} mm of the centroid (geometric, from the spot: {} mm)",
            target * 100.0,
            at(ee),
            at(geo_ee)
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The PSF as a linear grey OpenEXR image, +y up.
fn write_exr(psf: &Psf, path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let n = psf.size;
    let pixels = (0..n * n)
        .map(|i| {
            let (col, row) = (i % n, n - 1 - i / n);
            lens::DVec3::splat(psf.intensity[row * n + col])
        })
        .collect();
    render::image::Image { width: n, height: n, pixels }.save(path, 1.0)?;
    Ok(())
}
