//! `lens render`: a scene through its camera, to PNG and/or EXR.

use crate::outputs::{self, Output};
use crate::CmdResult;
use ::render::scene::format::{CompanionsSpec, SpectralSpec};
use ::render::scene::{CameraKind, ColourMode};
use ::render::{render, Options, Scene};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (JSON).
    scene: PathBuf,
    /// Output image (.png tone-mapped sRGB, or .exr linear).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write a linear OpenEXR file.
    #[arg(long, value_name = "OUT.exr")]
    exr: Option<PathBuf>,
    /// Samples per pixel (default: the scene's).
    #[arg(long)]
    spp: Option<u32>,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Colour transport: spectral (wavelengths through the glasses), RGB,
    /// or auto (spectral when the lens, a material or a light depends on
    /// wavelength). Default: the scene's (auto).
    #[arg(long, value_enum)]
    spectral: Option<SpectralFlag>,
    /// Render one wavelength only, nm: a grey image of the radiance there.
    #[arg(long, value_name = "NM")]
    wavelength_nm: Option<f64>,
    /// Through a real lens with glasses, which spectral samples trace their
    /// companion wavelengths (a lens trace each): auto (those bright
    /// enough for their colour to matter; faster where highlights
    /// dominate, more colour noise in dim regions) or all. Default: the
    /// scene's (auto).
    #[arg(long, value_enum)]
    companions: Option<CompanionsFlag>,
    /// Film width, pixels (overrides the scene's; alone, the height follows
    /// the scene's aspect).
    #[arg(long)]
    width: Option<u32>,
    /// Film height, pixels (alone, the width follows the scene's aspect).
    #[arg(long)]
    height: Option<u32>,
    /// Switch the camera: a real lens becomes the thin lens matched to it
    /// (focal length, f-number, focus, field of view); a thin lens with a
    /// focal length becomes a real lens (give --prescription) with the same
    /// field of view.
    #[arg(long, value_enum)]
    camera: Option<CameraFlag>,
    /// Thin-lens aperture diameter, m.
    #[arg(long, value_name = "M")]
    aperture: Option<f64>,
    /// f-number (a thin lens with --focal-length-mm, or a real lens: resizes its stop).
    #[arg(long, value_name = "N")]
    f_number: Option<f64>,
    /// Thin-lens focal length, mm.
    #[arg(long, value_name = "MM")]
    focal_length_mm: Option<f64>,
    /// Distance from the film to the plane in focus, m.
    #[arg(long, value_name = "M")]
    focus_distance: Option<f64>,
    /// Autofocus: a pixel COLUMN,ROW from the top left of the film as
    /// rendered, or the name of a shape; the focus distance is found by
    /// tracing the scene there (a real lens: its film moved to the
    /// real-ray best focus). Replaces the scene's focus.
    #[arg(long, value_name = "X,Y|NAME", value_parser = parse_focus_on, conflicts_with = "focus_distance")]
    focus_on: Option<::render::scene::format::FocusOn>,
    /// The thin lens's focus_shift (0.1: 10% nearer at the rim).
    #[arg(long, value_name = "FRACTION")]
    focus_shift: Option<f64>,
    /// Aperture shape: circle, polygon:BLADES[:ROTATION_DEG] or mask:FILE.png.
    #[arg(long, value_name = "SHAPE", value_parser = ::render::scene::Overrides::parse_shape)]
    aperture_shape: Option<::render::scene::format::ApertureSpec>,
    /// A real lens's prescription file (with --camera lens, or replacing the scene's).
    #[arg(long, value_name = "FILE")]
    prescription: Option<PathBuf>,
    /// Lens flare through a real lens: off, ghosts, or ghosts+glare
    /// (overrides the scene's film.flare).
    #[arg(long, value_name = "MODE")]
    flare: Option<::render::scene::format::FlareSpec>,
    /// Diffraction at a real lens's aperture: off or on (overrides the
    /// scene's film.diffraction).
    #[arg(long, value_name = "off|on")]
    diffraction: Option<::render::scene::format::DiffractionSpec>,
    /// Every surface's coating of a real lens: none or MgF2 (overrides the
    /// prescription's and the scene's camera.coating; layer lists go in the
    /// scene file).
    #[arg(long, value_name = "none|MgF2", value_parser = parse_coating)]
    coating: Option<lens::model::CoatingSpec>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    glass_range: crate::args::GlassRangeArgs,
    /// Render passes written as extra channels of the EXR output (-o
    /// OUT.exr or --exr): a comma-separated list of depth (Z, m along the
    /// axis), position (P.x P.y P.z, m), normal (N.x N.y N.z), coc (CoC,
    /// the lens's blur diameter in pixels), or all. One central ray per
    /// pixel centre, unfiltered (docs/rendering.md).
    #[arg(long, value_name = "LIST", value_parser = parse_passes)]
    passes: Option<PassList>,
    /// Instead of one render: render at 1, 2, 4, ... and --spp samples per
    /// pixel, time each and measure its RMSE (and relative to the mean
    /// pixel value) against a reference of 16x --spp samples, whose own
    /// noise is stated; write the report here (.md, or .json:
    /// {"reference_spp", "rows": [{"spp", "seconds", "rmse",
    /// "relative_rmse", "rays_through_lens"}]}), a plot beside it
    /// (NAME-plot.svg and .png) and the reference image as the output.
    #[arg(long, value_name = "OUT.md|OUT.json")]
    report: Option<PathBuf>,
}

