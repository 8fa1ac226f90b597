//! `lens optimize`: damped least squares on a design file's variables
//! against its merit function; the designed prescription, a markdown
//! report with pictures, a table or JSON.

use crate::args::GlassArgs;
use crate::{print_json, CmdResult};
use lens::analysis::fan::ImagePlane;
use lens::analysis::pattern::Pattern;
use lens::analysis::spot::{spot_polychromatic, SpotDiagram};
use lens::analysis::wave::mtf::mtf;
use lens::analysis::{Aim, Field, Launcher};
use lens::design::{optimize, Design, Measure, Optimized};
use lens::error::num;
use lens::paraxial::FirstOrder;
use lens::Prescription;
use plot::wave::{mtf_chart, MtfCurve};
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Design file (JSON): the starting prescription, variables, operands
    /// (docs/design.md).
    spec: PathBuf,
    /// Write the designed prescription (JSON) here.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    output: Option<PathBuf>,
    /// Write a markdown report here (merit history, operand and variable
    /// tables, spot and MTF pictures beside it as PNG).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// The most iterations (overrides the design file's max_iterations); 0
    /// evaluates the merit function of the start without changing it.
    #[arg(long, value_name = "N")]
    max_iterations: Option<usize>,
    #[command(flatten)]
    catalogs: GlassArgs,
    /// Print JSON (one object on one line) instead of tables.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> CmdResult {
    let inputs: Vec<PathBuf> =
        std::iter::once(args.spec.clone()).chain(args.catalogs.glass_catalogs.iter().cloned()).collect();
    let mut outs = Vec::new();
    if let Some(o) = &args.output {
        outs.push(crate::outputs::Output { path: o, flag: "-o", extensions: &["json"] });
    }
    let pictures = args.report.as_deref().map(picture_paths);
    if let (Some(r), Some(p)) = (&args.report, &pictures) {
        outs.push(crate::outputs::Output { path: r, flag: "--report", extensions: &["md"] });
        for q in p.iter() {
            outs.push(crate::outputs::Output { path: q, flag: "--report", extensions: &["png"] });
        }
    }
    crate::outputs::check(&outs, &inputs)?;
    let mut design = Design::load(&args.spec, args.catalogs.user_catalogs()?)?;
    if let Some(n) = args.max_iterations {
        design.max_iterations = n;
    }
    let o = optimize(&design)?;
    for w in &o.warnings {
        crate::warnings::warn("optimize", w);
    }
    if let Some(path) = &args.output {
        let text = o.end.spec.to_json_string() + "\n";
        lens::io::files::write_bytes_atomic(path, text.as_bytes())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    if let (Some(path), Some(pics)) = (&args.report, &pictures) {
        write_report(&o, &args.spec, path, pics)?;
    }
    if args.json {
        print_json(&summary(&o))?;
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "merit {} -> {} in {} iterations ({} evaluations, {:.3} s; {})",
        num(o.start.merit),
        num(o.end.merit),
        o.iterations,
        o.evaluations,
        o.seconds,
        stop_words(&o)
    );
    out!("{}", operand_table(&o));
    out!("{}", variable_table(&o));
    for s in &o.substitutions {
        outln!(
            "surface {}: model glass nd {:.5}, vd {:.2} -> {} (nd {:.5}, vd {:.2})",
            s.surface,
            s.model[0],
            s.model[1],
            s.glass,
            s.catalogue[0],
            s.catalogue[1]
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The pictures a report at `report` links: spot and MTF, start and end.
fn picture_paths(report: &Path) -> [PathBuf; 4] {
    let stem = report.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "report".into());
    let dir = report.parent().unwrap_or(Path::new(""));
    ["spot-start", "spot-end", "mtf-start", "mtf-end"].map(|k| dir.join(format!("{stem}-{k}.png")))
}

fn stop_words(o: &Optimized) -> &'static str {
    match o.stop {
        lens::design::least_squares::Stop::Zero => "every operand met",
        lens::design::least_squares::Stop::Converged => "converged",
        lens::design::least_squares::Stop::NoDescent => "no step lowers the merit further",
        lens::design::least_squares::Stop::Stalled => "stalled: the merit fell by less than 0.1% over 10 iterations",
        lens::design::least_squares::Stop::MaxIterations => "the iteration limit reached",
    }
}

/// The JSON summary `--json` prints.
fn summary(o: &Optimized) -> serde_json::Value {
    let d = &o.design;
    let operands: Vec<serde_json::Value> = d
        .operands
        .iter()
        .enumerate()
        .map(|(i, op)| {
            let mut v = serde_json::to_value(op.measure).unwrap_or_default();
            let target = match op.goal {
                lens::design::operands::Goal::Equal { target } => json!(target),
                _ => serde_json::Value::Null,
            };
            if let Some(m) = v.as_object_mut() {
                m.insert("target".into(), target);
                if let lens::design::operands::Goal::Within { min, max } = op.goal {
                    m.insert("min".into(), if min.is_finite() { json!(min) } else { serde_json::Value::Null });
                    m.insert("max".into(), if max.is_finite() { json!(max) } else { serde_json::Value::Null });
                }
                m.insert("weight".into(), json!(op.weight));
                m.insert("value".into(), json!(o.end.values[i]));
                m.insert("value_start".into(), json!(o.start.values[i]));
            }
            v
        })
        .collect();
    let variables: Vec<serde_json::Value> = d
        .variables
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let start = v.read(&o.start.spec);
            json!({
                "surface": v.surface,
                "param": if v.as_radius { "radius".to_string() } else { v.param.name() },
                "start": finite(v.shown(start)),
                "end": finite(v.shown(o.x_end[k])),
            })
        })
        .collect();
    json!({
        "merit_start": o.start.merit,
        "merit_end": o.end.merit,
        "iterations": o.iterations,
        "evaluations": o.evaluations,
        "seconds": o.seconds,
        "stop": o.stop,
        "operands": operands,
        "variables": variables,
        "history": o.history,
        "substitutions": o.substitutions,
    })
}

