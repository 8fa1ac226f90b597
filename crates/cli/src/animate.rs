//! `lens animate`: a scene's frame sequence, one file per frame, written
//! as each finishes.

use crate::outputs::{self, Output};
use crate::CmdResult;
use ::render::animation::{frame_path, Animation};
use ::render::{render, Options};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (JSON) with an `animation` section (keyframes), or any
    /// scene (a still repeated).
    scene: PathBuf,
    /// Frame files: a name with the frame number as %d or %04d
    /// (frames/f%04d.exr; .png or .exr).
    #[arg(short, long, value_name = "PATTERN")]
    output: String,
    /// Number of frames (default: the scene's animation.frames; another
    /// count stretches its keyframes over it).
    #[arg(long)]
    frames: Option<u32>,
    /// Every frame's film.
    #[command(flatten)]
    film: crate::args::FilmArgs,
    /// Random seed, the same for every frame (no flicker from the sampler).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    glass_range: crate::args::GlassRangeArgs,
    /// Skip frames whose file exists (a file is written whole or not at
    /// all, so an existing one is a finished frame).
    #[arg(long)]
    resume: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

pub fn run(a: Args) -> CmdResult {
    let overrides = a.film.overrides(&a.glass_range);
    let anim = Animation::load(&a.scene, &overrides, a.frames)?;
    let n = anim.frames();
    let paths: Vec<PathBuf> = (0..n).map(|k| frame_path(&a.output, k)).collect::<Result<_, _>>()?;
    if n > 1 && paths[0] == paths[1] {
        return Err(format!("-o {}: the frame number is missing from the name", a.output).into());
    }
    // every output checked, then every frame's settings, before any work
    if let Some(dir) = paths[0].parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("-o {}: cannot make {}: {e}", a.output, dir.display()))?;
    }
    let first = [Output { path: &paths[0], flag: "-o", extensions: &["png", "exr"] }];
    outputs::check(&first, std::slice::from_ref(&a.scene))?;
    anim.check()?;
    let todo: Vec<u32> = (0..n).filter(|&k| !(a.resume && paths[k as usize].exists())).collect();
    if todo.len() < n as usize {
        eprintln!("resuming: {} of {n} frames already written", n as usize - todo.len());
    }
    let pool = crate::render::pool(a.threads)?;
    // the film is the same in every frame (keyframes move the camera only)
    let film = anim.film();
    let spp = a.film.spp.unwrap_or(film.spp);
    let (w, h) = (film.width, film.height);
    let rows = h as u64;
    let bar = indicatif::ProgressBar::new(rows * todo.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} frame {msg}, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let t = Instant::now();
    for (done, &k) in todo.iter().enumerate() {
        bar.set_message(format!("{} of {} ({k})", done + 1, todo.len()));
        let scene = anim.scene(k)?;
        if done == 0 {
            // the scene's warnings, once for the sequence
            for w in &scene.glass_warnings {
                bar.suspend(|| crate::warnings::glass_range(w));
            }
            for w in &scene.warnings {
                bar.suspend(|| crate::warnings::warn("scene", w));
            }
        }
        let (image, _) = pool.install(|| render(&scene, Options { spp, seed: a.seed }, &|_| bar.inc(1)));
        image.save(&paths[k as usize], scene.film.exposure)?;
    }
    bar.finish_and_clear();
    eprintln!(
        "{} frames ({w} x {h} at {spp} spp, seed {}) in {:.2} s, written to {}",
        todo.len(),
        a.seed,
        t.elapsed().as_secs_f64(),
        a.output
    );
    Ok(ExitCode::SUCCESS)
}