/// `--camera` values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum CameraFlag {
    Pinhole,
    ThinLens,
    Lens,
}

/// `--spectral` values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum SpectralFlag {
    Auto,
    On,
    Off,
}

/// `--companions` values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum CompanionsFlag {
    Auto,
    All,
}

/// The most samples per pixel a render takes (a report renders up to four
/// times as many for its reference).
const MAX_SPP: u32 = 1 << 20;
/// The most worker threads.
const MAX_THREADS: usize = 256;

/// The worker threads `--threads` asks for (all cores when not given).
pub fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool, Box<dyn std::error::Error>> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        if t == 0 || t > MAX_THREADS {
            return Err(format!("--threads {t}: give 1 to {MAX_THREADS} worker threads").into());
        }
        b = b.num_threads(t);
    }
    Ok(b.build()?)
}

/// The report's plot files beside `md`.
fn report_plots(md: &std::path::Path) -> [std::path::PathBuf; 2] {
    let stem = md.file_stem().and_then(|s| s.to_str()).unwrap_or("report");
    ["svg", "png"].map(|ext| md.with_file_name(format!("{stem}-plot.{ext}")))
}

/// `--coating`: a coating's name, checked as the scene file's.
fn parse_coating(s: &str) -> Result<lens::model::CoatingSpec, String> {
    let spec = lens::model::CoatingSpec::Name(s.to_string());
    spec.coating()?;
    Ok(spec)
}