/// A radius at infinity (flat) as JSON null.
fn finite(x: f64) -> serde_json::Value {
    if x.is_finite() {
        json!(x)
    } else {
        serde_json::Value::Null
    }
}

fn operand_table(o: &Optimized) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "  {:>3}  {:<16} {:<28} {:>12} {:>7} {:>14} {:>14}",
        "#", "operand", "at", "target", "weight", "start", "end"
    );
    for (i, op) in o.design.operands.iter().enumerate() {
        let _ = writeln!(
            s,
            "  {:>3}  {:<16} {:<28} {:>12} {:>7} {:>14.6e} {:>14.6e}",
            i + 1,
            op.name(),
            op.place(),
            op.goal.describe(),
            num(op.weight),
            o.start.values[i],
            o.end.values[i]
        );
    }
    s
}

fn variable_table(o: &Optimized) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "  {:<28} {:>16} {:>16}", "variable", "start", "end");
    for (k, v) in o.design.variables.iter().enumerate() {
        let start = v.read(&o.start.spec);
        let _ = writeln!(s, "  {:<28} {:>16.9} {:>16.9}", v.label(), v.shown(start), v.shown(o.x_end[k]));
    }
    s
}

/// The report: summary, merit history, tables, and spot and MTF pictures
/// of the start and the end at the operands' fields.
fn write_report(
    o: &Optimized,
    spec: &Path,
    path: &Path,
    pics: &[PathBuf; 4],
) -> Result<(), Box<dyn std::error::Error>> {
    let d = &o.design;
    // (x, y) degrees
    let mut fields: Vec<(f64, f64)> = Vec::new();
    for op in &d.operands {
        if let Measure::RmsSpot { field_deg, field_x_deg, .. }
        | Measure::RmsWavefront { field_deg, field_x_deg, .. }
        | Measure::Mtf { field_deg, field_x_deg, .. } = op.measure
        {
            if !fields.contains(&(field_x_deg, field_deg)) {
                fields.push((field_x_deg, field_deg));
            }
        }
    }
    if fields.is_empty() {
        fields.push((0.0, 0.0));
    }
    let name = o.start.lens.name().to_string();
    for (lens, spot_pic, mtf_pic, when) in
        [(&o.start.lens, &pics[0], &pics[2], "start"), (&o.end.lens, &pics[1], &pics[3], "end")]
    {
        let spots = fields.iter().map(|&f| spot_at(lens, &d.waves, f)).collect::<Result<Vec<_>, _>>()?;
        plot::save(&plot::spot::spot_chart(&spots, &format!("{name} ({when})")), spot_pic)?;
        plot::save(&mtf_picture(lens, &fields, &format!("{name} ({when})"))?, mtf_pic)?;
    }
    let mut s = String::new();
    let _ = writeln!(s, "# Optimisation of {}\n", spec.display());
    let _ = writeln!(
        s,
        "Merit {} -> {} in {} iterations ({} merit evaluations, {:.3} s): {}.\n",
        num(o.start.merit),
        num(o.end.merit),
        o.iterations,
        o.evaluations,
        o.seconds,
        stop_words(o)
    );
    let _ =
        writeln!(s, "The merit is sqrt(sum w m^2 / sum w), m each operand's miss of its target (docs/design.md).\n");
    let _ = writeln!(s, "## Operands\n\n```\n{}```\n", operand_table(o));
    let _ = writeln!(s, "## Variables\n\n```\n{}```\n", variable_table(o));
    if !o.substitutions.is_empty() {
        let _ = writeln!(
            s,
            "## Glass substitution\n\n| surface | model nd | model vd | glass | nd | vd |\n|---|---|---|---|---|---|"
        );
        for g in &o.substitutions {
            let _ = writeln!(
                s,
                "| {} | {:.5} | {:.2} | {} | {:.5} | {:.2} |",
                g.surface, g.model[0], g.model[1], g.glass, g.catalogue[0], g.catalogue[1]
            );
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "## Merit history\n\n| iteration | merit |\n|---|---|");
    for (i, m) in o.history.iter().enumerate() {
        let _ = writeln!(s, "| {i} | {m:.9e} |");
    }
    let rel = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let _ = writeln!(
        s,
        "\n## Spot diagrams\n\nStart:\n\n![start]({})\n\nEnd:\n\n![end]({})\n",
        rel(&pics[0]),
        rel(&pics[1])
    );
    let _ = writeln!(
        s,
        "## MTF (primary wavelength; tangential solid, sagittal dashed)\n\nStart:\n\n![start]({})\n\nEnd:\n\n![end]({})",
        rel(&pics[2]),
        rel(&pics[3])
    );
    lens::io::files::write_bytes_atomic(path, s.as_bytes())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    Ok(())
}

/// The spot at the field of component angles `(x, y)`, degrees.
fn spot_at(lens: &Prescription, waves: &[(f64, f64)], (x, y): (f64, f64)) -> Result<SpotDiagram, lens::OpticsError> {
    let first = FirstOrder::of(lens)?;
    let l = Launcher::with_first(lens, &first, Field::at_angles(lens, &first, x, y), Aim::Auto)?;
    spot_polychromatic(lens, &l, Pattern::Gauss, 12, ImagePlane::ImageSurface, waves)
}

/// MTF against frequency at each field (primary wavelength), to half the
/// on-axis cutoff or 100 cycles/mm, whichever is lower.
fn mtf_picture(lens: &Prescription, fields: &[(f64, f64)], title: &str) -> Result<String, lens::OpticsError> {
    let first = FirstOrder::of(lens)?;
    let object = lens::paraxial::ObjectDistance::from_mm(lens.object_distance_mm().unwrap_or(f64::INFINITY))?;
    let wfn = lens::paraxial::imaging(lens, &first, object)?.working_f_number;
    let cutoff = 1.0 / (lens.wavelength_nm() * 1e-6 * wfn);
    let top = (0.5 * cutoff).min(100.0);
    let freqs: Vec<f64> = (1..=40).map(|k| top * k as f64 / 40.0).collect();
    let mut curves = Vec::new();
    for (i, &(x, f)) in fields.iter().enumerate() {
        let l = Launcher::with_first(lens, &first, Field::at_angles(lens, &first, x, f), Aim::Auto)?;
        let name = match x {
            0.0 => format!("{} deg", num(f)),
            _ => format!("x {}, y {} deg", num(x), num(f)),
        };
        let m = mtf(lens, lens, &l, ImagePlane::ImageSurface, &freqs)?;
        let pts = |v: &[f64]| {
            std::iter::once((0.0, 1.0)).chain(freqs.iter().copied().zip(v.iter().copied())).collect::<Vec<_>>()
        };
        curves.push(MtfCurve { label: format!("{name} T"), points: pts(&m.tangential), colour: i, dashed: false });
        curves.push(MtfCurve { label: format!("{name} S"), points: pts(&m.sagittal), colour: i, dashed: true });
    }
    Ok(mtf_chart(
        &format!("MTF: {title}"),
        &format!("{} nm", num(lens.wavelength_nm())),
        "spatial frequency (cycles/mm)",
        &curves,
    ))
}
