//! `lens mtf`: the diffraction MTF of a field at chosen frequencies, against
//! frequency, against image height (`--vs-field`) or through focus
//! (`--through-focus`).

use crate::args::{parse_list, AimArgs, FieldArgs, JsonArgs, LensArgs, PlaneArgs, PlotArgs, WavelengthArgs};
use crate::{print_json, CmdResult};
use lens::analysis::fan::ImagePlane;
use lens::analysis::wave::mtf::{cutoffs, geometric_mtf, mtf, polychromatic_mtf, Mtf};
use lens::analysis::{Field, Launcher};
use lens::paraxial::FirstOrder;
use lens::Prescription;
use plot::wave::{mtf_chart, MtfCurve};
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
    /// Frequencies, cycles/mm on the image plane (comma-separated; each
    /// above 0 and below the cutoff).
    #[arg(long, value_name = "C/MM,C/MM", value_parser = parse_list, default_value = "10,20,40", allow_hyphen_values = true)]
    frequencies: std::vec::Vec<f64>,
    /// The MTF at --frequencies against image height: tangential and
    /// sagittal at each of --fields.
    #[arg(long)]
    vs_field: bool,
    /// Field angles for --vs-field, degrees (default: 11 from 0 to the
    /// prescription's largest field, or to 20 degrees).
    #[arg(long, value_name = "DEG,DEG", value_parser = parse_list)]
    fields: Option<std::vec::Vec<f64>>,
    /// The MTF at --frequencies through focus: the image plane moved from
    /// -MM to +MM in 21 steps.
    #[arg(long, value_name = "MM")]
    through_focus: Option<f64>,
    /// Every wavelength of the prescription with its weight
    /// (`wavelength_weights`): their OTFs summed about the primary
    /// wavelength's chief ray (lateral colour lowers it).
    #[arg(long, conflicts_with = "wavelength_nm")]
    polychromatic: bool,
    /// Also the geometric MTF, from the spot diagram's rays (48 Gauss
    /// rings): the Fourier transform of the ray density about its centroid.
    #[arg(long)]
    geometric: bool,
    /// With --geometric: times the same pupil's diffraction-limited MTF
    /// (Zemax's "scale by diffraction limit").
    #[arg(long, requires = "geometric")]
    scale_by_diffraction: bool,
    #[command(flatten)]
    out: JsonArgs,
    #[command(flatten)]
    plot: PlotArgs,
}

/// Tangential and sagittal values at each frequency.
type TandS = (Vec<f64>, Vec<f64>);

/// What every MTF of the command shares.
struct Setup<'a> {
    p: &'a Prescription,
    traced: &'a Prescription,
    first: FirstOrder,
    aim: lens::analysis::Aim,
    /// (nm, weight) of each wavelength, for a polychromatic MTF.
    waves: Option<Vec<(f64, f64)>>,
}

impl Setup<'_> {
    /// The launcher of the field at component angles `x`, `y` (degrees).
    fn launcher(&self, x: f64, y: f64) -> Result<Launcher, lens::OpticsError> {
        Launcher::with_first(self.p, &self.first, Field::at_angles(self.p, &self.first, x, y), self.aim)
    }

    /// The MTF of the field the command was asked for.
    fn mtf(&self, field: &FieldArgs, plane: ImagePlane, freqs: &[f64]) -> Result<Mtf, lens::OpticsError> {
        self.mtf_with(&self.launcher(field.field_x_deg, field.field_deg)?, plane, freqs)
    }

    /// The MTF of `launcher`'s field, monochromatic or polychromatic.
    fn mtf_with(&self, launcher: &Launcher, plane: ImagePlane, freqs: &[f64]) -> Result<Mtf, lens::OpticsError> {
        match &self.waves {
            Some(w) => polychromatic_mtf(self.p, launcher, plane, freqs, w),
            None => mtf(self.p, self.traced, launcher, plane, freqs),
        }
    }

    /// How outputs name the light: one wavelength, or several with weights.
    fn light(&self) -> String {
        match &self.waves {
            Some(w) => {
                let list: Vec<String> = w.iter().map(|(nm, wt)| format!("{nm} (weight {wt})")).collect();
                format!("{} nm", list.join(", "))
            }
            None => format!("{} nm", self.traced.wavelength_nm()),
        }
    }
}