pub fn run(a: Args) -> CmdResult {
    let overrides = ::render::scene::Overrides {
        width: a.width,
        height: a.height,
        spp: None,
        camera: a.camera.map(|c| match c {
            CameraFlag::Pinhole => CameraKind::Pinhole,
            CameraFlag::ThinLens => CameraKind::ThinLens,
            CameraFlag::Lens => CameraKind::Lens,
        }),
        aperture: a.aperture,
        f_number: a.f_number,
        focal_length_mm: a.focal_length_mm,
        focus_distance: a.focus_distance,
        focus_on: a.focus_on.clone(),
        focus_shift: a.focus_shift,
        aperture_shape: a.aperture_shape.clone(),
        prescription: a.prescription.clone(),
        strict_glass_range: a.glass_range.strict_glass_range,
        flare: a.flare,
        coating: a.coating.clone(),
        diffraction: a.diffraction,
    };
    let mut scene = Scene::load_with(&a.scene, &overrides)?;
    // every output checked before any work: formats, folders, and none of
    // them an input or another output
    let plots = a.report.as_deref().map(report_plots);
    let mut outs = vec![Output { path: &a.output, flag: "-o", extensions: &["png", "exr"] }];
    if let Some(exr) = &a.exr {
        outs.push(Output { path: exr, flag: "--exr", extensions: &["exr"] });
    }
    if let (Some(md), Some(plots)) = (&a.report, &plots) {
        outs.push(Output { path: md, flag: "--report", extensions: &["md", "json"] });
        for p in plots {
            outs.push(Output { path: p, flag: "--report (its plot)", extensions: &[] });
        }
    }
    outputs::check(&outs, &scene.inputs)?;
    let exr_outputs: Vec<&PathBuf> =
        [Some(&a.output), a.exr.as_ref()].into_iter().flatten().filter(|p| is_exr(p)).collect();
    if a.passes.is_some() {
        if a.report.is_some() {
            return Err(
                "--passes with --report: the report writes its reference image only; render once for the passes".into(),
            );
        }
        if exr_outputs.is_empty() {
            return Err(format!(
                "--passes: the passes are channels of an OpenEXR file; give -o OUT.exr or --exr OUT.exr (the output {} is not one)",
                a.output.display()
            )
            .into());
        }
    }
    if let Some(spp) = a.spp {
        if spp > MAX_SPP {
            return Err(format!("--spp {spp}: at most {MAX_SPP} samples per pixel").into());
        }
    }
    if a.spectral.is_some() || a.wavelength_nm.is_some() {
        let spectral = match a.spectral {
            Some(SpectralFlag::On) => SpectralSpec::On,
            Some(SpectralFlag::Off) => SpectralSpec::Off,
            Some(SpectralFlag::Auto) => SpectralSpec::Auto,
            None => scene.film.spectral,
        };
        scene.set_colour(spectral, a.wavelength_nm.or(scene.film.wavelength_nm))?;
    }
    for w in &scene.glass_warnings {
        crate::warnings::glass_range(w);
    }
    for w in &scene.warnings {
        crate::warnings::warn("scene", w);
    }
    match a.companions {
        Some(CompanionsFlag::Auto) => scene.film.companions = CompanionsSpec::Auto,
        Some(CompanionsFlag::All) => scene.film.companions = CompanionsSpec::All,
        None => {}
    }
    let spp = a.spp.unwrap_or(scene.film.spp);
    if spp == 0 {
        return Err("--spp must be at least 1".into());
    }
    let pool = pool(a.threads)?;
    let bar = indicatif::ProgressBar::new(scene.film.height as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    if let Some(md) = &a.report {
        bar.finish_and_clear();
        return report(&a, &scene, spp, &pool, md);
    }
    let t = Instant::now();
    let (image, stats) = pool.install(|| render(&scene, Options { spp, seed: a.seed }, &|_| bar.inc(1)));
    bar.finish_and_clear();
    let secs = t.elapsed().as_secs_f64();
    match &a.passes {
        Some(which) => {
            let passes = ::render::passes::Passes::of(&scene)?;
            let channels = passes.channels(&which.0);
            for p in &exr_outputs {
                image.save_exr_with(p, &channels)?;
            }
            if !is_exr(&a.output) {
                image.save(&a.output, scene.film.exposure)?;
            }
        }
        None => {
            image.save(&a.output, scene.film.exposure)?;
            if let Some(exr) = &a.exr {
                image.save(exr, scene.film.exposure)?;
            }
        }
    }
    let colour = match &scene.colour {
        ColourMode::Rgb => "RGB".to_string(),
        ColourMode::Spectral(r) => format!("spectral {:.0}-{:.0} nm", r.nm()[0], r.nm()[1]),
        ColourMode::Monochromatic(nm) => format!("at {nm} nm"),
    };
    let flare = if stats.flare_seconds > 0.0 {
        format!(" (flare and diffraction {:.2} s of it)", stats.flare_seconds)
    } else {
        String::new()
    };
    eprintln!(
        "{} x {} at {spp} spp ({colour}) in {secs:.2} s{flare}; camera rays through the lens: {:.1}%; camera: {}",
        image.width,
        image.height,
        100.0 * stats.pass_rate(),
        scene.camera_summary
    );
    Ok(ExitCode::SUCCESS)
}

/// `--focus-on`: two numbers are a pixel, anything else a shape's name.
fn parse_focus_on(s: &str) -> Result<::render::scene::format::FocusOn, String> {
    use ::render::scene::format::FocusOn;
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if let [x, y] = parts.as_slice() {
        if let (Ok(x), Ok(y)) = (x.parse::<f64>(), y.parse::<f64>()) {
            return Ok(FocusOn::Pixel([x, y]));
        }
    }
    if s.trim().is_empty() {
        return Err("give a pixel COLUMN,ROW or a shape's name".into());
    }
    Ok(FocusOn::Shape(s.trim().to_string()))
}

/// `--passes`' list (one value, not a repeated flag).
#[derive(Clone)]
struct PassList(Vec<::render::passes::Pass>);

fn parse_passes(s: &str) -> Result<PassList, String> {
    ::render::passes::Pass::parse_list(s).map(PassList)
}

/// Whether `p` names an OpenEXR file.
fn is_exr(p: &std::path::Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// The report's reference has this many times the sweep's largest count.
const REFERENCE_FACTOR: u32 = 16;
/// Below this many samples per pixel a sweep has too few points to show a
/// trend.
const FEW_SPP: u32 = 8;

fn report(a: &Args, scene: &Scene, spp: u32, pool: &rayon::ThreadPool, path: &std::path::Path) -> CmdResult {
    if spp > MAX_SPP / REFERENCE_FACTOR {
        return Err(format!(
            "--report with --spp {spp}: at most {} (the reference renders {REFERENCE_FACTOR} times as many samples)",
            MAX_SPP / REFERENCE_FACTOR
        )
        .into());
    }
    if spp < FEW_SPP {
        eprintln!("warning: --spp {spp}: a sweep to fewer than {FEW_SPP} samples per pixel has too few points to show how the error falls");
    }
    let spps = ::render::report::sweep(spp);
    let reference_spp = spp * REFERENCE_FACTOR;
    // progress over every render's rows: the reference's two halves, then the sweep
    let bar = indicatif::ProgressBar::new(((spps.len() + 2) * scene.film.height as usize) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent}% of the sweep and its reference, {elapsed} elapsed, ETA {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let r = pool.install(|| {
        ::render::report::error_against_time(scene, &spps, reference_spp, a.seed, &|done| bar.set_position(done as u64))
    });
    bar.finish_and_clear();
    r.reference.save(&a.output, scene.film.exposure)?;
    let json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let text = if json {
        serde_json::json!({
            "scene": a.scene.display().to_string(),
            "width": scene.film.width,
            "height": scene.film.height,
            "threads": pool.current_num_threads(),
            "reference_spp": r.reference_spp,
            "reference_seconds": r.reference_seconds,
            "reference_noise": r.reference_noise,
            "reference_relative_noise": relative(r.reference_noise, r.reference_mean),
            "rows": r.rows,
        })
        .to_string()
            + "\n"
    } else {
        markdown(a, scene, pool, &r)
    };
    lens::io::files::write_bytes_atomic(path, text.as_bytes())
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    let svg = report_plot(&a.scene.display().to_string(), &r);
    for p in report_plots(path) {
        plot::save(&svg, &p)?;
    }
    if !json {
        eprint!("{text}");
    }
    Ok(ExitCode::SUCCESS)
}

/// `x / mean`, 0 for a black image.
fn relative(x: f64, mean: f64) -> f64 {
    if mean > 0.0 {
        x / mean
    } else {
        0.0
    }
}

/// The report as a markdown page.
fn markdown(a: &Args, scene: &Scene, pool: &rayon::ThreadPool, r: &::render::report::Report) -> String {
    let mut out = String::new();
    use std::fmt::Write;
    let _ = writeln!(out, "# Error against run time: {}\n", a.scene.display());
    let _ = writeln!(
        out,
        "{} x {} pixels, {} threads; reference: {} spp (two halves with other seeds) in {:.2} s, its own noise {:.5} \
         ({:.3}% of the mean pixel value {:.5}).\n",
        scene.film.width,
        scene.film.height,
        pool.current_num_threads(),
        r.reference_spp,
        r.reference_seconds,
        r.reference_noise,
        100.0 * relative(r.reference_noise, r.reference_mean),
        r.reference_mean,
    );
    let _ = writeln!(
        out,
        "| spp | time (s) | RMSE | relative RMSE (% of mean) | RMSE x sqrt(time) | camera rays through the lens |"
    );
    let _ = writeln!(out, "|---:|---:|---:|---:|---:|---:|");
    for row in &r.rows {
        let _ = writeln!(
            out,
            "| {} | {:.3} | {:.5} | {:.3} | {:.5} | {:.1}% |",
            row.spp,
            row.seconds,
            row.rmse,
            100.0 * row.relative_rmse,
            row.rmse * row.seconds.sqrt(),
            100.0 * row.rays_through_lens
        );
    }
    let _ = writeln!(
        out,
        "\nRMSE is in the image's linear radiance; relative RMSE divides it by the reference's mean pixel value. \
         RMSE x sqrt(time) is the cost of a given error: lower is cheaper; it is constant where the error falls as \
         1/sqrt(samples). Errors near the reference's own noise are the reference's."
    );
    out
}

/// Relative RMSE against time, log-log, a marker at each sample count, the
/// 1/sqrt(time) line through the first, and the reference's noise.
fn report_plot(title: &str, r: &::render::report::Report) -> String {
    use plot::figure::{Series, Style, PALETTE};
    let pts: Vec<(f64, f64)> =
        r.rows.iter().map(|x| (x.seconds.max(1e-6).log10(), (100.0 * x.relative_rmse).max(1e-9).log10())).collect();
    let mut series = vec![
        Series::new("render", pts.clone(), PALETTE[0], Style::Line),
        Series::new("each sample count", pts.clone(), PALETTE[0], Style::Dots(3.5)),
    ];
    if let (Some(&(t0, e0)), Some(&(t1, _))) = (pts.first(), pts.last()) {
        series.push(Series::new("1/sqrt(time)", vec![(t0, e0), (t1, e0 - 0.5 * (t1 - t0))], PALETTE[1], Style::Dashed));
        let noise = (100.0 * relative(r.reference_noise, r.reference_mean)).max(1e-9).log10();
        series.push(Series::new("reference's own noise", vec![(t0, noise), (t1, noise)], PALETTE[2], Style::Dashed));
    }
    let panel = plot::figure::Panel {
        title: title.to_string(),
        x_label: "log10 time (s)".into(),
        y_label: "log10 relative RMSE (% of mean)".into(),
        series,
        ..Default::default()
    };
    plot::figure::Figure {
        title: "Error against run time".into(),
        panels: vec![panel],
        columns: 1,
        panel_size: (560.0, 380.0),
    }
    .to_svg()
}
