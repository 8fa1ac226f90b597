//! `lens spot`: spot diagram statistics at one field.

use crate::args::{AimArgs, FieldArgs, FieldPlotArgs, JsonArgs, LensArgs, PlaneArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::pattern::Pattern;
use lens::analysis::spot::{spot_polychromatic, spot_traced};
use lens::analysis::{Field, Launcher};
use lens::paraxial::FirstOrder;
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum PatternArg {
    /// n Gauss-Legendre rings of 4n + 4 points, weighted by area: the RMS
    /// converges to the true value (the default).
    Gauss,
    /// n x n grid, points inside the unit circle.
    Square,
    /// n rings of 6k points.
    Hexapolar,
    /// n uniform random points (fixed seed).
    Random,
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
    /// Pupil pattern.
    #[arg(long, value_enum, default_value_t = PatternArg::Gauss)]
    pattern: PatternArg,
    /// Ring count (gauss, hexapolar), grid width (square) or ray count
    /// (random).
    #[arg(long, default_value_t = 12)]
    n: usize,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: FieldPlotArgs,
}

pub fn run(args: Args) -> CmdResult {
    args.lens.check_plot(args.plot.plot.as_deref())?;
    let plane = args.plane.plane()?;
    let (p, traced) = args.lens.load_at(args.wavelength.wavelength_nm)?;
    let pattern = match args.pattern {
        PatternArg::Gauss => Pattern::Gauss,
        PatternArg::Square => Pattern::Square,
        PatternArg::Hexapolar => Pattern::Hexapolar,
        PatternArg::Random => Pattern::Random,
    };
    let first = FirstOrder::of(&p)?;
    // every wavelength of the prescription with its weight, as Zemax
    // draws a spot, unless one is asked for
    let waves: Vec<(f64, f64)> = p.wavelengths_nm().iter().copied().zip(p.wavelength_weights()).collect();
    if args.wavelength.wavelength_nm.is_none() {
        args.lens.catalogs.report(&p, p.wavelengths_nm())?;
    }
    args.field.check()?;
    let spot_at = |(x, y): (f64, f64)| -> Result<_, lens::OpticsError> {
        let launcher = Launcher::with_first(&p, &first, Field::at_angles(&p, &first, x, y), args.aim.aim())?;
        match args.wavelength.wavelength_nm {
            Some(_) => spot_traced(&p, &traced, &launcher, pattern, args.n, plane),
            None => spot_polychromatic(&p, &launcher, pattern, args.n, plane, &waves),
        }
    };
    let field_deg = args.field.field_deg;
    let s = spot_at((args.field.field_x_deg, field_deg))?;
    if let Some(out) = &args.plot.plot {
        let fields = args.plot.fields(&args.field)?;
        let spots = fields.into_iter().map(spot_at).collect::<Result<Vec<_>, _>>()?;
        plot::save(&plot::spot::spot_chart(&spots, p.name()), out)?;
    }
    if args.out.json {
        print_json(&args.field.report(lens::report::spot(field_deg, &s)))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "spot at {} on {}, {} pattern: {} rays, {} vignetted",
        args.field.describe(),
        crate::args::describe_plane(plane, s.image_z),
        pattern.name(),
        s.rays,
        s.vignetted
    );
    outln!("  centroid            x {:.6e}, y {:.6e} mm", s.centroid[0], s.centroid[1]);
    outln!(
        "  RMS radius          {:.6e} mm (about the centroid), {:.6e} mm (about the chief ray)",
        s.rms_radius,
        s.rms_radius_chief
    );
    outln!(
        "  geometric radius    {:.6e} mm (about the centroid), {:.6e} mm (about the chief ray)",
        s.geo_radius,
        s.geo_radius_chief
    );
    let waves: Vec<String> = s
        .wavelengths_nm
        .iter()
        .zip(&s.wavelength_weights)
        .map(|(nm, w)| if s.wavelengths_nm.len() > 1 { format!("{nm} (weight {w})") } else { format!("{nm}") })
        .collect();
    outln!("  wavelengths, nm     {}", waves.join(", "));
    outln!("  Airy radius         {:.6e} mm ({} nm)", s.airy_radius, p.wavelength_nm());
    outln!(
        "  best focus          {:+.6e} mm from this plane, RMS radius {:.6e} mm",
        s.best_focus_shift,
        s.rms_radius_best_focus
    );
    Ok(ExitCode::SUCCESS)
}