pub fn run(args: Args) -> CmdResult {
    args.lens.check_plot(args.plot.plot.as_deref())?;
    let plane = args.plane.plane()?;
    let (p, traced) = args.lens.load_at(args.wavelength.wavelength_nm)?;
    let field_deg = args.field.field_deg;
    args.field.check()?;
    if args.frequencies.is_empty() {
        return Err("--frequencies: give at least one frequency in cycles/mm (e.g. 10,20,40)".into());
    }
    let waves = args.polychromatic.then(|| p.wavelengths_nm().iter().copied().zip(p.wavelength_weights()).collect());
    if args.polychromatic {
        args.lens.catalogs.report(&p, p.wavelengths_nm())?;
    }
    let s = Setup { p: &p, traced: &traced, first: FirstOrder::of(&p)?, aim: args.aim.aim(), waves };
    let name = args.lens.name(&p);
    // the on-axis cutoff, 1 / (lambda N_w) from the real marginal ray
    let axis = s.launcher(0.0, 0.0)?;
    let axis_cutoff = cutoffs(&p, &traced, &axis, plane.z(&p, &axis)?)?.0;
    if args.vs_field {
        return vs_field(&args, &s, plane, &name);
    }
    if let Some(range) = args.through_focus {
        return through_focus(&args, &s, plane, range, &name);
    }
    let m = s.mtf(&args.field, plane, &args.frequencies)?;
    let geometric = |freqs: &[f64], limit: (&[f64], &[f64])| -> Result<Option<TandS>, lens::OpticsError> {
        if !args.geometric {
            return Ok(None);
        }
        let launcher = s.launcher(args.field.field_x_deg, field_deg)?;
        let pattern = lens::analysis::pattern::Pattern::Gauss;
        let spot = match &s.waves {
            Some(w) => lens::analysis::spot::spot_polychromatic(s.p, &launcher, pattern, 48, plane, w)?,
            None => lens::analysis::spot::spot_traced(s.p, s.traced, &launcher, pattern, 48, plane)?,
        };
        let Some((mut t, mut g)) = geometric_mtf(&spot, freqs) else { return Ok(None) };
        if args.scale_by_diffraction {
            t.iter_mut().zip(limit.0).for_each(|(v, l)| *v *= l);
            g.iter_mut().zip(limit.1).for_each(|(v, l)| *v *= l);
        }
        Ok(Some((t, g)))
    };
    let geo = geometric(&args.frequencies, (&m.diffraction_limit_tangential, &m.diffraction_limit_sagittal))?;
    if let Some(out) = &args.plot.plot {
        let top = m.cutoff_tangential_per_mm.min(m.cutoff_sagittal_per_mm);
        let freqs: Vec<f64> = (1..60).map(|k| top * k as f64 / 60.0).collect();
        let curve = s.mtf(&args.field, plane, &freqs)?;
        let pts = |v: &[f64]| std::iter::once((0.0, 1.0)).chain(freqs.iter().copied().zip(v.iter().copied())).collect();
        let mut curves = vec![
            MtfCurve { label: "tangential".into(), points: pts(&curve.tangential), colour: 0, dashed: false },
            MtfCurve { label: "sagittal".into(), points: pts(&curve.sagittal), colour: 1, dashed: true },
            MtfCurve {
                label: "diffraction limit (this pupil), T".into(),
                points: pts(&curve.diffraction_limit_tangential),
                colour: usize::MAX,
                dashed: false,
            },
        ];
        if let Some((gt, gs)) =
            geometric(&freqs, (&curve.diffraction_limit_tangential, &curve.diffraction_limit_sagittal))?
        {
            curves.push(MtfCurve { label: "geometric T".into(), points: pts(&gt), colour: 2, dashed: false });
            curves.push(MtfCurve { label: "geometric S".into(), points: pts(&gs), colour: 3, dashed: true });
        }
        let title = format!("MTF: {name}, {}, {}", args.field.describe(), s.light());
        let panel = format!(
            "cutoff T {:.0} c/mm, S {:.0} c/mm; on axis 1/(lambda N_w) = {:.0} c/mm",
            m.cutoff_tangential_per_mm, m.cutoff_sagittal_per_mm, axis_cutoff
        );
        plot::save(&mtf_chart(&title, &panel, "spatial frequency (cycles/mm)", &curves), out)?;
    }
    if args.out.json {
        let geometric = geo.as_ref().map(|(t, g)| lens::report::GeometricMtf {
            tangential: t,
            sagittal: g,
            scaled_by_diffraction_limit: args.scale_by_diffraction,
        });
        print_json(&args.field.report(lens::report::mtf(
            field_deg,
            plane,
            &m,
            s.waves.as_deref(),
            axis_cutoff,
            geometric,
        )))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "diffraction MTF at {}, {}, on {}",
        args.field.describe(),
        s.light(),
        crate::args::describe_plane(plane, m.image_z)
    );
    outln!(
        "  cutoff              tangential {:.3} c/mm, sagittal {:.3} c/mm (on axis, 1/(lambda N_w): {:.3} c/mm)",
        m.cutoff_tangential_per_mm,
        m.cutoff_sagittal_per_mm,
        axis_cutoff
    );
    outln!("  {:>10}  {:>10}  {:>10}  {:>22}", "c/mm", "tangential", "sagittal", "diffraction limit T, S");
    for (i, f) in m.frequencies_per_mm.iter().enumerate() {
        let g = geo.as_ref().map_or(String::new(), |(t, g)| format!("   geometric {:.6}, {:.6}", t[i], g[i]));
        outln!(
            "  {:>10.3}  {:>10.6}  {:>10.6}  {:>10.6}, {:>10.6}{g}",
            f,
            m.tangential[i],
            m.sagittal[i],
            m.diffraction_limit_tangential[i],
            m.diffraction_limit_sagittal[i]
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The fields of --vs-field: --fields, or 11 from 0 to the prescription's
/// largest field (20 degrees where it gives none).
fn fields(args: &Args, p: &Prescription) -> Result<Vec<f64>, String> {
    if let Some(f) = &args.fields {
        crate::args::check_fields("--fields", f)?;
        return Ok(f.clone());
    }
    let top = p.fields_deg().iter().fold(0.0f64, |m, f| m.max(f.abs()));
    let top = if top > 0.0 { top } else { 20.0 };
    Ok((0..=10).map(|k| top * k as f64 / 10.0).collect())
}

/// T and S at each frequency over a sweep (of fields, or of focus).
struct Sweep {
    /// Per frequency, the tangential MTF at each step.
    tan: Vec<Vec<f64>>,
    /// Likewise sagittal.
    sag: Vec<Vec<f64>>,
}

impl Sweep {
    fn new(freqs: &[f64]) -> Self {
        Sweep { tan: vec![Vec::new(); freqs.len()], sag: vec![Vec::new(); freqs.len()] }
    }

    /// Adds one step's MTF.
    fn push(&mut self, m: &Mtf) {
        for k in 0..self.tan.len() {
            self.tan[k].push(m.tangential[k]);
            self.sag[k].push(m.sagittal[k]);
        }
    }

    /// The chart's curves against `xs` (one per step): T solid and S
    /// dashed, a colour per frequency.
    fn curves(&self, freqs: &[f64], xs: &[f64]) -> Vec<MtfCurve> {
        let pts = |v: &[f64]| xs.iter().copied().zip(v.iter().copied()).collect();
        let mut curves = Vec::new();
        for (k, f) in freqs.iter().enumerate() {
            curves.push(MtfCurve { label: format!("{f} c/mm T"), points: pts(&self.tan[k]), colour: k, dashed: false });
            curves.push(MtfCurve { label: format!("{f} c/mm S"), points: pts(&self.sag[k]), colour: k, dashed: true });
        }
        curves
    }

    /// The table's head over the frequencies.
    fn head(freqs: &[f64]) -> String {
        freqs.iter().map(|f| format!("{f:>8} c/mm T, S")).collect::<Vec<_>>().join("  ")
    }

    /// Step `i`'s T and S at each frequency, as a table row.
    fn row(&self, i: usize) -> String {
        (0..self.tan.len())
            .map(|k| format!("{:>8.4}, {:>8.4}", self.tan[k][i], self.sag[k][i]))
            .collect::<Vec<_>>()
            .join("  ")
    }
}

/// `--vs-field`: T and S at each frequency against image height.
fn vs_field(args: &Args, s: &Setup, plane: ImagePlane, name: &str) -> CmdResult {
    args.field.y_only("--vs-field")?;
    let fields = fields(args, s.p)?;
    let freqs = &args.frequencies;
    let mut heights = Vec::new();
    let mut sweep = Sweep::new(freqs);
    for &deg in &fields {
        let launcher = s.launcher(0.0, deg)?;
        let probe = lens::analysis::wave::opd::Probe::new(s.p, s.traced, &launcher, plane)?;
        heights.push(probe.chief_image().y);
        sweep.push(&s.mtf_with(&launcher, plane, freqs)?);
    }
    if let Some(out) = &args.plot.plot {
        let title = format!("MTF against image height: {name}, {}", s.light());
        let curves = sweep.curves(freqs, &heights);
        plot::save(&mtf_chart(&title, "tangential solid, sagittal dashed", "image height (mm)", &curves), out)?;
    }
    if args.out.json {
        print_json(&json!({
            "wavelength_nm": s.traced.wavelength_nm(),
            "image_plane": plane.name(),
            "fields_deg": fields,
            "image_height_mm": heights,
            "frequencies_per_mm": freqs,
            "tangential": sweep.tan,
            "sagittal": sweep.sag,
        }))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!("MTF against image height, {} (rows: fields; T and S at each frequency)", s.light());
    outln!("  {:>8}  {:>10}  {}", "deg", "height mm", Sweep::head(freqs));
    for (i, deg) in fields.iter().enumerate() {
        outln!("  {:>8.3}  {:>10.4}  {}", deg, heights[i], sweep.row(i));
    }
    Ok(ExitCode::SUCCESS)
}

/// `--through-focus MM`: T and S at each frequency with the image plane
/// moved from -MM to +MM.
fn through_focus(args: &Args, s: &Setup, plane: ImagePlane, range: f64, name: &str) -> CmdResult {
    if !(range.is_finite() && range > 0.0) {
        return Err(format!("--through-focus {range}: give the focus range in mm, above 0").into());
    }
    let launcher = s.launcher(args.field.field_x_deg, args.field.field_deg)?;
    let z0 = plane.z(s.p, &launcher)?;
    let freqs = &args.frequencies;
    let shifts: Vec<f64> = (0..=20).map(|k| -range + 2.0 * range * k as f64 / 20.0).collect();
    let mut sweep = Sweep::new(freqs);
    for &dz in &shifts {
        let film = z0 + dz - s.p.last_vertex_z();
        if film <= 0.0 {
            return Err(format!(
                "--through-focus {range}: a shift of {dz} mm puts the image plane inside the lens; give a smaller range"
            )
            .into());
        }
        sweep.push(&s.mtf_with(&launcher, ImagePlane::Film(film), freqs)?);
    }
    if let Some(out) = &args.plot.plot {
        let curves = sweep.curves(freqs, &shifts);
        let title = format!("Through-focus MTF: {name}, {}, {}", args.field.describe(), s.light());
        plot::save(&mtf_chart(&title, "tangential solid, sagittal dashed", "focus shift (mm)", &curves), out)?;
    }
    if args.out.json {
        print_json(&args.field.report(json!({
            "field_deg": args.field.field_deg,
            "wavelength_nm": s.traced.wavelength_nm(),
            "image_z": z0,
            "focus_shift_mm": shifts,
            "frequencies_per_mm": freqs,
            "tangential": sweep.tan,
            "sagittal": sweep.sag,
        })))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!("through-focus MTF at {}, {}, about z = {:.6} mm", args.field.describe(), s.light(), z0);
    outln!("  {:>10}  {}", "shift mm", Sweep::head(freqs));
    for (i, dz) in shifts.iter().enumerate() {
        outln!("  {:>+10.4}  {}", dz, sweep.row(i));
    }
    Ok(ExitCode::SUCCESS)
}
