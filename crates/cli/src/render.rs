//! `lens render`: a scene through its camera, to PNG and/or EXR.

use crate::CmdResult;
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
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

pub fn run(a: Args) -> CmdResult {
    let scene = Scene::load(&a.scene)?;
    let spp = a.spp.unwrap_or(scene.film.spp);
    if spp == 0 {
        return Err("--spp must be at least 1".into());
    }
    let pool = {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(t) = a.threads {
            if t == 0 {
                return Err("--threads must be at least 1".into());
            }
            b = b.num_threads(t);
        }
        b.build()?
    };
    let bar = indicatif::ProgressBar::new(scene.film.height as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let t = Instant::now();
    let (image, stats) = pool.install(|| render(&scene, Options { spp, seed: a.seed }, &|_| bar.inc(1)));
    bar.finish_and_clear();
    let secs = t.elapsed().as_secs_f64();
    image.save(&a.output, scene.film.exposure)?;
    if let Some(exr) = &a.exr {
        image.save(exr, scene.film.exposure)?;
    }
    eprintln!(
        "{} x {} at {spp} spp in {secs:.2} s; camera rays through the lens: {:.1}%",
        image.width,
        image.height,
        100.0 * stats.pass_rate()
    );
    Ok(ExitCode::SUCCESS)
}
